#!/usr/bin/env bash
# The viewer under Xvfb with scripted input: orbit, toggle shadows, edit a light, open a file.
# After each edit the trace restarts and the window's pixels change.
# usage: test_rayview.sh RAYVIEW SOURCE_DIR
set -u
rv=$(realpath "$1")
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export XDG_CONFIG_HOME="$tmp/config"  # the runs' settings, not the user's
source "$(dirname "$0")/check.sh"
cat >"$tmp/script.txt" <<SCRIPT
15 screenshot $tmp/0.png
16 orbit 0.4 0.1
30 screenshot $tmp/1.png
31 shadows off
45 screenshot $tmp/2.png
46 light 0 colour 0 0 3
60 screenshot $tmp/3.png
61 open $src/scenes/shapes.ray
75 screenshot $tmp/4.png
SCRIPT
xrun "$rv" --script "$tmp/script.txt" \
    "$src/scenes/lights.ray" >"$tmp/out.txt" 2>&1
rc=$?
check "rayview exits 0" test $rc -eq 0
for i in 0 1 2 3 4; do check "screenshot $i" test -s "$tmp/$i.png"; done
for cmd in orbit shadows light open; do
    check "$cmd restarts the trace" grep -q "$cmd: trace restarted" "$tmp/out.txt"
done
for i in 1 2 3 4; do
    check "edit before screenshot $i changes the window" bash -c "! cmp -s '$tmp/$((i - 1)).png' '$tmp/$i.png'"
done
# A V3 scene: a torus lit by a sphere light; its ambient colour and its radius edited.
cat >"$tmp/v3.ray" <<'SCENE'
#camera 0 2 6  0 -0.3 -1  0 1 0  0.5
#light_sphere 0.1 0.1 0.1  1 1 1  1 1 1  2 3 3  0.5  1 0 0
#material 0 0 0  0.5 0.5 0.5  0.6 0.5 0.4  0.3 0.3 0.3  20  0 0 0  1  -1 !!
#shape_torus 0  0 0 0  0.4 1.2
#shape_box 0  0 -1 0  6 0.2 6
SCENE
cat >"$tmp/v3.txt" <<SCRIPT
15 screenshot $tmp/v0.png
16 light 0 ambient 1 0 0
30 screenshot $tmp/v1.png
31 light 0 radius 1.5
45 screenshot $tmp/v2.png
SCRIPT
xrun "$rv" --script "$tmp/v3.txt" "$tmp/v3.ray" >"$tmp/v3out.txt" 2>&1
check "rayview exits 0 on a V3 scene" test $? -eq 0
check "V3 light edits restart the trace" test "$(grep -c 'light: trace restarted' "$tmp/v3out.txt")" -eq 2
check "the ambient edit changes the window" bash -c "! cmp -s '$tmp/v0.png' '$tmp/v1.png'"
check "the radius edit changes the window" bash -c "! cmp -s '$tmp/v1.png' '$tmp/v2.png'"
cat "$tmp/v3out.txt"
# Both panes show raytrace's framing for any up vector (rolled, straight down, straight up):
# each pane alone at the render's size against raytrace's image of the file.
imgdiff="$(dirname "$rv")/imgdiff"
scene() {
    cat <<SCENE
#camera $1
#light_point 4 6 6  1 1 1  1 0 0
#ambient 0.2 0.2 0.2
#material 0 0 0  0.2 0.2 0.2  0.8 0.2 0.2  0 0 0  1  0 0 0  1  -1 !red!
#material 0 0 0  0.2 0.2 0.2  0.2 0.8 0.2  0 0 0  1  0 0 0  1  -1 !green!
#shape_box 0  0 0 0  6 0.2 0.5
#shape_sphere 1  2.5 1 -1.5  0.8
SCENE
}
scene "0 3 9  0 -0.3 -1  1 1 0  0.5" >"$tmp/rolled.ray"
scene "0 8 0  0 -1 0  0 0 -1  0.5" >"$tmp/down.ray"
scene "0 -8 0  0 1 0  1 0 0  0.5" >"$tmp/up.ray"
printf '5 resolution 1\n6 wait-spp 8\n' >"$tmp/full.txt"
for cam in rolled down up; do
    "$(dirname "$rv")/raytrace" -q "$tmp/$cam.ray" -o "$tmp/$cam-raytrace.png"
    for pane in preview trace; do
        # wait-spp: on a loaded machine the trace's first full pass can take seconds.
        xrun "$rv" --size 640x480 --panel off --layout $pane \
            --frames 12 --script "$tmp/full.txt" --screenshot "$tmp/$cam-$pane.png" "$tmp/$cam.ray" \
            >/dev/null 2>&1
        check "the $pane pane frames the $cam camera as raytrace does" \
            "$imgdiff" "$tmp/$cam-$pane.png" "$tmp/$cam-raytrace.png" --max-mad 2
    done
