#!/usr/bin/env bash
# raytrace's animation options end to end (spec §14.7): --at, --interpolation, --rotation, the
# --frames sequence (count, names, the same image as --at alone and on any thread count), the
# key file errors (exit 1, file:line:col, no output), the usage errors, --video with and without
# ffmpeg.
# usage: test_cli_animation.sh RAYTRACE SOURCE_DIR
set -u
rt="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/check.sh"
differ() { ! cmp -s "$1" "$2"; }
arm="$src/scenes/robot_arm.ray"
size=(--width 48 --height 36)

# One frame: --at changes the picture, wraps around the loop (4 s) and takes the options.
"$rt" "$arm" "${size[@]}" -q -o "$tmp/key0.png"
"$rt" "$arm" "${size[@]}" -q --at 1.3 -o "$tmp/at.png" >"$tmp/at.txt" 2>&1
check "--at exits 0" test $? -eq 0
check "--at moves the joints" differ "$tmp/key0.png" "$tmp/at.png"
"$rt" "$arm" "${size[@]}" -q --at -2.7 -o "$tmp/wrap.png"
check "--at wraps the loop" cmp -s "$tmp/at.png" "$tmp/wrap.png"
"$rt" "$arm" "${size[@]}" -q --at 1.3 --interpolation linear --rotation euler -o "$tmp/lin.png"
check "--interpolation and --rotation change the frame" differ "$tmp/at.png" "$tmp/lin.png"
"$rt" "$arm" "${size[@]}" --at 1.3 -o "$tmp/sum.png" >"$tmp/sum.txt" 2>&1
check "summary names the time" grep -q "animation 5 DOFs, 4 s loop; the frame at t = 1.3 (catmull-rom, quaternion)" "$tmp/sum.txt"
"$rt" "$arm" "${size[@]}" -q --rotation log -o "$tmp/nolog.png" 2>"$tmp/noat.txt"
check "--rotation without --at warns" grep -q "warning: --interpolation and --rotation have no effect without --at" "$tmp/noat.txt"
check "--rotation without --at is key 0" cmp -s "$tmp/key0.png" "$tmp/nolog.png"

# A sequence: frame k at k / fps, one file each, the same image as --at alone, any thread count.
"$rt" "$arm" "${size[@]}" --frames 5 --fps 4 --threads 2 -o "$tmp/f_%03d.png" >"$tmp/seq.txt" 2>&1
check "--frames exits 0" test $? -eq 0
check "--frames writes 5 files" test "$(ls "$tmp"/f_*.png | wc -l)" -eq 5
check "--frames names them" test -s "$tmp/f_004.png"
check "--frames summary" grep -q "wrote     5 frames, $tmp/f_000.png .. $tmp/f_004.png" "$tmp/seq.txt"
check "no temporary left" test -z "$(ls "$tmp" | grep part)"
"$rt" "$arm" "${size[@]}" -q --at 0.75 --threads 1 -o "$tmp/alone.png"
check "frame 3 is --at 0.75 alone" cmp -s "$tmp/alone.png" "$tmp/f_003.png"
"$rt" "$arm" "${size[@]}" -q --frames 2 --fps 4 --start 0.5 --threads 1 -o "$tmp/s_%d.png"
check "--start shifts the frames" cmp -s "$tmp/s_1.png" "$tmp/f_003.png"
check "frames differ" differ "$tmp/f_000.png" "$tmp/f_001.png"

# A V3 scene (#dynamic_affine): its frames move, and a sequence's frame is --at's.
orrery="$src/scenes/v3_orrery.ray"
"$rt" "$orrery" "${size[@]}" --frames 3 --fps 2 -o "$tmp/o_%d.png" >"$tmp/orrery.txt" 2>&1
check "V3 --frames exits 0" test $? -eq 0
check "V3 frames differ" differ "$tmp/o_0.png" "$tmp/o_1.png"
"$rt" "$orrery" "${size[@]}" -q --at 1 -o "$tmp/o_at1.png"
check "V3 frame 2 is --at 1 alone" cmp -s "$tmp/o_2.png" "$tmp/o_at1.png"

# Usage errors: exit 2 and nothing written.
"$rt" "$arm" --frames 3 -o "$tmp/nopattern.png" >/dev/null 2>"$tmp/u1.txt"
check "--frames without a pattern exits 2" test $? -eq 2
check "--frames pattern message" grep -q "needs one frame number in its file name, such as frame_%04d.png" "$tmp/u1.txt"
"$rt" "$arm" --interpolation cubic >/dev/null 2>"$tmp/u2.txt"
check "unknown interpolation exits 2" test $? -eq 2
check "unknown interpolation lists the names" grep -q "unknown interpolation 'cubic' (accepted: nearest, linear, catmull-rom, bspline)" "$tmp/u2.txt"
"$rt" "$arm" --rotation spin >/dev/null 2>"$tmp/u3.txt"
check "unknown rotation lists the names" grep -q "unknown rotation 'spin' (accepted: matrix, closest, euler, log, quaternion)" "$tmp/u3.txt"
"$rt" "$arm" --frames 2 --at 1 -o "$tmp/x_%d.png" >/dev/null 2>&1
check "--frames with --at exits 2" test $? -eq 2
"$rt" "$arm" --frames 2 --fps 0 -o "$tmp/x_%d.png" >/dev/null 2>&1
check "--fps 0 exits 2" test $? -eq 2
"$rt" "$arm" --video "$tmp/v.mp4" >/dev/null 2>&1
check "--video without --frames exits 2" test $? -eq 2
check "usage errors write nothing" test -z "$(ls "$tmp" | grep -E '^(x_|nopattern|v\.mp4)')"

