#!/usr/bin/env bash
# End-to-end checks of the raytrace CLI: exit codes 0/1/2, the file:line:col message, no output
# file on failure, the formats by extension, identical images for any thread count.
# usage: test_cli.sh RAYTRACE SOURCE_DIR
set -u
rt="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/check.sh"

cat >"$tmp/ok.ray" <<'RAY'
#camera 0 0 5  0 0 -1  0 1 0  0.5
#light_point 1 1 1  2 2 2  1 0 0
#material 0 0 0  .1 .1 .1  .8 .2 .2  .5 .5 .5  20  0 0 0  1  -1 !!
#shape_sphere 0  0 0 0  1
RAY
printf '#background 0 0 0\n#shape_sphere 0 0 0 0 1 x\n' >"$tmp/bad.ray"

"$rt" "$tmp/ok.ray" -o "$tmp/ok.png" --width 40 --height 30 >"$tmp/out.txt" 2>&1
check "success exits 0" test $? -eq 0
check "png written" test -s "$tmp/ok.png"
check "prints shapes" grep -q "sphere 1" "$tmp/out.txt"
check "prints rays per second" grep -q "ray/s" "$tmp/out.txt"
check "prints dialect" grep -q "(V1" "$tmp/out.txt"

"$rt" "$tmp/bad.ray" -o "$tmp/bad.png" >"$tmp/err.txt" 2>&1
check "scene error exits 1" test $? -eq 1
check "scene error message" grep -q "bad.ray:2:15: error: material index 0 out of range" "$tmp/err.txt"
check "no output on scene error" test ! -e "$tmp/bad.png"
check "no scratch file left" sh -c "! ls -A '$tmp' | grep -q '^\\.bad\\.png\\.'"

"$rt" "$tmp/ok.ray" --width 0 -o "$tmp/x.png" >/dev/null 2>&1
check "bad width exits 2" test $? -eq 2
"$rt" "$tmp/ok.ray" --depth 30000 -o "$tmp/x.png" >/dev/null 2>"$tmp/usage.txt"
check "a depth beyond the maximum exits 2" test $? -eq 2
check "and names the maximum" grep -q "^raytrace: --depth must be between 1 and 256" "$tmp/usage.txt"
"$rt" "$tmp/ok.ray" --bogus >/dev/null 2>"$tmp/usage.txt"
check "unknown option exits 2" test $? -eq 2
check "unknown option message" grep -q "^raytrace: .*--bogus" "$tmp/usage.txt"
check "usage error points to --help" grep -q "see raytrace --help" "$tmp/usage.txt"
"$rt" >/dev/null 2>&1
check "no scene exits 2" test $? -eq 2
"$rt" "$tmp/ok.ray" -o "$tmp/x.tiff" >/dev/null 2>&1
check "unknown format exits 2" test $? -eq 2
"$rt" "$tmp/ok.ray" --dialect v7 >/dev/null 2>&1
check "bad dialect exits 2" test $? -eq 2
"$rt" --help | grep -q -- "--no-shadows"
check "help lists options" test $? -eq 0
"$rt" --help | grep -q -- "--width N=640"
check "help shows defaults" test $? -eq 0

"$rt" "$tmp/nothere.ray" -o "$tmp/n.png" >"$tmp/err2.txt" 2>&1
check "missing scene exits 1" test $? -eq 1
check "missing scene message" grep -q "cannot open scene file" "$tmp/err2.txt"

"$rt" "$tmp/ok.ray" --dialect v0 -o "$tmp/v0.png" >"$tmp/err3.txt" 2>&1
check "dialect override rejects V1 material" test $? -eq 1
check "dialect override message" grep -q "needs 16" "$tmp/err3.txt"

"$rt" "$tmp/ok.ray" -o "$tmp/nodir/x.png" >"$tmp/err4.txt" 2>&1
check "missing output directory exits 1" test $? -eq 1
check "missing output directory message" grep -q "cannot write" "$tmp/err4.txt"
mkdir -p "$tmp/adir.png"
"$rt" "$tmp/ok.ray" -o "$tmp/adir.png" >/dev/null 2>&1
check "output is a directory exits 1" test $? -eq 1

for ext in png bmp ppm pfm; do
    "$rt" "$tmp/ok.ray" -q -o "$tmp/f.$ext" --width 20 --height 10 >/dev/null 2>&1
    check "writes .$ext" test -s "$tmp/f.$ext"
done
check "pfm header" bash -c "head -c 2 '$tmp/f.pfm' | grep -q PF"