done
# The preview shows mirrors and glass as the trace does, approximately (materials.ray: mean
# difference 26.5 of 255 with local shading only, 6.6 with the environment maps).
"$(dirname "$rv")/raytrace" -q "$src/scenes/materials.ray" -o "$tmp/materials-raytrace.png"
printf '2 markers off\n3 wait-jobs\n' >"$tmp/markers.txt"
(cd "$src/scenes" && xrun "$rv" --size 640x480 --panel off \
    --layout preview --frames 8 --script "$tmp/markers.txt" --screenshot "$tmp/materials.png" \
    materials.ray >/dev/null 2>&1)
check "the preview of materials.ray is near the trace" "$imgdiff" "$tmp/materials.png" \
    "$tmp/materials-raytrace.png" --max-mad 12 --max-dark-share 0.01

# A texture put on a material in the panel (script: material I texture T) shows in the preview
# as in the trace of the file that names it: the image and the set's texture coordinates are
# uploaded then (the preview had left both out).
for t in -1 0; do
    cat >"$tmp/retexture$t.ray" <<SCENE
#camera 0 0 4  0 0 -1  0 1 0  0.5
#light_dir 1 1 1  0 0 -1
#texture $src/scenes/textures/checker.bmp
#material 0 0 0  0.2 0.2 0.2  0.8 0.8 0.8  0 0 0  1  0 0 0  1  $t !ball!
#shape_sphere 0  0 0 0  1.5
SCENE
done
"$(dirname "$rv")/raytrace" -q "$tmp/retexture0.ray" --width 320 --height 240 \
    -o "$tmp/retexture-raytrace.png"
printf '2 markers off\n3 material 0 texture 0\n' >"$tmp/retexture.txt"
xrun "$rv" --size 320x240 --panel off --layout preview --frames 12 --script "$tmp/retexture.txt" \
    --screenshot "$tmp/retexture.png" "$tmp/retexture-1.ray" >/dev/null 2>&1
check "a texture put on a material shows in the preview" "$imgdiff" "$tmp/retexture.png" \
    "$tmp/retexture-raytrace.png" --max-mad 3
printf '3 material 0 texture 1\n' >"$tmp/retexture-bad.txt"
xrun "$rv" --size 320x240 --frames 6 --script "$tmp/retexture-bad.txt" \
    "$tmp/retexture-1.ray" >"$tmp/retexture-bad.out" 2>&1
check "a texture index the file lacks is refused with its range" \
    grep -q "texture.*\(-1\|0\)" "$tmp/retexture-bad.out"

# The target error: the trace stops once its estimate reaches it, and the status bar says when;
# before that, the time it will take (from the slope of the error against time).
cat >"$tmp/target.txt" <<SCRIPT
3 resolution 1
4 target-error 0.05
5 wait-spp 8
8 status
9 target-error 1e-7
10 wait-spp 24
12 status
SCRIPT
xrun "$rv" --size 640x480 --script "$tmp/target.txt" "$src/scenes/showpiece.ray" >"$tmp/targetout.txt" 2>&1
check "target-error runs" test $? -eq 0
check "a reached target is said with its time" grep -q "status: 8 spp | .* | target 0.05 reached at [0-9.]* s" "$tmp/targetout.txt"
check "an unreached target says how long it will take" grep -Eq "status: .* \| target 1e-07 in (~[0-9.]+ s|> 1 h)" "$tmp/targetout.txt"

# Every kind of scripted input runs and is answered (the camera and lights restart the trace).
cat >"$tmp/all.txt" <<SCRIPT
5 pan 0.1 0
6 dolly 0.8
7 look 0.05 0
8 fly 0 0.1 0
9 light 0 position 1 5 2
10 add-light directional
11 add-light spot
12 frame-light 1
13 pick 0.5 0.6
13 inspect 100 80
14 exposure 1
15 tonemap aces
16 depth 3
17 help on
18 undo
19 redo
20 save-scene $tmp/saved.ray
21 save-image $tmp/saved.png
22 reload
30 screenshot $tmp/all.png
SCRIPT
(cd "$src/scenes" && xrun "$rv" --script "$tmp/all.txt" \
    lights.ray >"$tmp/allout.txt" 2>&1)
