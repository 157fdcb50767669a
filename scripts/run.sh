#!/usr/bin/env bash
# Installs what is missing, builds, and opens the default scene in the viewer; without a display
# (or without the viewer's libraries) it renders the scene headless to out/showpiece.png.
# Extra arguments go to raytrace in the headless case (e.g. ./scripts/run.sh --spp 16).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
. scripts/build-env.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
# Only what it runs (not the tests and the benchmarks, which the test command builds): rayview
# with a display, where its libraries are installed; else raytrace.
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] &&
    cmake --build build --target help | grep -q '^rayview:'; then
    cmake --build build -j"$(nproc)" --target rayview
    exec ./build/app/rayview scenes/showpiece.ray
fi
cmake --build build -j"$(nproc)" --target raytrace
echo "run.sh: no display: rendering headless with raytrace" >&2
mkdir -p out
./build/app/raytrace scenes/showpiece.ray -o out/showpiece.png "$@"
