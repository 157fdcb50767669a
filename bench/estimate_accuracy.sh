#!/usr/bin/env bash
# The reference-free error estimate against the true error on every scene of scenes/ with the
# progressive features on: raytrace --progressive to 32 spp at 96x72 against an auto reference
# of 512 spp, one row per scene and pass after the fourth (16 and 32 spp), with the ratio of the
# estimated to the true relMSE. The reference's own error, spp / 512 of the image's for
# independent samples, is taken out of the truth. Asserts nothing; the target is a ratio within
# 0.75 to 1.25.
# usage: bench/estimate_accuracy.sh [BUILD_DIR] [FEATURE OPTIONS...]
#   default features: --light-radius 0.3 --aperture 0.02 --roughness 0.1
set -euo pipefail
build=$(realpath "${1:-build}")
shift || true
features=("$@")
if ((${#features[@]} == 0)); then features=(--light-radius 0.3 --aperture 0.02 --roughness 0.1); fi
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-24s %5s %12s %12s %7s\n' scene spp "true relMSE" estimate ratio
for scene in "$src"/scenes/*.ray; do
    name=$(basename "$scene")
    if ! (cd "$src/scenes" && "$build/app/raytrace" "$scene" --width 96 --height 72 --progressive \
        --spp 32 --reference auto --reference-spp 512 --report "$tmp/r.csv" -o "$tmp/x.png" -q \
        "${features[@]}") >"$tmp/err.txt" 2>&1; then
        printf '%-24s failed: %s\n' "$name" "$(head -1 "$tmp/err.txt")"
        continue
    fi
    awk -F, -v name="$name" 'NR > 5 {
        truth = $6 / (1 + $3 / 512)
        printf "%-24s %5d %12.4g %12.4g %7.3f\n", name, $3, truth, $9, (truth > 0 ? $9 / truth : 0)
    }' "$tmp/r.csv"
done