# OpenEXR: float RGB equal to the PFM's (read back by imgdiff through OpenEXR), half RGB within
# half's rounding, the AOV channels named in the header (stored uncompressed; the values are
# checked by rt_tests' Aov tests), also in progressive mode and sequences; usage errors exit 2.
imgdiff="$(dirname "$rt")/imgdiff"
check "imgdiff is built beside raytrace" test -x "$imgdiff"
"$rt" "$tmp/ok.ray" -q -o "$tmp/e.pfm" --width 32 --height 24 --spp 2
"$rt" "$tmp/ok.ray" -q -o "$tmp/e.exr" --width 32 --height 24 --spp 2 --exr-float \
    --aov albedo,normal,depth,samples,variance
check "exr with every aov exits 0" test $? -eq 0
check "float exr RGB is the pfm's" "$imgdiff" "$tmp/e.pfm" "$tmp/e.exr" --max-abs 0
for ch in R G B Albedo.R Albedo.G Albedo.B Ns.X Ns.Y Ns.Z depth.Z Samples.N Variance.R \
    Variance.G Variance.B; do
    check "exr has channel $ch" grep -qaF "$ch" "$tmp/e.exr"
done
check "no aov channel in a plain exr" bash -c "'$rt' '$tmp/ok.ray' -q -o '$tmp/h.exr' --width 32 --height 24 --spp 2 && ! grep -qaF Albedo '$tmp/h.exr'"
check "half exr RGB is the pfm's within half's rounding" "$imgdiff" "$tmp/e.pfm" "$tmp/h.exr" --max-abs 0.002
check "half exr RGB is rounded" bash -c "! '$imgdiff' '$tmp/e.pfm' '$tmp/h.exr' --max-abs 0 >/dev/null"
# The share of pixels off by more than K/255: none between an image and itself; another
# background is off, and --max-off-share then fails.
check "an image is off nowhere against itself" bash -c "'$imgdiff' '$tmp/e.pfm' '$tmp/e.pfm' --max-off-share 0 | grep -q 'off by more than 32/255: 0.0000 (0 pixels)'"
{ printf '#background 0.5 0.5 0.5\n'; cat "$tmp/ok.ray"; } >"$tmp/grey.ray"
"$rt" "$tmp/grey.ray" -q -o "$tmp/grey.png" --width 32 --height 24 --spp 2
"$rt" "$tmp/ok.ray" -q -o "$tmp/plain.png" --width 32 --height 24 --spp 2
check "another background is off by more than 32/255" bash -c "! '$imgdiff' '$tmp/grey.png' '$tmp/plain.png' --max-off-share 0 >/dev/null"
"$rt" "$tmp/ok.ray" -q --progressive --spp 4 -o "$tmp/pe.exr" --width 32 --height 24 --aov samples,depth
check "progressive exr with aovs" grep -qaF Samples.N "$tmp/pe.exr"
"$rt" "$tmp/ok.ray" -q --frames 2 -o "$tmp/fe_%d.exr" --width 16 --height 12 --aov normal 2>/dev/null
check "every frame of a sequence has the aovs" bash -c "grep -qaF Ns.X '$tmp/fe_0.exr' && grep -qaF Ns.X '$tmp/fe_1.exr'"
"$rt" "$tmp/ok.ray" -o "$tmp/a.png" --aov depth >/dev/null 2>"$tmp/aov.txt"
check "--aov without .exr exits 2" test $? -eq 2
check "--aov without .exr message" grep -q "need an OpenEXR output (-o FILE.exr)" "$tmp/aov.txt"
check "--aov without .exr writes nothing" test ! -e "$tmp/a.png"
"$rt" "$tmp/ok.ray" -o "$tmp/b.exr" --aov depth,shadow >/dev/null 2>"$tmp/aov2.txt"
check "unknown aov exits 2" test $? -eq 2
check "unknown aov names the accepted ones" grep -q "unknown AOV 'shadow' (accepted: albedo, normal, depth, samples, variance" "$tmp/aov2.txt"
"$rt" "$tmp/ok.ray" -o "$tmp/c.part" --aov depth >/dev/null 2>&1
check "--aov with a .part exits 2" test $? -eq 2
"$rt" "$tmp/ok.ray" -o "$tmp/nodir/x.exr" --aov depth >/dev/null 2>&1
check "exr in a missing directory exits 1" test $? -eq 1

"$rt" "$tmp/ok.ray" -q -o "$tmp/t1.ppm" --threads 1 --spp 4 --width 50 --height 40
"$rt" "$tmp/ok.ray" -q -o "$tmp/t3.ppm" --threads 3 --spp 4 --width 50 --height 40
check "same image for any thread count" cmp -s "$tmp/t1.ppm" "$tmp/t3.ppm"

