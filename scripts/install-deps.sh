#!/usr/bin/env bash
# Installs the Debian packages this project builds and tests with. Safe to run again: it only
# installs what is missing. Needs root (or sudo) the first time on a new machine.
set -euo pipefail

# Required to build the core, the CLIs and the tests (CLI11 parses the programs' options, OpenEXR
# writes .exr images, help2man writes the man pages from --help).
required=(build-essential cmake pkg-config libgtest-dev libglm-dev libstb-dev libcli11-dev
    libopenexr-dev help2man)
# Optional: Embree is the benchmark's yardstick (raybench builds without it); GLFW, ImGui, OSMesa
# and Xvfb are for the viewer and its headless GL tests.
# clang and libFuzzer (libclang-rt-14-dev) build the fuzz target of scripts/test.sh, which skips
# the fuzz run with a message when they are missing. OpenMPI builds raytrace-mpi, the cluster
# mode (its tests are skipped with a message without it). ffmpeg encodes --video (without it the
# frames are written with a warning, and the test of the encoding is skipped). desktop-file-utils
# and shared-mime-info check the desktop entry and the MIME type of the package (tests/install).
optional=(libembree-dev libglfw3-dev libimgui-dev libosmesa6-dev xvfb xauth clang libclang-rt-14-dev
    libopenmpi-dev openmpi-bin ffmpeg desktop-file-utils shared-mime-info)

missing() {
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
    done
}
mapfile -t need < <(missing "${required[@]}")
mapfile -t want < <(missing "${optional[@]}")
if ((${#need[@]} == 0 && ${#want[@]} == 0)); then
    exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
if ((${#need[@]})); then
    echo "install-deps: installing ${need[*]}" >&2
    $sudo apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
if ((${#want[@]})); then
    echo "install-deps: installing ${want[*]}" >&2
    $sudo apt-get install -y -qq --no-install-recommends "${want[@]}" >/dev/null ||
        echo "install-deps: warning: optional packages not installed (${want[*]})" >&2
fi
