#!/usr/bin/env bash
# Installs what is missing, builds, and renders the default scene to out/showpiece.png.
# Extra arguments go to raytrace (e.g. ./scripts/run.sh --spp 16).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
mkdir -p out
./build/app/raytrace scenes/showpiece.ray -o out/showpiece.png "$@"
