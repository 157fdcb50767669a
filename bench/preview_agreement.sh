#!/usr/bin/env bash
# The preview against the trace beside it, the viewer's promise: for each scene, rayview's
# preview alone (--layout preview, no panel, light markers off) at the file camera against
# raytrace at the same size, with imgdiff: the mean absolute difference per channel (of 255) and
# the share of pixels off by more than 32/255 in one channel. Asserts nothing; the target is at
# most 4.0 per channel and 3% of pixels. A texture that cannot be opened is a checker in both
# (the public scenes come without some of theirs).
# usage: bench/preview_agreement.sh [BUILD_DIR] [SCENE.ray...]
#   default scenes: v0, materials, showpiece, v3_csg of scenes/ and the public ones the viewer's
#   issue names. Needs Xvfb (xvfb-run).
set -euo pipefail
build=$(realpath "${1:-build}")
shift || true
src=$(cd "$(dirname "$0")/.." && pwd)
pub=$(realpath "$src/../shared/public-scenes")
scenes=()
for scene in "$@"; do scenes+=("$(realpath -m "$scene")"); done  # each run cds to its scene
if ((${#scenes[@]} == 0)); then
    scenes=("$src/scenes/v0.ray" "$src/scenes/materials.ray" "$src/scenes/showpiece.ray"
        "$src/scenes/v3_csg.ray" "$src/scenes/robot_arm.ray"
        "$pub/matthew-richard__cg2/test.ray"
        "$pub/aarxa__RayForge-CPP-Ray-Tracing-Engine/test.directional.ray"
        "$pub/aarxa__RayForge-CPP-Ray-Tracing-Engine/test.directional.torus.ray"
        "$pub/aarxa__RayForge-CPP-Ray-Tracing-Engine/lens.ray"
        "$pub/henry-md__ray-tracer/test.ray" "$pub/dcalvo__Graphics-2021/chess_room.ray")
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-44s %-20s %s\n' scene "mean difference" "off by > 32"
for scene in "${scenes[@]}"; do
    [[ -f "$scene" ]] || { printf '%-44s missing\n' "$scene"; continue; }
    name=${scene#"$src/"}
    name=${name#"$pub/"}
    dir=$(dirname "$scene")
    printf '1 markers off\n' >"$tmp/script.txt"
    if ! (cd "$dir" && xvfb-run -a -s '-screen 0 1600x900x24' "$build/app/rayview" "$scene" \
        --layout preview --panel off --size 400x300 --frames 120 --script "$tmp/script.txt" \
        --missing-textures checker --screenshot "$tmp/p.png" >"$tmp/log.txt" 2>&1) ||
        ! (cd "$dir" && "$build/app/raytrace" "$scene" --width 400 --height 300 -o "$tmp/t.png" \
            --missing-textures checker -q >>"$tmp/log.txt" 2>&1); then
        printf '%-44s failed: %s\n' "$name" "$(tail -1 "$tmp/log.txt")"
        continue
    fi
    out=$("$build/app/imgdiff" "$tmp/p.png" "$tmp/t.png")
    mad=$(sed -n 's/^mean abs diff \([0-9. ]*\);.*/\1/p' <<<"$out")
    off=$(sed -n 's/^off by more than 32\/255: \([0-9.]*\).*/\1/p' <<<"$out")
    printf '%-44s %-20s %.1f%%\n' "$name" "$mad" "$(awk -v s="$off" 'BEGIN { print 100 * s }')"
done