# Bad key files: exit 1, the message at its place, no output.
mkdir -p "$tmp/bad"
printf '#key_file k.key\n#shape_sphere -1 0 0 0 1\n#joint_begin arm\n#shape_sphere -1 0 0 0 1\n#joint_end\n' >"$tmp/bad/t.ray"
bad_key() {  # bad_key NAME KEY-TEXT MESSAGE
    printf '%b' "$2" >"$tmp/bad/k.key"
    "$rt" "$tmp/bad/t.ray" -q --at 1 -o "$tmp/bad/out.png" >"$tmp/bad/err.txt" 2>&1
    check "$1 exits 1" test $? -eq 1
    check "$1 message" grep -qF "$3" "$tmp/bad/err.txt"
    check "$1 writes nothing" test ! -e "$tmp/bad/out.png"
}
id="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"
bad_key "truncated key file" "#DOFS 1 arm #DURATION 1 #FRAMES 2\n$id\n" "k.key:3:1: error: key file has 16 numbers after #FRAMES, expected 16·1·2 = 32"
bad_key "zero duration" "#DOFS 1 arm #DURATION 0 #FRAMES 1 $id" "k.key:1:23: error: #DURATION must be > 0, got 0"
bad_key "no such DOF" "#DOFS 1 leg #DURATION 1 #FRAMES 1 $id" "t.ray:3:14: error: no DOF 'arm' in key files k.key"
bad_key "non-finite key" "#DOFS 1 arm #DURATION 1 #FRAMES 1 1 0 0 0 0 1 0 0 0 0 1 0 inf 0 0 1" "k.key:1:59: error: non-finite number 'inf'"
rm -f "$tmp/bad/k.key"
"$rt" "$tmp/bad/t.ray" -q -o "$tmp/bad/out.png" >"$tmp/bad/err.txt" 2>&1
check "missing key file exits 1" test $? -eq 1
check "missing key file message" grep -q "t.ray:1:11: error: cannot open key file 'k.key'" "$tmp/bad/err.txt"

# --video: encoded by ffmpeg when it is installed; without it, a warning and the frames.
PATH=/nonexistent "$rt" "$arm" "${size[@]}" --frames 2 --video "$tmp/no.mp4" -o "$tmp/nv_%d.png" >/dev/null 2>"$tmp/nv.txt"
check "--video without ffmpeg exits 0" test $? -eq 0
check "--video without ffmpeg says so" grep -q "warning: --video: ffmpeg is not installed" "$tmp/nv.txt"
check "--video without ffmpeg writes the frames" test -s "$tmp/nv_1.png"
check "--video without ffmpeg writes no video" test ! -e "$tmp/no.mp4"
if command -v ffmpeg >/dev/null; then
    "$rt" "$arm" "${size[@]}" -q --frames 6 --fps 12 --video "$tmp/arm.mp4" -o "$tmp/v_%02d.png"
    check "--video exits 0" test $? -eq 0
    check "--video writes the video" test -s "$tmp/arm.mp4"
    check "--video leaves no scratch file" sh -c "! ls -A '$tmp' | grep -q '^\\.arm\\.mp4\\.'"
fi

# A --frames run that fails (here frame 3's name is taken by a directory; on a cluster, a full
# disk) leaves none of its frames, as raytrace-mpi's (docs/cluster.md), and says so.
mkdir -p "$tmp/fail/f_3.pfm"
"$rt" "$arm" "${size[@]}" --spp 1 --frames 6 -q -o "$tmp/fail/f_%d.pfm" >"$tmp/fail.txt" 2>&1
check "a failed --frames run exits 1" test $? -eq 1
check "it names the frame and the removal" grep -qF "raytrace: error: frame 3 not written (cannot write '$tmp/fail/f_3.pfm': it is a directory, not a regular file); the 3 frames written so far were removed" "$tmp/fail.txt"
check "none of its frames is left" test "$(ls -A "$tmp/fail")" = "f_3.pfm"
# A frame whose animation fails (its joint beyond the renderer's range at t = 0.5): the same.
printf '#key_file k.key\n#shape_sphere -1 0 0 0 1\n#joint_begin arm\n#shape_sphere -1 0 0 0 1\n#joint_end\n' >"$tmp/fail/t.ray"
printf '#DOFS 1 arm #DURATION 1 #FRAMES 2 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1  1 0 0 0 0 1 0 0 0 0 1 0 1e305 0 0 1\n' >"$tmp/fail/k.key"
"$rt" "$tmp/fail/t.ray" "${size[@]}" --spp 1 --frames 3 --fps 2 -q -o "$tmp/fail/g_%d.pfm" >"$tmp/fail2.txt" 2>&1
check "a frame whose animation fails exits 1" test $? -eq 1
check "and its frames are removed" bash -c "! ls '$tmp'/fail/g_* 2>/dev/null && grep -qF 'frame 1 not written (the animation failed there); the 1 frame written so far was removed' '$tmp/fail2.txt'"

summary "animation"
