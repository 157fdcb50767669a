#!/usr/bin/env bash
# The viewer's timeline under Xvfb: a scripted scrub, play and pause show what
# raytrace --at renders at the times the viewer reports, each pane alone at the render's size;
# scrubbing changes the picture; "render animation" writes the frames raytrace --frames writes.
# usage: test_rayview_animation.sh RAYVIEW SOURCE_DIR
set -u
rv=$(realpath "$1")
src="$2"
bin=$(dirname "$rv")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export XDG_CONFIG_HOME="$tmp/config"
source "$(dirname "$0")/check.sh"
arm="$src/scenes/robot_arm.ray"
view() {  # view PANE SCRIPT OUT FRAMES: one pane alone at 640x480, the output in OUT.txt
    xrun "$rv" --size 640x480 --panel off --layout "$1" \
        --frames "$4" --script "$2" --screenshot "$3.png" "$arm" >"$3.txt" 2>&1
}

# A scrub to t = 1.3: both panes show raytrace --at 1.3.
"$bin/raytrace" -q "$arm" --at 1.3 -o "$tmp/ref13.png"
printf '2 resolution 1\n3 time 1.3\n4 wait-spp 8\n' >"$tmp/scrub.txt"
view trace "$tmp/scrub.txt" "$tmp/trace13" 10
check "rayview exits 0" test $? -eq 0
check "the trace at t = 1.3 is raytrace --at 1.3" "$bin/imgdiff" "$tmp/trace13.png" "$tmp/ref13.png" --max-mad 2
view preview "$tmp/scrub.txt" "$tmp/preview13" 40
check "the preview at t = 1.3 is near raytrace --at 1.3" "$bin/imgdiff" "$tmp/preview13.png" "$tmp/ref13.png" --max-mad 8
printf '2 resolution 1\n3 time 3.1\n' >"$tmp/scrub2.txt"
view preview "$tmp/scrub2.txt" "$tmp/preview31" 40
check "scrubbing changes the picture" bash -c "! cmp -s '$tmp/preview13.png' '$tmp/preview31.png'"

# The interpolation and rotation choices: the trace is raytrace's with the same choices.
"$bin/raytrace" -q "$arm" --at 1.3 --interpolation nearest --rotation euler -o "$tmp/ref13le.png"
printf '2 resolution 1\n3 time 1.3\n4 interpolation nearest\n5 rotation euler\n6 wait-spp 8\n' \
    >"$tmp/choices.txt"
view trace "$tmp/choices.txt" "$tmp/trace13le" 10
check "nearest and euler: the trace is raytrace's" "$bin/imgdiff" "$tmp/trace13le.png" "$tmp/ref13le.png" --max-mad 1.5
"$bin/imgdiff" "$tmp/trace13le.png" "$tmp/ref13.png" --max-mad 1.5 >/dev/null 2>&1
check "nearest and euler change the picture" test $? -eq 1

# Play, then pause: the trace converges at the time the viewer paused at.
printf '2 resolution 1\n5 play\n45 pause\n46 wait-spp 8\n' >"$tmp/play.txt"
view trace "$tmp/play.txt" "$tmp/played" 50
paused=$(sed -n 's/.*paused at t = \([0-9.e+-]*\).*/\1/p' "$tmp/played.txt")
check "pause reports the time" test -n "$paused"
check "playing moved the time" awk -v t="${paused:-0}" 'BEGIN { exit !(t > 0.05) }'
"$bin/raytrace" -q "$arm" --at "${paused:-0}" -o "$tmp/ref-paused.png"
check "the paused trace is raytrace --at the paused time" "$bin/imgdiff" "$tmp/played.png" "$tmp/ref-paused.png" --max-mad 2
"$bin/raytrace" -q "$arm" -o "$tmp/ref-key0.png"
"$bin/imgdiff" "$tmp/played.png" "$tmp/ref-key0.png" --max-mad 2 >/dev/null 2>&1
check "the paused picture is not key 0's" test $? -eq 1

# Render animation: the frames raytrace --frames writes (fps 12, interpolation linear).
printf '2 fps 12\n2 interpolation linear\n3 render-animation %s 3 64 48 1\n4 wait-jobs\n' \
    "$tmp/rv_%02d.png" >"$tmp/render-script.txt"
view trace "$tmp/render-script.txt" "$tmp/render" 8
"$bin/raytrace" -q "$arm" --frames 3 --fps 12 --interpolation linear --width 64 --height 48 -o "$tmp/rt_%02d.png"
for k in 00 01 02; do
    check "render animation wrote frame $k" test -s "$tmp/rv_$k.png"
    check "frame $k is raytrace's" "$bin/imgdiff" "$tmp/rv_$k.png" "$tmp/rt_$k.png" --max-mad 0.5
done

summary "rayview animation"
