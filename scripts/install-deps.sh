#!/usr/bin/env bash
# Installs the Debian packages this project builds and tests with. Safe to run again: it only
# installs what is missing. Needs root (or sudo) the first time on a new machine.
set -euo pipefail

# Required to build the core, the CLI and the tests.
packages=(build-essential cmake pkg-config libgtest-dev libglm-dev libstb-dev)
# The viewer, its headless GL tests and the screenshot workflow.
packages+=(libglfw3-dev libimgui-dev libosmesa6-dev xvfb xauth)
# Benchmarks: Embree is the yardstick, Google Benchmark where it fits.
packages+=(libembree-dev libbenchmark-dev)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
    exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
