#!/usr/bin/env bash
# Split renders end to end: raytrace -o NAME.part with --tile and --samples, merged by
# raymerge, equals the one-process render bit for bit (.pfm compared byte for byte) for several
# split shapes, an instanced scene and an animation frame; every refused part (corrupt,
# truncated, another scene, other settings, overlapping or missing coverage, an image beyond
# --max-pixels) gets its message and no output file, parts that miss pixels of a large image
# before the image is allocated.
# usage: test_split_merge.sh RAYTRACE RAYMERGE SOURCE_DIR
set -u
rt="$1"
merge="$2"
src="$3"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/check.sh"
size=(--width 61 --height 45 --spp 6)

# split NAME SCENE "ARGS|ARGS|..." [EXTRA...]: the parts, merged, against the whole render.
split() {
    local name="$1" scene="$2" shares="$3"
    shift 3
    "$rt" "$scene" "${size[@]}" "$@" -q -o "$tmp/$name-whole.pfm"
    local parts=() i=0
    IFS='|' read -ra list <<<"$shares"
    for share in "${list[@]}"; do
        # shellcheck disable=SC2086
        "$rt" "$scene" "${size[@]}" "$@" $share --threads $((1 + i % 2)) -q -o "$tmp/$name-$i.part"
        parts+=("$tmp/$name-$i.part")
        i=$((i + 1))
    done
    "$merge" -q -o "$tmp/$name-merged.pfm" "${parts[@]}"
    check "$name: merge exits 0" test $? -eq 0
    check "$name: the merged image is the whole render's, bit for bit" \
        cmp -s "$tmp/$name-whole.pfm" "$tmp/$name-merged.pfm"
}
show="$src/scenes/showpiece.ray"
split one "$show" "--samples 0:6"
split tiles "$show" "--tile 0,0,30,45|--tile 30,0,61,20|--tile 30,20,61,45"
split samples "$show" "--samples 0:1|--samples 1:4|--samples 4:6"
split both "$show" "--tile 0,0,61,13 --samples 0:3|--tile 0,0,61,13 --samples 3:6|--tile 0,13,17,45|--tile 17,13,61,45 --samples 0:5|--tile 17,13,61,45 --samples 5:6"
split instanced "$src/scenes/groups.ray" "--tile 0,0,40,45 --samples 0:2|--tile 0,0,40,45 --samples 2:6|--tile 40,0,61,45"
split soft "$src/scenes/v3_penumbra.ray" "--samples 0:3|--samples 3:6" --light-radius 0.2
split frame "$src/scenes/robot_arm.ray" "--tile 0,0,61,30|--tile 0,30,61,45" --frame 7 --fps 4
"$rt" "$src/scenes/robot_arm.ray" "${size[@]}" --at 1.75 -q -o "$tmp/at.pfm"
check "--frame 7 --fps 4 is --at 1.75" cmp -s "$tmp/at.pfm" "$tmp/frame-whole.pfm"
"$merge" -q -o "$tmp/tiles.png" "$tmp"/tiles-*.part
check "merge writes any format" test -s "$tmp/tiles.png"

# Refused: each with its message, and no output.
refused() {  # refused NAME MESSAGE PART...
    local name="$1" message="$2"
    shift 2
    "$merge" -o "$tmp/refused.pfm" "$@" >"$tmp/err.txt" 2>&1
    check "$name: exit 1" test $? -eq 1
    check "$name: message" grep -qF "$message" "$tmp/err.txt"
    check "$name: no output" test ! -e "$tmp/refused.pfm"
}
cp "$tmp/tiles-1.part" "$tmp/truncated.part"
truncate -s -100 "$tmp/truncated.part"
refused "truncated part" "truncated.part: truncated: " "$tmp/tiles-0.part" "$tmp/truncated.part" "$tmp/tiles-2.part"
cp "$tmp/tiles-1.part" "$tmp/corrupt.part"
printf '\x7f' | dd of="$tmp/corrupt.part" bs=1 seek=2000 conv=notrunc 2>/dev/null
refused "corrupt part" "corrupt.part: corrupt: its checksum does not match" "$tmp/tiles-0.part" "$tmp/corrupt.part" "$tmp/tiles-2.part"
refused "not a part" "not a part file" "$tmp/tiles-0.part" "$tmp/tiles-whole.pfm"
refused "another scene" "instanced-0.part is of another scene" "$tmp/tiles-0.part" "$tmp/instanced-0.part"
"$rt" "$show" "${size[@]}" --tile 30,0,61,45 --depth 2 -q -o "$tmp/depth2.part"
refused "other settings" "depth2.part was rendered with other settings" "$tmp/tiles-0.part" "$tmp/depth2.part"
refused "overlapping parts" "is in two parts ($tmp/tiles-1.part and $tmp/tiles-1.part)" "$tmp/tiles-0.part" "$tmp/tiles-1.part" "$tmp/tiles-2.part" "$tmp/tiles-1.part"
refused "missing tile" "pixel (30, 20): samples 0..5 are in no part" "$tmp/tiles-0.part" "$tmp/tiles-1.part"
refused "missing samples" "samples 4..5 are in no part" "$tmp/samples-0.part" "$tmp/samples-1.part"
# A part of a 32768 x 32768 image (one pixel of it): refused by the size of its image before
# anything is allocated (merging made the whole image first, 8.2 GB); --max-pixels is the budget.
"$rt" "$show" --width 32768 --height 32768 --max-pixels 1073741824 --tile 0,0,1,1 -q \
    -o "$tmp/huge.part"