check "every scripted input runs" test $? -eq 0
for cmd in pan dolly look fly light add-light frame-light depth; do
    check "$cmd restarts the trace" grep -q "$cmd: trace restarted" "$tmp/allout.txt"
done
check "pick names the shape and its directive" grep -q "picked .* lights.ray:[0-9]" "$tmp/allout.txt"
check "inspect prints the pixel's ray tree" grep -q "^camera ray, depth 5: from" "$tmp/allout.txt"
check "inspect names the hit's directive" grep -qE "^  hits .* at lights.ray:[0-9]+:[0-9]+" "$tmp/allout.txt"
check "inspect ends with the pixel's value" grep -q "^pixel value (" "$tmp/allout.txt"
check "save-scene writes the edits" grep -q "#light_directional\|#light_dir" "$tmp/saved.ray"
# "Revert to the file" (script: revert): the file's lights again after an edit and an added
# light, whatever was kept.
cat >"$tmp/revert.txt" <<SCRIPT
3 light 0 position 1 5 2
4 add-light point
5 save-scene $tmp/edited.ray
6 revert
7 save-scene $tmp/reverted.ray
SCRIPT
(cd "$src/scenes" && xrun "$rv" --script "$tmp/revert.txt" lights.ray >/dev/null 2>&1)
check "revert runs" test $? -eq 0
check "the edit was saved before the revert" bash -c "grep -c '^#light_' '$tmp/edited.ray' | grep -qx 4"
# A material edit (the panel's, script: material) is saved with the scene.
printf '3 material 0 diffuse 0.1 0.6 0.1\n4 save-scene %s\n' "$tmp/material.ray" >"$tmp/material.txt"
(cd "$src/scenes" && xrun "$rv" --script "$tmp/material.txt" lights.ray >/dev/null 2>&1)
check "a material edit runs" test $? -eq 0
check "a material edit is saved" grep -q '^#material .*0.1 0.6 0.1.*!white!' "$tmp/material.ray"
check "revert brings back the file's lights" bash -c "grep -c '^#light_' '$tmp/reverted.ray' | grep -qx 3 && grep -q '^#light_spot 1.6 0.3 0.3 *-2 6 2' '$tmp/reverted.ray'"
check "save-image writes the trace" test -s "$tmp/saved.png"
echo "1 teleport 1 2" >"$tmp/unknown.txt"
xrun "$rv" --frames 3 --script "$tmp/unknown.txt" \
    "$src/scenes/lights.ray" >"$tmp/unknownout.txt" 2>&1
check "an unknown command is an error" grep -q "unknown command .*teleport" "$tmp/unknownout.txt"

# Bad script input is reported and the run goes on: a non-finite setting, a screenshot that
# cannot be written; a scene that fails at start-up still takes the script's open.
echo '#shape_sphere 0  0 0 0  1' >"$tmp/broken.ray"
cat >"$tmp/bad.txt" <<SCRIPT
3 resolution nan
4 screenshot $tmp/no/such/dir/shot.png
5 open $src/scenes/shapes.ray
20 screenshot $tmp/after.png
SCRIPT
xrun "$rv" --script "$tmp/bad.txt" "$tmp/broken.ray" \
    >"$tmp/badout.txt" 2>&1
check "a run with failed commands exits 1, not a crash" test $? -eq 1
check "the non-finite resolution is refused" grep -q "resolution: 'nan' is not a number" "$tmp/badout.txt"
check "the unwritable screenshot is reported" grep -q "no/such/dir/shot.png" "$tmp/badout.txt"
check "the broken file's error is printed" grep -q "broken.ray:1:" "$tmp/badout.txt"
check "the script's open works with no scene open" test -s "$tmp/after.png"
# Any failure of a scripted run exits 1, with its message: a failed open (a FIFO here: an error,
# not a frozen window; the timeout turns a hang into a failed check), a failed background load
# or render, a scene that does not open at start-up.
mkfifo "$tmp/fifo.ray"
fails() {  # fails NAME MESSAGE RAYVIEW-ARGS...
    local name=$1 message=$2
    shift 2
    timeout 120 "$(dirname "$0")/xrun.sh" "$rv" "$@" >"$tmp/failout.txt" 2>&1
    check "$name exits 1" test $? -eq 1
    check "$name: its message" grep -qF -- "$message" "$tmp/failout.txt"
}
echo "1 open $tmp/fifo.ray" >"$tmp/fifo.txt"
fails "a scripted open of a FIFO" "'$tmp/fifo.ray' is a FIFO, not a regular file" \
    --script "$tmp/fifo.txt" "$src/scenes/lights.ray"
