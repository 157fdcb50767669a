#!/usr/bin/env bash
# How loading grows with the scene: raygen meshes of 10k, 100k, 1M and 4M triangles (or the
# counts given), each loaded and rendered at 64x48 by raytrace --stats, RUNS times (3 unless
# set) in fresh processes, the run with the least parse + compile kept. Prints one table row per
# mesh: the text's size, parse time and rate (and the rate on one thread, --threads 1, best of
# RUNS), compile and BVH build time, parse + compile, peak memory (the process's maximum
# resident set) and bytes per triangle, and the load's growth against the previous row. With
# BASELINE=DIR (another build tree, say of an older commit), each mesh gets a row of that
# tree's raytrace too, measured in the same loop, and ours says how much faster it loads.
# Asserts nothing. Needs about 400 MB of disk and 2.5 GB of memory for 4M
# triangles.
# usage: [BASELINE=DIR] [RUNS=N] bench/load_scaling.sh [BUILD_DIR] [TRIANGLES...]
set -euo pipefail
build=${1:-build}
shift || true
counts=("$@")
if ((${#counts[@]} == 0)); then counts=(10000 100000 1000000 4000000); fi
runs=${RUNS:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
trees=("$build")
if [[ -n ${BASELINE:-} ]]; then trees=("$BASELINE" "$build"); fi

# One run: "parse compile bvh peak_kb triangles" of tree $1 on $tmp/mesh.ray (more arguments
# go to raytrace).
run() {
    local tree=$1
    shift
    /usr/bin/time -f "peak %M" -o "$tmp/time.txt" "$tree/app/raytrace" "$tmp/mesh.ray" --stats \
        --width 64 --height 48 -o "$tmp/mesh.png" "$@" >"$tmp/stats.txt" 2>&1
    awk '$1 == "parse" && NF == 2 { p = $2 } $1 == "compile" { c = $2 }
         /of which BVH build/ { sub(/.*of which BVH build /, ""); b = $1 + 0 }
         /^triangles / { t = $2 + 0 }
         END { printf "%s %s %s ", p, c, b; printf "%d ", t }' "$tmp/stats.txt"
    sed -n 's/^peak \([0-9]*\)/\1/p' "$tmp/time.txt"
}

printf '%-10s %-10s %8s %8s %10s %7s %9s %8s %8s %8s %6s %s\n' triangles tree "text MB" \
    "parse s" "parse MB/s" "1 thread" "compile s" "build s" "load s" "peak MB" "B/tri" \
    "growth / speed-up"
declare -A prev_load=() prev_n=() base_load=()
for n in "${counts[@]}"; do
    "$build/app/raygen" --triangles "$n" -o "$tmp/mesh.ray" >/dev/null
    bytes=$(stat -c %s "$tmp/mesh.ray")
    declare -A best=()
    for ((r = 0; r < runs; ++r)); do
        for tree in "${trees[@]}"; do  # side by side: the trees take turns
            line=$(run "$tree")
            load=$(awk '{ print $1 + $2 }' <<<"$line")
            if [[ -z ${best[$tree]:-} ]] ||
                awk -v a="$load" -v b="${best[$tree]%% *}" 'BEGIN { exit !(a < b) }'; then
                best[$tree]="$load $line"
            fi
        done
    done
    # The parse alone on one thread (--threads 1), best of RUNS, ours only: MB/s.
    one=-
    for ((r = 0; r < runs; ++r)); do
        p=$(run "$build" --threads 1 | awk '{ print $1 }')
        if [[ $one == - ]] || awk -v a="$p" -v b="$one" 'BEGIN { exit !(a < b) }'; then one=$p; fi
    done
    for tree in "${trees[@]}"; do
        read -r load parse compile bvh tris peak_kb <<<"${best[$tree]}"
        note=""
        if [[ -n ${prev_n[$tree]:-} ]]; then
            note=$(awk -v l="$load" -v pl="${prev_load[$tree]}" -v t="$tris" -v pt="${prev_n[$tree]}" \
                'BEGIN { printf "%.1fx for %.1fx the triangles", l / pl, t / pt }')
        fi
        if [[ $tree == "$build" && -n ${BASELINE:-} ]]; then
            note+="${note:+; }$(awk -v b="${base_load[$n]}" -v l="$load" \
                'BEGIN { printf "%.2fx faster than the baseline", b / l }')"
        elif [[ -n ${BASELINE:-} ]]; then
            base_load[$n]=$load
        fi
        label=$([[ $tree == "$build" ]] && echo ours || echo baseline)
        awk -v n="$tris" -v tr="$label" -v b="$bytes" -v p="$parse" -v c="$compile" -v bv="$bvh" \
            -v l="$load" -v k="$peak_kb" -v g="$note" -v o="$([[ $tree == "$build" ]] && echo "$one" || echo -)" '
            BEGIN {
                one = o == "-" ? "-" : sprintf("%.0f", b / 1e6 / o)
                printf "%-10d %-10s %8.1f %8.3f %10.0f %7s %9.3f %8.3f %8.3f %8.0f %6.0f %s\n",
                    n, tr, b / 1e6, p, b / 1e6 / p, one, c, bv, l, k / 1024, k * 1024 / n, g }'
        prev_n[$tree]=$tris
        prev_load[$tree]=$load
    done
    unset best
done