refused "an image beyond the budget" "huge.part: its image of 32768x32768 pixels (1073741824) is larger than the budget of 67108864 pixels" "$tmp/huge.part"
refused "--max-pixels" "tiles-0.part: its image of 61x45 pixels (2745) is larger than the budget of 2000 pixels" --max-pixels 2000 "$tmp"/tiles-?.part
"$merge" -o "$tmp/x.png" --max-pixels 0 "$tmp/tiles-0.part" >/dev/null 2>&1
check "--max-pixels 0 exits 2" test $? -eq 2
# Issue 49: a part of an image within the budget (77 KB, 40x40 pixels of 8192x8192) made
# raymerge allocate the whole image (5.5 GB) before its coverage error. The parts' headers are
# read first and the coverage checked from their tiles and samples: refused before a pixel is
# read or the image allocated, under a cap of 1 GB (not for a sanitizer build, as
# check_out_of_memory) and in a few MB (GNU time's maximum resident set size).
"$rt" "$show" --width 8192 --height 8192 --spp 1 --tile 0,0,40,40 -q -o "$tmp/corner.part"
small_merge() {  # small_merge NAME MESSAGE ARGS...: exit 1, MESSAGE, under 64 MB, no output
    local name="$1" message="$2" sanitized=0
    shift 2
    grep -q -e __asan_init -e __tsan_init "$merge" && sanitized=1
    (test $sanitized -eq 1 || ulimit -v 1000000
        exec /usr/bin/time -f "%M" -o "$tmp/rss.txt" "$merge" -o "$tmp/refused.pfm" "$@") \
        >"$tmp/err.txt" 2>&1
    check "$name: exit 1" test $? -eq 1
    check "$name: message" grep -qxF "$message" "$tmp/err.txt"
    check "$name: no output" test ! -e "$tmp/refused.pfm"
    local rss
    rss=$(tail -n 1 "$tmp/rss.txt")  # after "Command exited with non-zero status 1"
    check "$name: under 64 MB ($rss KB)" test $sanitized -eq 1 -o "$rss" -lt 65536
}
small_merge "a small part of a large image" \
    "raymerge: error: the parts do not cover the image once: pixel (40, 0): samples 0..0 are in no part" \
    "$tmp/corner.part"
# And beyond the memory there is (the budget raised to 2^30 pixels): the same.
small_merge "a one-pixel part of 32768x32768" \
    "raymerge: error: the parts do not cover the image once: pixel (1, 0): samples 0..0 are in no part" \
    --max-pixels 1073741824 "$tmp/huge.part"

# raytrace's usage errors for splits.
"$rt" "$show" --tile 0,0,10,10 -o "$tmp/x.png" >/dev/null 2>"$tmp/u.txt"
check "--tile without .part exits 2" test $? -eq 2
check "--tile without .part says so" grep -q "write a partial result: -o must end in .part" "$tmp/u.txt"
"$rt" "$show" --tile 0,0,700,10 -o "$tmp/x.part" >/dev/null 2>"$tmp/u.txt"
check "a tile outside the image exits 2" test $? -eq 2
"$rt" "$show" --spp 4 --samples 2:5 -o "$tmp/x.part" >/dev/null 2>"$tmp/u.txt"
check "samples beyond --spp exit 2" test $? -eq 2
check "samples beyond --spp say so" grep -q "is not inside the --spp 4 samples" "$tmp/u.txt"
"$rt" "$show" --tile 1,2,3 -o "$tmp/x.part" >/dev/null 2>&1
check "a malformed tile exits 2" test $? -eq 2
check "usage errors write no part" test ! -e "$tmp/x.part"

# Scratch files have names of their own (they were OUT.part, truncated and removed): an output
# named like an input part does not destroy it, nor does raytrace -o x.png an x.png.part.
mkdir "$tmp/own"
cp "$tmp/tiles-0.part" "$tmp/own/img.pfm.part"
"$merge" -q -o "$tmp/own/img.pfm" "$tmp/own/img.pfm.part" "$tmp/tiles-1.part" "$tmp/tiles-2.part"
check "raymerge -o img.pfm img.pfm.part ... exits 0" test $? -eq 0
check "and its input part is intact" cmp -s "$tmp/tiles-0.part" "$tmp/own/img.pfm.part"
check "and the image is the whole render's" cmp -s "$tmp/tiles-whole.pfm" "$tmp/own/img.pfm"
echo "not mine to touch" >"$tmp/own/x.png.part"
"$rt" "$show" --width 16 --height 12 --spp 1 -q -o "$tmp/own/x.png"
check "raytrace -o x.png leaves x.png.part alone" grep -qx "not mine to touch" "$tmp/own/x.png.part"
check "and leaves no scratch file" test "$(ls -A "$tmp/own" | sort | tr '\n' ' ')" = "img.pfm img.pfm.part x.png x.png.part "

summary "split and merge"