printf '1 open-background %s\n2 wait-jobs\n' "$tmp/none.ray" >"$tmp/bgload.txt"
fails "a failed background load" "none.ray" --script "$tmp/bgload.txt" "$src/scenes/lights.ray"
printf '1 render-image %s 16 16 1\n2 wait-jobs\n' "$tmp/no/dir/r.png" >"$tmp/bgrender.txt"
fails "a failed background render" "no/dir/r.png" --script "$tmp/bgrender.txt" "$src/scenes/lights.ray"
fails "--frames with a scene that does not open" "broken.ray:1:" --frames 3 "$tmp/broken.ray"
# A script that is no regular file, and frame numbers past the maximum, are usage errors.
mkdir "$tmp/scriptdir"
for script in "$tmp/scriptdir" "$tmp/fifo.ray"; do
    timeout 60 "$rv" --script "$script" "$src/scenes/lights.ray" >/dev/null 2>"$tmp/err.txt"
    check "--script $script exits 2" test $? -eq 2
    check "--script $script: says it is no regular file" grep -q "not a regular file" "$tmp/err.txt"
done
echo "100001 status" >"$tmp/late.txt"
"$rv" --script "$tmp/late.txt" "$src/scenes/lights.ray" >/dev/null 2>"$tmp/err.txt"
check "a frame number past 100000 exits 2" test $? -eq 2
check "and names its line" grep -q "late.txt:1: frame 100001 is not in 0..100000" "$tmp/err.txt"
"$rv" --frames 100001 "$src/scenes/lights.ray" >/dev/null 2>"$tmp/err.txt"
check "--frames past 100000 exits 2" test $? -eq 2
# Settings kept between runs: the window's size and the recent files.
conf="$tmp/config/rayview/rayview.conf"
check "the settings are written at exit" grep -q "^window = [0-9]*x[0-9]*$" "$conf"
check "the recent files are kept" grep -q "^recent = .*scenes/lights.ray" "$conf"
sed -i 's/^window = .*/window = 800x500/' "$conf"
xrun "$rv" --frames 3 --screenshot "$tmp/sized.png" \
    "$src/scenes/lights.ray" >/dev/null 2>&1
check "the next run opens at the kept size" bash -c "file '$tmp/sized.png' | grep -q '800 x 500'"
xrun "$rv" --frames 3 --size 640x480 --screenshot "$tmp/other.png" \
    "$src/scenes/lights.ray" >/dev/null 2>&1
check "a scripted --size run keeps the saved size" grep -q "^window = 800x500$" "$conf"
# A kill (SIGTERM; Ctrl+C's SIGINT the same) closes the viewer as its window's close button
# does: exit 0, settings kept. (A background job here ignores SIGINT, hence TERM.)
rm -f "$conf"
timeout 60 "$(dirname "$0")/xrun.sh" bash -c '"$0" "$1" & pid=$!; sleep 3; kill -TERM $pid; wait $pid' \
    "$rv" "$src/scenes/lights.ray" >/dev/null 2>&1
check "SIGTERM closes the viewer cleanly" test $? -eq 0
check "SIGTERM keeps the settings" test -s "$conf"
"$rv" --missing-textures bogus "$src/scenes/lights.ray" >"$tmp/bad.txt" 2>&1
check "--missing-textures takes error or checker only" test $? -eq 2
check "--help lists --missing-textures, as raytrace's" bash -c "'$rv' --help | grep -q -- '--missing-textures M:{error,checker}'"
# The comparison pane: a render with the wrong specular exponent against the reference, its
# difference (a heat map), the threshold view (red) and theirs, each in the pane right of the
# trace (--layout trace --panel off: the window's right half); a probe prints both values and
# the reference's ray tree; a file that cannot be read fails the run.
cat >"$tmp/cmp.ray" <<'SCENE'
#camera 0 0 5  0 0 -1  0 1 0  0.5
#light_point 1 1 1  2 2 4  1 0 0
#material 0.1 0.1 0.1  0 0 0  0.4 0.4 0.4  0.8 0.8 0.8  40  0 0 0  1  -1 !!
#shape_sphere 0  0 0 0  1.2
SCENE
sed 's/  40  /  4  /' "$tmp/cmp.ray" >"$tmp/cmp_wrong.ray"
"$(dirname "$rv")/raytrace" "$tmp/cmp_wrong.ray" -o "$tmp/wrong.png" --width 160 --height 120 \
    >/dev/null 2>&1
