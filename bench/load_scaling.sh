#!/usr/bin/env bash
# How loading grows with the scene: raygen meshes of 10k, 100k, 1M and 4M triangles (or the
# counts given), each rendered once at 640x480 by raytrace --stats. Prints one table row per
# mesh: the text's size, parse time and rate, compile and BVH build time, render time, peak
# memory (the process's maximum resident set) and bytes per triangle, and the compile's growth
# against the previous row. Asserts nothing. Needs about 400 MB of disk and 2.5 GB of memory for
# 4M triangles.
# usage: bench/load_scaling.sh [BUILD_DIR] [TRIANGLES...]
set -euo pipefail
build=${1:-build}
shift || true
counts=("$@")
if ((${#counts[@]} == 0)); then counts=(10000 100000 1000000 4000000); fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-10s %9s %8s %9s %9s %8s %8s %9s %8s %s\n' triangles "text MB" "parse s" "parse MB/s" \
    "compile s" "build s" "render s" "peak MB" "B/tri" "compile growth"
prev_n=0
prev_c=0
for n in "${counts[@]}"; do
    "$build/app/raygen" --triangles "$n" -o "$tmp/mesh.ray" >/dev/null
    bytes=$(stat -c %s "$tmp/mesh.ray")
    /usr/bin/time -f "peak %M" -o "$tmp/time.txt" "$build/app/raytrace" "$tmp/mesh.ray" --stats \
        -o "$tmp/mesh.png" >"$tmp/stats.txt" 2>&1
    tris=$(sed -n 's/^triangles \([0-9]*\),.*/\1/p' "$tmp/stats.txt")
    parse=$(awk '$1 == "parse" { print $2 }' "$tmp/stats.txt")
    compile=$(awk '$1 == "compile" { print $2 }' "$tmp/stats.txt")
    bvh=$(sed -n 's/.*of which BVH build \([0-9.]*\).*/\1/p' "$tmp/stats.txt")
    render=$(awk '$1 == "render" && NF == 2 { print $2 }' "$tmp/stats.txt")
    peak_kb=$(sed -n 's/^peak \([0-9]*\)/\1/p' "$tmp/time.txt")
    growth=""
    if ((prev_n > 0)); then
        growth=$(awk -v c="$compile" -v pc="$prev_c" -v n="$tris" -v pn="$prev_n" \
            'BEGIN { printf "%.1fx for %.1fx the triangles", c / pc, n / pn }')
    fi
    awk -v n="$tris" -v b="$bytes" -v p="$parse" -v c="$compile" -v bv="$bvh" -v r="$render" \
        -v k="$peak_kb" -v g="$growth" 'BEGIN {
            printf "%-10d %9.1f %8.3f %9.0f %9.3f %8.3f %8.3f %9.0f %8.0f %s\n",
                n, b / 1e6, p, b / 1e6 / p, c, bv, r, k / 1024, k * 1024 / n, g }'
    prev_n=$tris
    prev_c=$compile
done
