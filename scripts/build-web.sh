#!/usr/bin/env bash
# Builds the web page into build-web/ (index.html and its files, for any static web server):
# rayview compiled with Emscripten once (build-web-obj/) and linked twice, with the tracer on web
# workers and on one thread (for pages served without cross-origin isolation), as a unity build
# (a few files compiled as one: 135 s instead of 215 s on 2 cores). Serve it with
# scripts/serve-web.sh. RT_WEB_JOBS sets the parallel compiles (default: the cores).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
if ! command -v emcmake >/dev/null; then
    echo "build-web: Emscripten is not installed (Debian package emscripten)" >&2
    exit 1
fi
. scripts/build-env.sh
unset CMAKE_CXX_COMPILER_LAUNCHER  # em++ compiles as it always has (no ccache)
# Debian's Emscripten finds its node modules (acorn) there.
export NODE_PATH="${NODE_PATH:+$NODE_PATH:}/usr/share/nodejs"
emcmake cmake -S . -B build-web-obj -DCMAKE_BUILD_TYPE=Release -DRT_WERROR=ON \
    -DRT_WEB_OUTPUT_DIR="$PWD/build-web" -DCMAKE_UNITY_BUILD=ON >/dev/null
cmake --build build-web-obj -j"${RT_WEB_JOBS:-$(nproc)}" --target page
echo "build-web: the page is in build-web/ (serve it: scripts/serve-web.sh)" >&2