check "raytrace renders their image" test -s "$tmp/wrong.png"
cat >"$tmp/cmp.txt" <<SCRIPT
1 wait-compare 60
2 compare view difference
4 screenshot $tmp/cmp_diff.ppm
5 compare view threshold
7 screenshot $tmp/cmp_thr.ppm
8 compare flip
10 screenshot $tmp/cmp_theirs.ppm
11 compare probe 95 45
12 status
SCRIPT
xrun "$rv" --compare "$tmp/wrong.png" --layout trace --panel off --size 1200x500 \
    --script "$tmp/cmp.txt" "$tmp/cmp.ray" >"$tmp/cmp_out.txt" 2>&1
check "rayview --compare exits 0" test $? -eq 0
check "it says the trace takes the image's size" grep -q "comparing with wrong.png (160x120)" \
    "$tmp/cmp_out.txt"
check "the figures are printed" grep -qE "vs wrong.png: mean \|diff\| [0-9.]+ .* [0-9.]+% off by > 8/255" \
    "$tmp/cmp_out.txt"
check "a probe prints both values" grep -qE "compare pixel 95,45: theirs \([0-9 ]+\), ours \([0-9 ]+\), off by" \
    "$tmp/cmp_out.txt"
check "and the reference's ray tree there" grep -q "^camera ray, depth" "$tmp/cmp_out.txt"
python3 - "$tmp/cmp_diff.ppm" "$tmp/cmp_thr.ppm" "$tmp/cmp_theirs.ppm" >"$tmp/cmp_px.txt" 2>&1 <<'PY'
import sys
def load(p):
    data = open(p, 'rb').read()
    parts = data.split(maxsplit=4)
    w, h = int(parts[1]), int(parts[2])
    return w, h, parts[4][-w * h * 3:]
def count(p, test, x0, x1):  # pixels of the central box of a half passing `test`
    w, h, px = load(p)
    n = 0
    for y in range(h // 4, 3 * h // 4):
        for x in range(x0 + w // 8, x1 - w // 8):
            i = 3 * (y * w + x)
            n += test(px[i], px[i + 1], px[i + 2])
    return n, w
hue = lambda r, g, b: max(r, g, b) - min(r, g, b) > 100  # a heat map's colours, not grey
red = lambda r, g, b: r >= 240 and g <= 40 and b <= 40
w = load(sys.argv[1])[0]
print('heat', count(sys.argv[1], hue, w // 2, w)[0], 'trace', count(sys.argv[1], hue, 0, w // 2)[0])
print('red', count(sys.argv[2], red, w // 2, w)[0])
print('theirs', count(sys.argv[3], hue, w // 2, w)[0])
PY
read -r _ heat _ trace_hue <<<"$(grep '^heat' "$tmp/cmp_px.txt")"
check "the difference view is a heat map (${heat:-?} coloured pixels)" test "${heat:-0}" -gt 500
check "beside a grey trace (${trace_hue:-?})" test "${trace_hue:-1}" -eq 0
check "the threshold view marks pixels red" test "$(awk '/^red/ {print $2}' "$tmp/cmp_px.txt")" -gt 100
check "theirs is shown as it is (grey)" test "$(awk '/^theirs/ {print $2}' "$tmp/cmp_px.txt")" -eq 0
xrun "$rv" --compare "$tmp/missing.png" --frames 3 "$tmp/cmp.ray" >/dev/null 2>"$tmp/cmp_err.txt"
check "a missing image fails the run" test $? -eq 1
check "and says why" grep -q "cannot compare with $tmp/missing.png" "$tmp/cmp_err.txt"
cat "$tmp/cmp_out.txt"
cat "$tmp/out.txt"
summary
