#!/usr/bin/env bash
# The viewer under Xvfb with scripted input: orbit, toggle shadows, edit a light, open a file.
# After each edit the trace restarts and the window's pixels change.
# usage: test_rayview.sh RAYVIEW SOURCE_DIR
set -u
rv="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
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
xvfb-run -a -s "-screen 0 1280x720x24" "$rv" --script "$tmp/script.txt" \
    "$src/scenes/lights.ray" >"$tmp/out.txt" 2>&1
rc=$?
fails=0
passes=0
check() {
    if "${@:2}"; then passes=$((passes + 1)); else echo "FAIL: $1"; fails=$((fails + 1)); fi
}
check "rayview exits 0" test $rc -eq 0
for i in 0 1 2 3 4; do check "screenshot $i" test -s "$tmp/$i.png"; done
for cmd in orbit shadows light open; do
    check "$cmd restarts the trace" grep -q "$cmd: trace restarted" "$tmp/out.txt"
done
for i in 1 2 3 4; do
    check "edit before screenshot $i changes the window" bash -c "! cmp -s '$tmp/$((i - 1)).png' '$tmp/$i.png'"
done
"$rv" --missing-textures bogus "$src/scenes/lights.ray" >"$tmp/bad.txt" 2>&1
check "--missing-textures takes error or checker only" test $? -eq 2
check "--help lists --missing-textures" bash -c "'$rv' --help | grep -q -- '--missing-textures error|checker'"
cat "$tmp/out.txt"
echo "$passes passed, $fails failed"
test "$fails" -eq 0
