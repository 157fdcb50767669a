#!/usr/bin/env bash
# cmake --install into a temporary prefix, the prefix moved elsewhere (nothing may point back at
# the build or the source tree), then every installed program run from an empty directory:
# --version, a render of an installed sample scene, rayview's default scene under Xvfb, the man
# pages, the bash completion, the desktop entry and the MIME type.
# usage: test_install.sh BUILD_DIR SOURCE_DIR IMGDIFF
set -u
build=$(realpath "$1")
src=$(realpath "$2")
imgdiff=$(realpath "$3")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$src/tests/app/check.sh"
unset RAYTRACER_DATA_DIR
export XDG_CONFIG_HOME="$tmp/config"

cmake --install "$build" --prefix "$tmp/first" >"$tmp/install.txt" 2>&1
check "cmake --install succeeds" test $? -eq 0
mv "$tmp/first" "$tmp/moved"
p="$tmp/moved"
mkdir "$tmp/cwd"
cd "$tmp/cwd" || exit 1

programs="raytrace rayview raygen raymerge raycompare"
for prog in $programs; do
    check "$prog installed" test -x "$p/bin/$prog"
    out=$("$p/bin/$prog" --version 2>&1)
    check "$prog --version names the program, version and commit" \
        grep -qE "^$prog [0-9]+\.[0-9]+\.[0-9]+ \(git [0-9a-f]{7,}(-dirty)?|^$prog [0-9.]+ \(git unknown" <<<"$out"
    # The data comes from beside the program: no path into the build or source tree remains.
    check "$prog holds no path to the build tree" bash -c "! grep -qF '$build/' '$p/bin/$prog'"
    check "$prog holds no path to the scenes or shaders of the source tree" \
        bash -c "! grep -qE '$src/(scenes|shaders)' '$p/bin/$prog'"
    check "$prog has a man page" bash -c "gzip -dc '$p/share/man/man1/$prog.1.gz' | grep -qi '^\.TH \"*$prog'"
done
if [ -x "$build/app/raytrace-mpi" ]; then
    check "raytrace-mpi installed" test -x "$p/bin/raytrace-mpi"
fi
check "rayview finds its data in the moved prefix" \
    grep -qxF "data: $p/share/raytracer" <("$p/bin/rayview" --version)
for f in shaders/preview.vert shaders/preview.frag scenes/showpiece.ray scenes/parts scenes/textures/grid.png; do
    check "installed: share/raytracer/$f" test -e "$p/share/raytracer/$f"
done

# An installed scene, rendered by the installed raytrace from an unrelated directory, is the
# image the build tree's raytrace renders.
"$p/bin/raytrace" "$p/share/raytracer/scenes/showpiece.ray" --width 160 --height 120 -q -o a.png
check "the installed raytrace renders the installed showpiece" test $? -eq 0 -a -s a.png
"$build/app/raytrace" "$src/scenes/showpiece.ray" --width 160 --height 120 -q -o b.png
check "the same image as the build tree's" cmp -s a.png b.png

# rayview with no scene opens the installed showpiece (its default) and draws both panes.
if command -v xvfb-run >/dev/null; then
    xrun "$p/bin/rayview" --frames 40 --screenshot "$tmp/shot.png" --size 800x450 >"$tmp/rv.txt" 2>&1
    check "the installed rayview opens its default scene and exits 0" test $? -eq 0
    check "its window was saved" test -s "$tmp/shot.png"
    check "it opened the installed showpiece" grep -qx "rayview: opened $p/share/raytracer/scenes/showpiece.ray" "$tmp/rv.txt"
    # Not a blank window: the screenshot differs from a black image of its size.
    "$build/app/raytrace" "$src/tests/install/black.ray" --width 800 --height 450 -q -o black.png
    check "the window shows the scene (far from black)" \
        bash -c "! '$imgdiff' '$tmp/shot.png' black.png --max-mad 10 >/dev/null"
    # Without its data (the share directory gone), a clear message and exit 1, no crash.
    mv "$p/share/raytracer" "$p/share/elsewhere"
    xrun "$p/bin/rayview" --frames 5 "$p/share/elsewhere/scenes/simple.ray" >"$tmp/nodata.txt" 2>&1
    rc=$?
    check "rayview without its data exits 1" test $rc -eq 1
    check "and says where it looked" grep -q "cannot find shaders/preview.vert (looked in $p/share/raytracer" "$tmp/nodata.txt"
    RAYTRACER_DATA_DIR="$p/share/elsewhere" xrun "$p/bin/rayview" --frames 5 \
        "$p/share/elsewhere/scenes/simple.ray" >/dev/null 2>&1
    check "RAYTRACER_DATA_DIR points it at the data" test $? -eq 0
    mv "$p/share/elsewhere" "$p/share/raytracer"
else
    echo "test_install: xvfb-run missing: the installed rayview's window is not tested"
fi

# bash completion: the options come from --help, names and files after the options.
comp="$p/share/bash-completion/completions"
for prog in $programs; do check "completion installed for $prog" test -f "$comp/$prog"; done
complete_words() {  # complete_words WORD...: the completions of the last word
    bash -c 'source "$0"; COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
             _raytracer_complete; printf "%s\n" "${COMPREPLY[@]}"' "$comp/raytrace" "$@"
}
check "raytrace --sp completes to --spp" grep -qx -- "--spp" <(complete_words "$p/bin/raytrace" --sp)
check "rayview --tar completes to --target-error" \
    grep -qx -- "--target-error" <(complete_words "$p/bin/rayview" --tar)
check "--dialect offers v3" grep -qx v3 <(complete_words "$p/bin/raytrace" --dialect "")
check "--aov completes a list" grep -qx "albedo,normal" <(complete_words "$p/bin/raytrace" --aov albedo,no)
touch scene.ray notes.txt
out=$(complete_words "$p/bin/raytrace" "")
check "a scene completes to .ray files, not others" \
    bash -c "grep -qx scene.ray <<<'$out' && ! grep -qx notes.txt <<<'$out'"

# Desktop entry and MIME type.
desktop="$p/share/applications/rayview.desktop"
check "desktop entry installed" test -f "$desktop"
if command -v desktop-file-validate >/dev/null; then
    check "the desktop entry is valid" desktop-file-validate "$desktop"
fi
check "the desktop entry opens .ray files in rayview" grep -qx "MimeType=text/x-ray-scene;" "$desktop"
check "the desktop entry names an installed icon" test -s "$p/share/icons/hicolor/256x256/apps/rayview.png"
check "icons at 48 and 128 pixels" test -s "$p/share/icons/hicolor/48x48/apps/rayview.png" -a \
    -s "$p/share/icons/hicolor/128x128/apps/rayview.png"
if command -v update-mime-database >/dev/null; then
    cp -r "$p/share/mime" "$tmp/mime"
    update-mime-database "$tmp/mime" >/dev/null 2>&1
    check "the MIME database maps *.ray to text/x-ray-scene" grep -qx "text/x-ray-scene:\*.ray" "$tmp/mime/globs"
fi

summary "installed tree"
