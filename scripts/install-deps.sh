#!/usr/bin/env bash
# Installs the Debian packages this project builds and tests with. Safe to run again: it only
# installs what is missing. Needs root (or sudo) the first time on a new machine.
set -euo pipefail

# Required to build the core, the CLIs and the tests (CLI11 parses the programs' options, OpenEXR
# writes .exr images, libpng and libjpeg-turbo decode PNG and JPEG textures, stb writes PNG and
# BMP and decodes PNG and JPEG on the web page, help2man writes the man pages from --help).
required=(build-essential cmake pkg-config libgtest-dev libglm-dev libstb-dev libcli11-dev
    libopenexr-dev libpng-dev libjpeg-dev help2man)
# Optional: Ninja schedules builds better than make (scripts/test.sh uses it when it is there);
# ccache makes the test command's repeated builds short (scripts/build-env.sh).
# Embree is the benchmark's yardstick (raybench builds without it); GLFW, ImGui, OSMesa and Xvfb
# are for the viewer and its headless GL tests.
# clang and libFuzzer (libclang-rt-14-dev) build the fuzz target of scripts/test.sh, which skips
# the fuzz run with a message when they are missing. OpenMPI builds raytrace-mpi, the cluster
# mode (its tests are skipped with a message without it). ffmpeg encodes --video (without it the
# frames are written with a warning, and the test of the encoding is skipped). desktop-file-utils
# and shared-mime-info check the desktop entry and the MIME type of the package (tests/install).
# Emscripten builds the web page (scripts/build-web.sh); Chromium and ChromeDriver load it in its
# test (tests/web); glslang-tools checks the preview's shaders as GLSL ES 3.00.
optional=(ninja-build ccache libembree-dev libglfw3-dev libimgui-dev libosmesa6-dev xvfb xauth clang
    libclang-rt-14-dev libopenmpi-dev openmpi-bin ffmpeg desktop-file-utils shared-mime-info
    emscripten chromium chromium-driver glslang-tools)

missing() {
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
    done
}
mapfile -t need < <(missing "${required[@]}")
mapfile -t want < <(missing "${optional[@]}")
imgui_src="$(dirname "$0")/../build-web-deps/imgui-1.86"
if ((${#need[@]} == 0 && ${#want[@]} == 0)) && [ -f "$imgui_src/imgui.cpp" ]; then
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

# The web build compiles Dear ImGui itself (libimgui-dev holds a native library only): the
# sources of the very version the desktop links (libimgui-dev's source package), fetched once
# into build-web-deps/ (git ignores it) from the machine's own apt sources: their deb lines as
# deb-src lines (the same mirrors, suites and keys; apt's own configuration, proxies included,
# applies), in a private apt state directory so the system's lists are left alone.
deb_src_sources() {  # writes the deb-src equivalents of the enabled apt sources into $1
    local out=$1 f
    [ -f /etc/apt/sources.list ] &&
        sed -n 's/^[[:space:]]*deb[[:space:]]/deb-src /p' /etc/apt/sources.list >"$out/src.list"
    for f in /etc/apt/sources.list.d/*.list; do
        [ -f "$f" ] && sed -n 's/^[[:space:]]*deb[[:space:]]/deb-src /p' "$f" >"$out/$(basename "$f")"
    done
    for f in /etc/apt/sources.list.d/*.sources; do
        [ -f "$f" ] && sed 's/^\(Types:.*[[:space:]]\)deb\([[:space:]]\|$\)/\1deb-src\2/' "$f" >"$out/$(basename "$f")"
    done
}
if [ ! -f "$imgui_src/imgui.cpp" ] && command -v emcc >/dev/null; then
    version=$(dpkg-query -W -f='${source:Version}' libimgui-dev 2>/dev/null || true)
    echo "install-deps: fetching Debian's imgui ${version:-?} source package for the web build" >&2
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    mkdir -p "$tmp/parts" "$tmp/lists/partial" "$tmp/cache/archives/partial"
    deb_src_sources "$tmp/parts"
    apt_src=(-o Dir::Etc::SourceList=/dev/null -o Dir::Etc::SourceParts="$tmp/parts"
        -o Dir::State::Lists="$tmp/lists" -o Dir::Cache="$tmp/cache" -o Debug::NoDropPrivs=true
        -o APT::Sandbox::User=root)
    if [ -n "$version" ] && apt-get "${apt_src[@]}" update -qq 2>/dev/null &&
        (cd "$tmp" && apt-get "${apt_src[@]}" source --download-only -qq "imgui=$version" \
            >/dev/null 2>&1) && compgen -G "$tmp/imgui_*.orig.tar.*" >/dev/null; then
        mkdir -p "$imgui_src"
        tar -xf "$(compgen -G "$tmp/imgui_*.orig.tar.*" | head -1)" -C "$imgui_src" \
            --strip-components=1
    else
        echo "install-deps: warning: cannot fetch the imgui sources (deb-src of the apt" \
            "sources); no web build" >&2
    fi
fi
