#!/usr/bin/env bash
# Whole frames, before and after: raytrace --stats on the showpiece (640x480), the public dog.ray
# at 1280x960 and a 1M-triangle raygen mesh at 640x480, with this build's raytrace and, when
# given, another one (an older commit's), run alternately, best of N runs each. Prints one row
# per scene and binary: render seconds and million rays per second. Asserts nothing.
# usage: bench/frames.sh [BUILD_DIR] [OTHER_RAYTRACE] [RUNS]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
other=${2:-}
runs=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/app/raygen" --triangles 1000000 -o "$tmp/mesh1m.ray" >/dev/null
dog="$here/../shared/public-scenes/whitefusion__CG/dog.ray"
scenes=("$here/scenes/showpiece.ray|640|480" "$dog|1280|960" "$tmp/mesh1m.ray|640|480")
bins=("$build/app/raytrace")
if [[ -n "$other" ]]; then bins+=("$other"); fi
printf '%-14s %-10s %8s %10s\n' scene binary "render s" "Mray/s"
for entry in "${scenes[@]}"; do
    IFS='|' read -r file w h <<<"$entry"
    [[ -f "$file" ]] || { echo "skipped: $file not found"; continue; }
    declare -A best_t=() best_r=()
    for ((i = 0; i < runs; ++i)); do
        for b in "${bins[@]}"; do
            "$b" "$file" --width "$w" --height "$h" --stats -o "$tmp/out.png" >"$tmp/stats.txt" 2>&1
            t=$(awk '$1 == "render" && NF == 2 { print $2 }' "$tmp/stats.txt")
            r=$(sed -n 's/^rays *\([0-9.]*\) Mray\/s.*/\1/p' "$tmp/stats.txt")
            if [[ -z "${best_t[$b]:-}" ]] || awk -v a="$t" -v b="${best_t[$b]}" 'BEGIN { exit !(a < b) }'; then
                best_t[$b]=$t
                best_r[$b]=$r
            fi
        done
    done
    for b in "${bins[@]}"; do
        name=$([[ "$b" == "${bins[0]}" ]] && echo this || echo other)
        printf '%-14s %-10s %8s %10s\n' "$(basename "$file" .ray)" "$name" "${best_t[$b]}" "${best_r[$b]}"
    done
    unset best_t best_r
done