"$rt" "$tmp/ok.ray" -q -o "$tmp/ns.ppm" --no-shadows --depth 1 --cutoff 0.5 --width 20 --height 10
check "no-shadows depth cutoff accepted" test -s "$tmp/ns.ppm"

# Progressive mode: a report with the required columns, an SVG plot, the image.
"$rt" "$tmp/ok.ray" --progressive --spp 8 --light-radius 0.3 --report "$tmp/r.csv" \
    --plot "$tmp/r.svg" -o "$tmp/prog.png" --width 32 --height 24 >"$tmp/prog.txt" 2>&1
check "progressive exits 0" test $? -eq 0
check "report header" bash -c "head -1 '$tmp/r.csv' | grep -q 'seconds,spp,rays,rmse,relmse,off_share,estimate'"
check "report has passes" test "$(wc -l <"$tmp/r.csv")" -ge 4
check "plot is svg" grep -q "<svg" "$tmp/r.svg"
check "progressive image" test -s "$tmp/prog.png"
check "formula printed" grep -q "relMSE = mean over pixels" "$tmp/prog.txt"
"$rt" "$tmp/ok.ray" -o "$tmp/ref.pfm" --spp 16 --width 32 --height 24 -q
"$rt" "$tmp/ok.ray" --progressive --spp 4 --reference "$tmp/ref.pfm" --report "$tmp/r2.csv" \
    -o "$tmp/p2.png" --width 32 --height 24 -q
check "report with reference has errors" bash -c "tail -1 '$tmp/r2.csv' | grep -qE '^uniform,[^,]+,[^,]+,[^,]+,[0-9]'"
"$rt" "$tmp/ok.ray" --progressive --spp 4 --reference "$tmp/ref.pfm" -o "$tmp/p3.png" >/dev/null 2>&1
check "reference of another size exits 1" test $? -eq 1
"$rt" "$tmp/ok.ray" --progressive --target-error 1e-3 --light-radius 0.3 --report "$tmp/t.csv" \
    -o "$tmp/target.png" --width 32 --height 24 >"$tmp/target.txt" 2>&1
check "--target-error exits 0" test $? -eq 0
check "--target-error says when it was reached" grep -q "uniform: reached the target error 0.001 at" "$tmp/target.txt"
check "--target-error's last pass reaches it" awk -F, 'END { exit !($9 <= 1e-3 && $3 >= 8) }' "$tmp/t.csv"
"$rt" "$tmp/ok.ray" --time 2 >/dev/null 2>&1
check "--time without --progressive exits 2" test $? -eq 2
"$rt" "$tmp/ok.ray" --progressive >/dev/null 2>&1
check "--progressive without a limit exits 2" test $? -eq 2
"$rt" "$tmp/ok.ray" --aperture -1 >/dev/null 2>&1
check "negative aperture exits 2" test $? -eq 2

# Leave out what a scene does not need: --explain lists it, --no-specialize renders the same image.
"$rt" "$tmp/ok.ray" -o "$tmp/spec.pfm" --width 32 --height 24 --explain >"$tmp/explain.txt" 2>&1
check "--explain exits 0" test $? -eq 0
check "--explain: refraction left out" grep -qx "left out: refraction: no transparent material" "$tmp/explain.txt"
check "--explain: highlights kept" grep -q "^kept: specular highlights" "$tmp/explain.txt"
check "--explain: lines have the form" bash -c "! grep -E '^(left out|kept)' '$tmp/explain.txt' | grep -vqE '^(left out|kept): [^:]+: .+'"
"$rt" "$tmp/ok.ray" -o "$tmp/generic.pfm" --width 32 --height 24 --no-specialize -q
check "--no-specialize: same image" cmp -s "$tmp/spec.pfm" "$tmp/generic.pfm"

# The ray tree of a pixel: the text, the JSON, its colour the PFM's value there, usage errors.
(cd "$tmp" && "$rt" ok.ray --width 32 --height 24 --inspect 16,12 --inspect-json tree.json) \
    >"$tmp/tree.txt" 2>&1
check "--inspect exits 0" test $? -eq 0
check "--inspect: the camera ray" grep -q "^camera ray, depth 5: from (0 0 5)" "$tmp/tree.txt"
check "--inspect: the hit, named by its directive" grep -q "hits sphere 0 of instance 0 at ok.ray:4:1" "$tmp/tree.txt"
check "--inspect: the diffuse term" grep -qE "^  +diffuse  = I_l \(.*\) x K_D \(0.8 0.2 0.2\) x N.L [0-9.]+ = " "$tmp/tree.txt"
check "--inspect: the pixel's value" grep -q "^pixel value (" "$tmp/tree.txt"
check "--inspect writes no image" test ! -e "$tmp/out.png"
check "--inspect-json: the top level" grep -q '^{"pixel":\[16,12\],"sample":0,' "$tmp/tree.json"
if command -v python3 >/dev/null; then
    # The JSON's colour is the PFM's pixel (a float: to 1e-6 relative).
    python3 - "$tmp/tree.json" "$tmp/spec.pfm" >"$tmp/json_check.txt" 2>&1 <<'PY'
