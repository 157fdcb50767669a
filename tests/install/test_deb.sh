#!/usr/bin/env bash
# The Debian packages: cpack -G DEB from the build tree, then their file lists and control
# fields, and the programs run from the unpacked package (a relocated /usr).
# usage: test_deb.sh BUILD_DIR
set -u
build=$(realpath "$1")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/../app/check.sh"

(cd "$tmp" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/out") >"$tmp/cpack.txt" 2>&1
rc=$?
check "cpack -G DEB succeeds" test $rc -eq 0
[ $rc -eq 0 ] || cat "$tmp/cpack.txt"
deb=$(ls "$tmp"/out/raytracer_*_*.deb 2>/dev/null | head -n 1)
check "the package raytracer_VERSION-1_ARCH.deb is built" test -n "$deb" -a -s "$deb"
[ -n "$deb" ] || { summary "Debian package"; exit 1; }
dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$tmp/files.txt"
for f in /usr/bin/raytrace /usr/bin/rayview /usr/bin/raygen /usr/bin/raymerge /usr/bin/raycompare \
    /usr/share/raytracer/shaders/preview.vert /usr/share/raytracer/shaders/preview.frag \
    /usr/share/raytracer/scenes/showpiece.ray \
    /usr/share/applications/rayview.desktop /usr/share/mime/packages/raytracer.xml \
    /usr/share/icons/hicolor/256x256/apps/rayview.png \
    /usr/share/man/man1/raytrace.1.gz /usr/share/man/man1/rayview.1.gz \
    /usr/share/man/man1/raygen.1.gz /usr/share/man/man1/raymerge.1.gz /usr/share/man/man1/raycompare.1.gz \
    /usr/share/bash-completion/completions/raytrace /usr/share/doc/raytracer/README.md; do
    check "the package holds $f" grep -qx "$f" "$tmp/files.txt"
done
check "the package holds no build or test files" bash -c "! grep -qE '\.(o|a|cmake|py)$|/tests?/' '$tmp/files.txt'"
field() { dpkg-deb -f "$deb" "$1"; }
check "Package: raytracer" test "$(field Package)" = raytracer
check "Version: the project's" grep -qE '^[0-9]+\.[0-9]+\.[0-9]+-1$' <<<"$(field Version)"
depends=$(field Depends)
for lib in libc6 libstdc\\+\\+6 libglfw3 libopenexr; do
    check "Depends names $lib" grep -qE "(^|, )$lib" <<<"$depends"
done
check "Depends has no -dev package" bash -c "! grep -q -- '-dev' <<<'$depends'"

# The unpacked package is a relocated /usr: its programs find their data beside them.
dpkg-deb -x "$deb" "$tmp/root"
r="$tmp/root/usr"
check "the packaged raytrace runs" grep -q "^raytrace " <("$r/bin/raytrace" --version)
(cd "$tmp" && "$r/bin/raytrace" "$r/share/raytracer/scenes/simple.ray" --width 64 --height 48 -q -o "$tmp/p.png")
check "and renders a packaged scene" test -s "$tmp/p.png"
check "the packaged rayview finds its data" grep -qx "data: $r/share/raytracer" <("$r/bin/rayview" --version)

mpi=$(ls "$tmp"/out/raytracer-mpi_*.deb 2>/dev/null | head -n 1)
if [ -x "$build/app/raytrace-mpi" ]; then
    check "the cluster mode has its own package" test -n "$mpi"
    if [ -n "$mpi" ]; then
        check "raytracer-mpi holds raytrace-mpi" grep -q "usr/bin/raytrace-mpi$" <(dpkg-deb -c "$mpi")
        check "raytracer-mpi depends on raytracer and OpenMPI" \
            grep -qE "raytracer \(= .*\).*openmpi|openmpi.*raytracer \(= " <(dpkg-deb -f "$mpi" Depends)
    fi
fi
summary "Debian package"
