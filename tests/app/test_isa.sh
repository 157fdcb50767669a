#!/usr/bin/env bash
# The instruction sets: every scene of scenes/ and ../shared/public-scenes renders to the same
# PFM bytes under each instruction set this CPU runs (RAYTRACER_ISA), the programs say which one
# they use (--version, --stats), and a RAYTRACER_ISA that cannot be honoured is an error that
# names the CPU's. With RT_ISA_SHIPPED_ONLY=1, scenes/ only (the sanitizer tree: there every
# public scene twice takes 90 s).
# usage: test_isa.sh RAYTRACE SOURCE_DIR
set -u
rt="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/check.sh"

# "instruction set avx2 (this CPU runs sse2, avx2)" -> "sse2 avx2"
runs=$("$rt" --version | sed -n 's/^instruction set .*this CPU runs \([a-z0-9, ]*\)).*/\1/p' |
    tr -d ,)
check "--version names the CPU's instruction sets" test -n "$runs"
widest=${runs##* }
check "--version names the one in use (the widest)" \
    grep -q "^instruction set $widest (this CPU runs" <("$rt" --version)
echo "this CPU runs: $runs"

scenes=("$src"/scenes/*.ray)
least=${#scenes[@]}
if [ "${RT_ISA_SHIPPED_ONLY:-0}" != 1 ]; then
    while IFS= read -r -d '' f; do scenes+=("$f"); done \
        < <(find "$src/../shared/public-scenes" -name '*.ray' -print0 2>/dev/null | sort -z)
    least=50
fi
rendered=0
differ=0
for isa in $runs; do
    mkdir -p "$tmp/$isa"
    i=0
    for f in "${scenes[@]}"; do
        i=$((i + 1))
        RAYTRACER_ISA=$isa "$rt" "$f" --width 96 --height 72 --spp 1 --quiet \
            --missing-textures checker -o "$tmp/$isa/$i.pfm" >/dev/null 2>&1
        [ "$isa" = sse2 ] || [ ! -e "$tmp/sse2/$i.pfm" ] && continue
        rendered=$((rendered + 1))
        if ! cmp -s "$tmp/sse2/$i.pfm" "$tmp/$isa/$i.pfm"; then
            echo "differs under $isa: $f"
            differ=$((differ + 1))
        fi
    done
done
if [ "$runs" != sse2 ]; then
    check "scenes rendered under a second instruction set" test "$rendered" -ge "$least"
    check "every image is the same bit for bit under each instruction set" test "$differ" -eq 0
fi

"$rt" "${scenes[0]}" --width 8 --height 6 --quiet --stats -o "$tmp/s.png" >"$tmp/stats.txt"
check "--stats names the instruction set" \
    grep -q "^instruction set  $widest (this CPU runs" "$tmp/stats.txt"
RAYTRACER_ISA=sse2 "$rt" "${scenes[0]}" --width 8 --height 6 --quiet --stats -o "$tmp/s.png" \
    >"$tmp/stats.txt"
check "--stats says RAYTRACER_ISA chose it" \
    grep -q "^instruction set  sse2 (set by RAYTRACER_ISA; this CPU runs" "$tmp/stats.txt"

RAYTRACER_ISA=neon "$rt" "${scenes[0]}" -o "$tmp/bad.png" >/dev/null 2>"$tmp/err.txt"
check "an unknown instruction set exits 2" test $? -eq 2
check "and names the known ones and the CPU's" grep -qx "raytrace: error: RAYTRACER_ISA=neon: \
not an instruction set; use sse2, avx2 or avx512 (this CPU runs ${runs// /, })" "$tmp/err.txt"
check "and writes nothing" test ! -e "$tmp/bad.png"
for isa in avx2 avx512; do
    case " $runs " in *" $isa "*) continue ;; esac
    RAYTRACER_ISA=$isa "$rt" "${scenes[0]}" -o "$tmp/bad.png" >/dev/null 2>"$tmp/err.txt"
    check "$isa on a CPU without it exits 2" test $? -eq 2
    check "$isa on a CPU without it names the CPU's" grep -qx "raytrace: error: \
RAYTRACER_ISA=$isa: this CPU cannot run it; it runs ${runs// /, }" "$tmp/err.txt"
done

summary "instruction sets"