import json, struct, sys
tree = json.load(open(sys.argv[1]))
data = open(sys.argv[2], "rb").read()
parts = data.split(b"\n", 3)
w, h = map(int, parts[1].split())
scale = float(parts[2])
fmt = "<" if scale < 0 else ">"
x, y = tree["pixel"]
row = h - 1 - y  # PFM rows go from the bottom
off = (row * w + x) * 12
pix = struct.unpack(fmt + "3f", parts[3][off:off + 12])
assert tree["rays"][0]["kind"] == "camera", tree["rays"][0]["kind"]
assert tree["rays"][0]["hit"]["primitive"]["location"].endswith("ok.ray:4:1")
assert all(abs(a - b) <= 1e-6 * max(1.0, abs(b)) for a, b in zip(tree["color"], pix)), (tree["color"], pix)
print("ok")
PY
    check "--inspect-json: colour = the PFM's pixel" grep -qx ok "$tmp/json_check.txt"
fi
"$rt" "$tmp/ok.ray" --width 32 --height 24 --inspect 32,0 >/dev/null 2>"$tmp/usage.txt"
check "--inspect outside the image exits 2" test $? -eq 2
check "and says the range" grep -q "outside the 32x24 image (X in 0..31, Y in 0..23)" "$tmp/usage.txt"
"$rt" "$tmp/ok.ray" --spp 4 --inspect 1,1 --inspect-sample 4 >/dev/null 2>"$tmp/usage.txt"
check "--inspect-sample beyond --spp exits 2" test $? -eq 2
check "and says the range" grep -q "not one of the pixel's --spp 4 samples (0..3)" "$tmp/usage.txt"
"$rt" "$tmp/ok.ray" --inspect 1,x >/dev/null 2>&1
check "--inspect X,Y malformed exits 2" test $? -eq 2
"$rt" "$tmp/ok.ray" --inspect 1,1 -o "$tmp/i.png" >/dev/null 2>&1
check "--inspect with -o exits 2" test $? -eq 2

echo "$passes passed, $fails failed"
test "$fails" -eq 0

# Bad input never crashes: exit 1 with file:line:col, no output, for deep nesting,
# binary garbage, a self-include and numbers out of range.
for i in $(seq 1 20000); do echo "#group_begin 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"; done >"$tmp/deep.ray"
"$rt" "$tmp/deep.ray" -o "$tmp/deep.png" >"$tmp/deep.txt" 2>&1
check "deep nesting exits 1" test $? -eq 1
check "deep nesting message" grep -q "deep.ray:10001:1: error: #group_begin nests groups deeper than 10000 levels" "$tmp/deep.txt"
check "no output on deep nesting" test ! -e "$tmp/deep.png"
head -c 65536 /dev/urandom >"$tmp/junk.ray"
printf '\0\0\0' >>"$tmp/junk.ray"
"$rt" "$tmp/junk.ray" -o "$tmp/junk.png" >"$tmp/junk.txt" 2>&1
check "binary garbage exits 1" test $? -eq 1
check "binary garbage message" grep -q "junk.ray:[0-9]*:[0-9]*: error: " "$tmp/junk.txt"
printf '#ray_file self.ray\n' >"$tmp/self.ray"
"$rt" "$tmp/self.ray" -o "$tmp/self.png" >"$tmp/self.txt" 2>&1
check "self-include exits 1" test $? -eq 1
check "self-include message" grep -q "self.ray:1:11: error: include cycle: self.ray -> self.ray" "$tmp/self.txt"
printf '#ambient 0 1e400 0\n#vertex_num 1000000000000\n' >"$tmp/num.ray"
"$rt" "$tmp/num.ray" -o "$tmp/num.png" >"$tmp/num.txt" 2>&1
check "huge number exits 1" test $? -eq 1
check "huge number message" grep -q "num.ray:1:12: error: non-finite number '1e400'" "$tmp/num.txt"

