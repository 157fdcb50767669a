#!/usr/bin/env bash
# The README's viewer screenshot: rayview under Xvfb, N frames, the whole window saved.
# usage: scripts/screenshot.sh [SCENE.ray] [OUT.png]   (after a build)
set -euo pipefail
cd "$(dirname "$0")/.."
scene="${1:-scenes/showpiece.ray}"
out="${2:-docs/rayview.png}"
xvfb-run -a -s '-screen 0 1280x720x24' ./build/app/rayview --frames 150 --screenshot "$out" "$scene"