# Every public V3 file, opened on its own as a user would, with checker stand-ins for the
# textures that were never published: exit 0 and an image (spec §13; tests/test_scenes.cpp checks
# the pixels).
pub="$src/../shared/public-scenes"
if [ -d "$pub" ]; then
    n=0
    for f in "$pub"/henry-md__ray-tracer/*.ray "$pub"/aarxa__RayForge-CPP-Ray-Tracing-Engine/*.ray \
        "$pub"/dcalvo__Graphics-2021/*.ray; do
        "$rt" "$f" --missing-textures checker -q --width 32 --height 24 -o "$tmp/v3.ppm" \
            >"$tmp/v3.txt" 2>&1
        check "V3 $(basename "$f") exits 0" test $? -eq 0
        check "V3 $(basename "$f") writes an image" test -s "$tmp/v3.ppm"
        rm -f "$tmp/v3.ppm"
        n=$((n + 1))
    done
    check "41 public V3 files" test "$n" -eq 41
    "$rt" "$pub/dcalvo__Graphics-2021/scene.ray" -q -o "$tmp/chess.png" >"$tmp/chess.txt" 2>&1
    check "missing texture exits 1" test $? -eq 1
    check "missing texture names the places tried" grep -q "error: cannot open texture 'board.jpg' (tried " "$tmp/chess.txt"
    check "missing texture: no output" test ! -e "$tmp/chess.png"
fi

# Only regular files are read: a FIFO (no writer: it would block forever; the timeout turns a
# hang into a failed check, it measures nothing), a directory or a device as the scene, an
# included file, a key file, a texture or --reference is an error that says what it is.
mkdir "$tmp/fifo"
mkfifo "$tmp/fifo/scene.ray" "$tmp/fifo/part.ray" "$tmp/fifo/k.key" "$tmp/fifo/t.bmp" "$tmp/fifo/ref.pfm"
printf '#ray_file part.ray\n' >"$tmp/fifo/include.ray"
printf '#key_file k.key\n#shape_sphere -1 0 0 0 1\n' >"$tmp/fifo/key.ray"
printf '#texture t.bmp\n#shape_sphere -1 0 0 0 1\n' >"$tmp/fifo/texture.ray"
not_regular() {  # not_regular NAME MESSAGE ARGS...: exit 1, MESSAGE, no image
    local name=$1 message=$2
    shift 2
    timeout 60 "$rt" "$@" --width 8 --height 6 -q -o "$tmp/fifo/out.png" >"$tmp/fifo/err.txt" 2>&1
    check "$name exits 1" test $? -eq 1
    check "$name: the message says so" grep -qF -- "$message" "$tmp/fifo/err.txt"
    check "$name: no image" test ! -e "$tmp/fifo/out.png"
}
not_regular "a FIFO scene" "cannot open scene file '$tmp/fifo/scene.ray': '$tmp/fifo/scene.ray' is a FIFO, not a regular file" "$tmp/fifo/scene.ray"
not_regular "a directory scene" "'$tmp/fifo' is a directory, not a regular file" "$tmp/fifo"
not_regular "a device scene" "'/dev/zero' is a character device, not a regular file" /dev/zero
not_regular "a FIFO included" "include.ray:1:11: error: cannot read ray file '$tmp/fifo/part.ray': '$tmp/fifo/part.ray' is a FIFO, not a regular file" "$tmp/fifo/include.ray"
not_regular "a FIFO key file" "key.ray:1:11: error: cannot read key file '$tmp/fifo/k.key': '$tmp/fifo/k.key' is a FIFO, not a regular file" "$tmp/fifo/key.ray"
not_regular "a FIFO texture" "texture.ray:1:10: error: cannot decode texture '$tmp/fifo/t.bmp': '$tmp/fifo/t.bmp' is a FIFO, not a regular file" "$tmp/fifo/texture.ray"
not_regular "a FIFO --reference" "--reference: '$tmp/fifo/ref.pfm' is a FIFO, not a regular file" "$tmp/ok.ray" --progressive --spp 2 --reference "$tmp/fifo/ref.pfm"

# Out of memory: said so, exit 1, no output.
check_out_of_memory "out of memory" "raytrace: error: out of memory while rendering $tmp/ok.ray" \
    "$rt" "$tmp/ok.ray" --width 20000 --height 20000 --max-pixels 400000000 -q -o "$tmp/oom.png"
check "out of memory: no output" test ! -e "$tmp/oom.png"

# The tree's limits (docs/inspect.md): glass in a mirror box doubles the rays at each glass hit;
# at --depth 256 one pixel traces 7,195 rays. The tree records 4,096 of them and says so; the JSON
# is flat and strict; its text is indented no deeper than 64 spaces plus a ray's own lines.
cat >"$tmp/explode.ray" <<'RAY'
#camera 0 0 0  0.3 0.1 -1  0 1 0  0.5
#light_point 1 1 1  0 0.9 0  1 0 0
#material 0 0 0  0 0 0  0 0 0  1 1 1  10  0 0 0  1  -1 !mirror!
#material 0 0 0  0 0 0  0 0 0  0.5 0.5 0.5  10  0.5 0.5 0.5  1.5  -1 !glass!
#shape_box 0  0 0 0  4 2 6
#shape_sphere 1  0.8 0 -1.5  0.5
#shape_sphere 1  -1 0.3 1.5  0.6
RAY
"$rt" "$tmp/explode.ray" --width 8 --height 8 --depth 256 --inspect 4,4 \
    --inspect-json "$tmp/explode.json" >"$tmp/explode.txt" 2>&1
check "--inspect of an exploding tree exits 0" test $? -eq 0
check "and says how many rays it left out" grep -qE "^[0-9]+ more rays traced but not recorded: a tree records at most 4096 rays" "$tmp/explode.txt"
check "its text is indented 72 spaces at most" bash -c "! grep -qE '^ {73}' '$tmp/explode.txt'"
check "its JSON is under 16 MB" test "$(stat -c %s "$tmp/explode.json")" -lt 16000000
if command -v python3 >/dev/null; then
    python3 - "$tmp/explode.json" >"$tmp/explode_check.txt" 2>&1 <<'PY'
import json, sys
tree = json.load(open(sys.argv[1], encoding="utf-8"))
assert tree["rays_recorded"] == len(tree["rays"]) == 4096, tree["rays_recorded"]
assert tree["rays_not_recorded"] > 1000, tree["rays_not_recorded"]
assert all(r["index"] == i for i, r in enumerate(tree["rays"]))
assert all(tree["rays"][c]["parent"] == r["index"] for r in tree["rays"] for c in r["children"])
print("ok")
PY
    check "its JSON is flat: parents and children by index" grep -qx ok "$tmp/explode_check.txt"
fi

# Nothing is written when the run fails: the tree cannot be printed (a full disk), so no JSON
# file, and no scratch file either.
mkdir "$tmp/full"
"$rt" "$tmp/ok.ray" --width 8 --height 8 --inspect 4,4 --inspect-json "$tmp/full/t.json" \
    >/dev/full 2>"$tmp/full.txt"
check "--inspect to a full disk exits 1" test $? -eq 1
check "and says so" grep -q "^raytrace: error: cannot write the tree to the standard output" "$tmp/full.txt"
check "and writes no JSON, nor a scratch file" test -z "$(ls -A "$tmp/full")"

# A reader that stops early (head) ends raytrace by SIGPIPE while the text is printed: the text
# comes first, so no JSON file has been started, and no scratch file is left.
mkdir "$tmp/pipe"
"$rt" "$tmp/explode.ray" --width 8 --height 8 --depth 256 --inspect 4,4 \
    --inspect-json "$tmp/pipe/t.json" 2>/dev/null | head -1 >/dev/null
check "--inspect | head leaves no JSON, nor a scratch file" test -z "$(ls -A "$tmp/pipe")"

# Names from the scene: control characters are escaped in the text (they would move the
# terminal's cursor) and the JSON is strict UTF-8 whatever the bytes.
printf '#camera 0 0 5  0 0 -1  0 1 0  0.5\n#light_point 1 1 1  2 2 2  1 0 0\n#material 0 0 0  .1 .1 .1  .8 .2 .2  .5 .5 .5  20  0 0 0  1  -1 !red\033[2J\377!\n#shape_sphere 0  0 0 0  1\n' >"$tmp/names.ray"
"$rt" "$tmp/names.ray" --width 9 --height 9 --inspect 4,4 --inspect-json "$tmp/names.json" \
    >"$tmp/names.txt" 2>&1
check "--inspect of a scene with control characters in names exits 0" test $? -eq 0
check "the text shows them escaped" grep -qF "!'red\\x1b[2J\\xff'!" "$tmp/names.txt"
check "and holds no escape byte" bash -c "! grep -q $'\033' '$tmp/names.txt'"
if command -v python3 >/dev/null; then
    python3 -c 'import json, sys; t = json.load(open(sys.argv[1], encoding="utf-8")); print(t["rays"][0]["hit"]["material"]["name"] == "red\x1b[2J\ufffd")' \
        "$tmp/names.json" >"$tmp/names_check.txt" 2>&1
    check "the JSON is strict UTF-8, the name escaped" grep -qx True "$tmp/names_check.txt"
fi

# --inspect's X,Y may have spaces around it; --inspect-json needs a name.
"$rt" "$tmp/ok.ray" --width 8 --height 8 --inspect '1,2 ' >"$tmp/space.txt" 2>&1
check "--inspect '1,2 ' exits 0" test $? -eq 0
check "and inspects pixel 1,2" grep -q "^pixel 1,2, sample 0" "$tmp/space.txt"
"$rt" "$tmp/ok.ray" --width 8 --height 8 --inspect '1,2x' >/dev/null 2>"$tmp/usage.txt"
check "--inspect '1,2x' exits 2" test $? -eq 2
check "and says why" grep -q "'1,2x' is not X,Y" "$tmp/usage.txt"
(cd "$tmp" && "$rt" ok.ray --width 8 --height 8 --inspect 1,2 --inspect-json "") \
    >/dev/null 2>"$tmp/usage.txt"
check "--inspect-json '' exits 2" test $? -eq 2
check "and says it needs a file name" grep -q "inspect-json.*needs a file name" "$tmp/usage.txt"

# What a student compares (docs/inspect.md): spec §7.6's worked example seen from its eye, the
# centre pixel of 41x41 being its ray. The 8 bits written (145 145 236), the camera's inputs,
# the shadow ray's origin offset; a light below the plane says why it traced no shadow ray; the
# filters --inspect-depth and --inspect-light, and their usage errors.
cat >"$tmp/worked.ray" <<'RAY'
#camera 0 10 10  3 -10 -4  0 1 0  0.5
#ambient 0.5 0.5 0.5
#background 0.2 0.2 0.2
#light_point 1 1 1  5 5 5  0.01 0.02 0.03
#light_point 1 1 1  5 -5 5  0.01 0.02 0.03
#material 0 0 0  .3 .3 .3  .1 .1 .5  1 1 1  100  0 0 0  1  -1 !!
#vertex -100 0 -100 0 0 0 0 0
#vertex -100 0 100 0 0 0 0 0
#vertex 100 0 100 0 0 0 0 0
#vertex 100 0 -100 0 0 0 0 0
#shape_triangle 0 0 1 2
#shape_triangle 0 0 2 3
RAY
"$rt" "$tmp/worked.ray" --width 41 --height 41 --cutoff 0.001 --inspect 20,20 \
    --inspect-json "$tmp/worked.json" >"$tmp/worked.txt" 2>&1
check "--inspect of §7.6 exits 0" test $? -eq 0
check "--inspect: the bytes written, (145 145 236)" \
    grep -q "^written as 8 bits (145 145 236) = floor(255 x clamp(c, 0, 1) + 0.5)" "$tmp/worked.txt"
check "--inspect: the camera's angle and tangents" \
    grep -q "^camera (the scene's): ha 28.6479 deg (the half-height angle), tan_h = tan(ha) 0.546302, tan_w = tan_h x 41/41 0.546302" "$tmp/worked.txt"
check "--inspect: the basis" grep -qE "^  at \(0 10 10\), f \(0.268328 -0.894427 -0.357771\), r \(0.8 -?0 0.6\), up' \(0.536656 0.447214 -0.715542\)" "$tmp/worked.txt"
check "--inspect: the image-plane point of the centre" grep -qE "^  sample offset \(sx sy\) \(0.5 0.5\): x = .* = 0, y = .* = 0;" "$tmp/worked.txt"
check "--inspect: the shadow ray's origin offset" grep -q "origin offset 0 (the hit point's error bound is 0 there" "$tmp/worked.txt"
check "--inspect: §7.6's diffuse term" grep -q "x N.L 0.912871 = (0.0895371 0.0895371 0.447686)" "$tmp/worked.txt"
check "--inspect: the light below says why no shadow ray" \
    grep -q "^    no shadow ray: the surface faces away from the light (N.L <= 0)" "$tmp/worked.txt"
if command -v python3 >/dev/null; then
    python3 -c 'import json, sys; t = json.load(open(sys.argv[1])); c = t["camera"]; l = t["rays"][0]["terms"]["lights"]
print(t["output"]["bytes"] == [145, 145, 236] and abs(c["tan_h"] - 0.546302489843790) < 1e-12 and c["image_point"] == [0, 0] and l[0]["no_shadow_ray"] is None and "faces away" in l[1]["no_shadow_ray"])' \
        "$tmp/worked.json" >"$tmp/worked_check.txt" 2>&1
    check "--inspect-json: output, camera, no_shadow_ray" grep -qx True "$tmp/worked_check.txt"
fi
"$rt" "$tmp/worked.ray" -q --width 41 --height 41 --inspect 20,20 --inspect-depth 1 \
    --inspect-light 0 >"$tmp/filtered.txt" 2>&1
check "--inspect-depth 1 --inspect-light 0 exits 0" test $? -eq 0
check "--inspect-depth 1 leaves the reflected ray out" grep -q "left out (--inspect-depth 1): reflected ray, depth 4" "$tmp/filtered.txt"
check "and counts it" grep -q "^1 ray deeper than level 1 left out" "$tmp/filtered.txt"
check "and shows no reflected ray's line" bash -c "! grep -q '^    reflected ray, depth 4' '$tmp/filtered.txt'"
check "--inspect-light 0 shows light 0 only" bash -c "! grep -q '^  light 1 ' '$tmp/filtered.txt' && grep -q '^  light 0 ' '$tmp/filtered.txt'"
check "and says one light term was left out" grep -q "1 other light term left out (--inspect-light 0" "$tmp/filtered.txt"
"$rt" "$tmp/worked.ray" --inspect 1,1 --inspect-light 2 >/dev/null 2>"$tmp/usage.txt"
check "--inspect-light past the lights exits 2" test $? -eq 2
check "and gives the range" grep -q "inspect-light 2: the scene's lights are 0..1" "$tmp/usage.txt"
"$rt" "$tmp/worked.ray" --inspect 1,1 --inspect-depth 0 >/dev/null 2>"$tmp/usage.txt"
check "--inspect-depth 0 exits 2" test $? -eq 2
check "and says levels count from 1" grep -q "counts levels of rays from 1" "$tmp/usage.txt"
"$rt" "$tmp/worked.ray" --inspect-depth 2 >/dev/null 2>"$tmp/usage.txt"
check "--inspect-depth without --inspect exits 2" test $? -eq 2

# --mistake (teaching only, docs/mistakes.md): the catalogue, a mistaken render, bad names.
"$rt" --mistake list >"$tmp/mistakes.txt" 2>&1
check "--mistake list exits 0" test $? -eq 0
check "and lists the catalogue" test "$(grep -c '^  [a-z-]* *\(camera\|shading\|output\) ' "$tmp/mistakes.txt")" -ge 20
check "no-shadows among them" grep -q "^  no-shadows .*shading.*§7.2" "$tmp/mistakes.txt"
"$rt" --help | grep -q -- "--mistake NAME" && "$rt" --help | grep -q "teaching only"
check "--help documents --mistake as teaching only" test $? -eq 0
"$rt" "$tmp/ok.ray" --width 20 --height 16 -o "$tmp/right.ppm" >/dev/null 2>&1
"$rt" "$tmp/ok.ray" --width 20 --height 16 --mistake flip-vertical -o "$tmp/flip.ppm" \
    >"$tmp/flip.txt" 2>&1
check "--mistake flip-vertical exits 0" test $? -eq 0
check "and says the image is wrong on purpose" grep -q "^mistakes  flip-vertical (teaching only" "$tmp/flip.txt"
check "the image differs from the right one" sh -c "! cmp -s '$tmp/right.ppm' '$tmp/flip.ppm'"
if command -v python3 >/dev/null; then
    python3 -c '
import sys
def rows(p):
    d = open(p, "rb").read()
    head = d.split(b"\n", 3)
    w, h = map(int, head[1].split())
    px = head[3]
    return [px[y * w * 3:(y + 1) * w * 3] for y in range(h)]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
print(b == a[::-1] and a != b)' "$tmp/right.ppm" "$tmp/flip.ppm" >"$tmp/flip_check.txt" 2>&1
    check "row j of it is row H-1-j of the right one" grep -qx True "$tmp/flip_check.txt"
fi
"$rt" "$tmp/ok.ray" --width 20 --height 16 --mistake no-shadows,gamma -q -o "$tmp/two.png"
check "two mistakes, comma-separated, exit 0" test $? -eq 0
"$rt" "$tmp/ok.ray" --width 20 --height 16 --mistake nope -o "$tmp/nope.png" >/dev/null \
    2>"$tmp/usage.txt"
check "an unknown mistake exits 2" test $? -eq 2
check "and names it and the list" grep -q "unknown mistake 'nope' (the catalogue: raytrace --mistake list)" "$tmp/usage.txt"
check "and writes no image" test ! -e "$tmp/nope.png"
"$rt" "$tmp/ok.ray" --mistake gamma --mistake bgr --mistake no-shadows -o "$tmp/three.png" \
    >/dev/null 2>"$tmp/usage.txt"
check "three mistakes exit 2" test $? -eq 2
check "and say at most two" grep -q "at most two mistakes at once" "$tmp/usage.txt"
"$rt" "$tmp/ok.ray" --mistake gamma --progressive --spp 2 -o "$tmp/p.png" >/dev/null \
    2>"$tmp/usage.txt"
check "--mistake with --progressive exits 2" test $? -eq 2

summary "with the bad-input checks"
