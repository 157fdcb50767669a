#!/usr/bin/env bash
# raycompare end to end: an image equal to the reference passes with 0 difference; shifted by one
# pixel it fails, and passes with --neighbourhood; a wrong specular exponent fails and its largest
# difference is on a highlight; the HTML report's images exist and its table matches the CSV;
# unreadable and non-image files fail naming the file, an empty list is a usage error; images of
# two sizes get a reference each; PFM is compared linear. The report's folder: never one of other
# files, never replacing an input, no stale file of an earlier report; the outputs probed before
# rendering; names escaped; a class with a bad file and an out-of-memory reference.
# usage: test_raycompare.sh BUILD_APP_DIR SOURCE_DIR
set -u
bin=$(realpath "$1")
src=$(realpath "$2")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/check.sh"
cd "$tmp" || exit 1
rt="$bin/raytrace"
rc="$bin/raycompare"

cat >scene.ray <<'RAY'
#camera 0 0 5  0 0 -1  0 1 0  0.5
#background 0.1 0.1 0.2
#ambient 0.2 0.2 0.2
#light_point 1 1 1  2 3 4  1 0 0
#material 0 0 0  .1 .1 .1  .7 .2 .2  .8 .8 .8  40  0 0 0  1  -1 !red!
#shape_sphere 0  0 0 0  1
RAY
sed 's/  40  /  4  /' scene.ray >wrong.ray  # the student's exponent

"$rt" scene.ray --width 64 --height 48 -q -o same.png
"$rt" scene.ray --width 64 --height 48 -q -o same.ppm
"$rt" scene.ray --width 64 --height 48 -q -o same.pfm
"$rt" wrong.ray --width 64 --height 48 -q -o wrong.ppm
"$rt" scene.ray --width 40 --height 30 -q -o small.png

"$rc" scene.ray same.png >out.txt 2>&1
check "an equal image passes" test $? -eq 0
check "with 0 difference" grep -qE "^same +64x48 +0\.000 +0\.000% +0\.0 .*PASS$" out.txt
"$rc" scene.ray same.pfm >out.txt 2>&1
check "a PFM, compared linear, passes" test $? -eq 0
check "also with 0 difference" grep -qE "^same +64x48 +0\.000 .*PASS$" out.txt

# The image shifted right by one pixel (the first column repeated).
python3 - same.ppm shifted.ppm <<'PY'
import sys
data = open(sys.argv[1], 'rb').read()
parts = data.split(b'\n', 3)
w, h = map(int, parts[1].split())
px = parts[3]
rows = [px[y * w * 3:(y + 1) * w * 3] for y in range(h)]
out = b''.join(r[:3] + r[:-3] for r in rows)
open(sys.argv[2], 'wb').write(b'\n'.join(parts[:3]) + b'\n' + out)
PY
"$rc" scene.ray shifted.ppm >out.txt 2>&1
check "shifted by a pixel it fails" test $? -eq 1
check "said FAIL" grep -qE "^shifted .*FAIL$" out.txt
"$rc" scene.ray shifted.ppm --neighbourhood >out.txt 2>&1
check "and passes with --neighbourhood" test $? -eq 0

# A wrong specular exponent: fails, and the largest difference is on the highlight.
"$rc" scene.ray wrong.ppm same.png small.png --size any --csv table.csv --html report >out.txt 2>&1
check "a wrong exponent fails (the run exits 1)" test $? -eq 1
check "its row says FAIL" grep -qE "^wrong .*FAIL$" out.txt
check "two sizes, two references" test "$(grep -c 'rendered the .* reference' out.txt)" -eq 2
python3 - table.csv same.ppm wrong.ppm >hl.txt 2>&1 <<'PY'
import csv, math, sys
rows = {r['file']: r for r in csv.DictReader(open(sys.argv[1]))}
r = rows['wrong.ppm']
x, y = int(r['max_x']), int(r['max_y'])
def load(p):
    parts = open(p, 'rb').read().split(b'\n', 3)
    w, h = map(int, parts[1].split())
    px = parts[3]
    lum = [0.2126 * px[3 * i] + 0.7152 * px[3 * i + 1] + 0.0722 * px[3 * i + 2] for i in range(w * h)]
    return w, lum
w, ref = load(sys.argv[2])
_, wrong = load(sys.argv[3])
peak = max(range(len(ref)), key=lambda i: ref[i])
# Beside the reference's highlight, where the wrong exponent's broader one is bright.
near = math.hypot(x - peak % w, y - peak // w) <= 4
print('ok' if near and wrong[y * w + x] >= 0.6 * max(wrong) and float(r['max_diff']) > 50
      else f'no: at {x},{y}, the highlight at {peak % w},{peak // w}, {r}')
PY
check "its largest difference is on the highlight" grep -qx ok hl.txt

# The report: the page, its images, its rows those of the CSV.
check "report: index.html" test -s report/index.html
for f in reference_64x48.png reference_40x30.png image_1.png heat_1.png image_2.png heat_2.png scale.png; do
    check "report: $f" test -s "report/$f"
done
check "report: three rows, as the CSV" test "$(grep -c '^<tr class=' report/index.html)" -eq "$(($(wc -l <table.csv) - 1))"
check "report: no external link" bash -c "! grep -qE '(src|href)=\"(https?:)?//' report/index.html"
check "report: the failing row says FAIL" grep -q '"wrong.ppm">wrong</td>.*FAIL' report/index.html

# Bad input: named, and the run fails; nothing half-written.
echo "not an image" >notes.txt
"$rc" scene.ray same.png notes.txt missing.png >out.txt 2>&1
check "a non-image and a missing file fail the run" test $? -eq 1
check "the non-image is named" grep -qE "^notes .*FAIL: .*notes.txt" out.txt
check "the missing file is named" grep -qE "^missing .*FAIL: .*missing.png" out.txt
check "the good image still passes" grep -qE "^same .*PASS$" out.txt
"$rc" scene.ray >out.txt 2>&1
check "no image is a usage error" test $? -eq 2
printf '#shape_sphere 0 0 0 0 1 x\n' >bad.ray
"$rc" bad.ray same.png >out.txt 2>&1
check "a scene error exits 1" test $? -eq 1
check "with file:line:col" grep -qE "^bad.ray:1:[0-9]+: error: " out.txt
"$rc" scene.ray same.png --max-bad 2 >out.txt 2>&1
check "--max-bad beyond 1 is a usage error" test $? -eq 2


# The report's folder never takes a student's file. The issue's case: --html . in the folder of
# the images, named image_1.png and image_2.png as the report's own: refused before anything is
# rendered, the folder as it was (given in this order, the inputs were swapped on disk).
mkdir class && cp scene.ray class/ && cp same.png class/image_1.png && cp small.png class/image_2.png
(cd class && ls -A >../listing.before && sha256sum image_1.png image_2.png scene.ray >../sums)
(cd class && "$rc" scene.ray image_2.png image_1.png --html . >../out.txt 2>&1)
check "--html . among the images: refused (exit 2)" test $? -eq 2
check "saying why" grep -qF "raycompare: error: --html '.': the folder is not empty and holds no report of raycompare" out.txt
check "before rendering" bash -c "! grep -q 'rendered the' out.txt"
check "the images are as they were" bash -c "cd class && sha256sum --quiet -c ../sums"
check "and nothing was added" bash -c "cd class && ls -A | cmp -s - ../listing.before"
# A folder of someone else's files (a scale.png of their own): refused, untouched.
mkdir theirs && echo "their scale" >theirs/scale.png && echo "notes" >theirs/notes.txt
"$rc" scene.ray same.png --html theirs >out.txt 2>&1
check "a folder of other files: refused (exit 2)" test $? -eq 2
check "their file kept" test "$(cat theirs/scale.png)" = "their scale"
check "nothing added" test "$(ls -A theirs | tr '\n' ' ')" = "notes.txt scale.png "
# --html naming a file: refused before rendering, the file kept.
"$rc" scene.ray same.png --html notes.txt >out.txt 2>&1
check "--html FILE: refused" test $? -eq 2
check "--html FILE: the file kept" test "$(cat notes.txt)" = "not an image"
check "--html FILE: before rendering" bash -c "! grep -q 'rendered the' out.txt"

# Our own folder again, with fewer images: the earlier report's files go, no stale row stays.
"$rc" scene.ray same.png wrong.ppm small.png --size any --html again >/dev/null 2>&1
check "a first report of three images" test -s again/heat_3.png -a -s again/reference_40x30.png
echo "a teacher's notes" >again/notes.txt
"$rc" scene.ray same.png --html again >out.txt 2>&1
check "a second report into it: exit 0" test $? -eq 0
check "its files only: the earlier report's are gone, the teacher's note stays" \
    test "$(ls -A again | tr '\n' ' ')" = ".raycompare-report heat_1.png image_1.png index.html notes.txt reference_64x48.png scale.png signed_1.png signed_scale.png "
check "the page has one row" test "$(grep -c '^<tr class=' again/index.html)" -eq 1
# An input inside our folder under one of the report's names is never replaced, even under a
# second name (a hard link): the report is refused.
cp again/image_1.png kept.png && ln again/image_1.png student.png
"$rc" scene.ray student.png --html again >out.txt 2>&1
check "an input that is the report's image_1.png: refused (exit 2)" test $? -eq 2
check "and it stays" cmp -s student.png kept.png
check "its name is said" grep -qF "again/image_1.png', which is one of the files given on the command line" out.txt
rm student.png
# The CSV must not be an input, and is probed before rendering; so is the report's folder.
cp same.png same2.png
"$rc" scene.ray same2.png --csv same2.png >out.txt 2>&1
check "--csv naming an image: refused (exit 2)" test $? -eq 2
check "the image stays" cmp -s same.png same2.png
"$rc" scene.ray same.png --csv nodir/table.csv >out.txt 2>&1
check "--csv in a missing folder: exit 1" test $? -eq 1
check "said before rendering" bash -c "grep -q \"cannot write 'nodir/table.csv'\" out.txt && ! grep -q 'rendered the' out.txt"
"$rc" scene.ray same.png --html notes.txt/report >out.txt 2>&1
check "--html under a file: fails" test $? -ne 0
check "said before rendering" bash -c "grep -q \"^raycompare: error: --html 'notes.txt/report'\" out.txt && ! grep -q 'rendered the' out.txt"

# A file's name with control characters: escaped in the table, the CSV and the error, never
# sent to the terminal (a name can move the cursor and write PASS over FAIL).
esc=$'evil\r\e[2KPASS.png'
cp wrong.ppm "$esc"
"$rc" scene.ray "$esc" "missing$esc" --csv esc.csv >out.txt 2>&1
check "escaped names: the run fails" test $? -eq 1
check "no control byte in the table" bash -c "! LC_ALL=C grep -q \$'[\\x01-\\x08\\x0b-\\x1f\\x7f]' out.txt"
check "no control byte in the CSV" bash -c "! LC_ALL=C grep -q \$'[\\x01-\\x08\\x0b-\\x1f\\x7f]' esc.csv"
check "the name shown escaped" grep -qF 'evil\x0d\x1b[2KPASS ' out.txt
check "the error too" grep -qF "FAIL: cannot read 'missingevil\x0d\x1b[2KPASS.png'" out.txt
check "the CSV too" grep -qF 'evil\x0d\x1b[2KPASS.png,evil\x0d\x1b[2KPASS,64,48' esc.csv
"$rc" scene.ray "$esc" --html escrep >/dev/null 2>&1
check "the page escapes it" grep -qF '<td title="evil\x0d\x1b[2KPASS.png">evil\x0d\x1b[2KPASS</td>' escrep/index.html
rm -f "$esc"

# A class of many images: each is a row; a bad file, and an image whose reference cannot be
# rendered (out of memory), are FAIL rows of their own, and the table, the CSV and the page come
# out for everyone. Under a cap of 240 MB, the 2048x2048 image is read in 115 MB, its reference
# needs 320 MB.
class=()
for i in $(seq 2 20); do cp same.png "c$i.png" && class+=("c$i.png"); done
cp same.png c1.png
python3 -c '
import struct, sys, zlib
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
w = h = 2048
ihdr = struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)
idat = zlib.compress((b"\0" + b"\x80" * w) * h, 9)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")
open(sys.argv[1], "wb").write(png)
' big.png
if grep -q -e __asan_init -e __tsan_init "$rc"; then
    echo "(the class out of memory: skipped for a sanitizer build, which needs no address cap)"
else
    (ulimit -v 240000 && exec "$rc" scene.ray c1.png notes.txt big.png "${class[@]}" \
        --size any --csv class.csv --html classrep) >out.txt 2>&1
    check "the class: exit 1 (two images fail)" test $? -eq 1
    check "the class: every image has its row" test "$(grep -cE '^c[0-9]+ +64x48 .*PASS$' out.txt)" -eq 20
    check "the class: the bad file is a FAIL row" grep -qE '^notes +- +FAIL: .*notes.txt' out.txt
    check "the class: the reference out of memory is a FAIL row" \
        grep -qE '^big +2048x2048 +FAIL: out of memory while rendering the 2048x2048 reference$' out.txt
    check "the class: the CSV has every row" test "$(($(wc -l <class.csv) - 1))" -eq 22
    check "the class: so has the page" test "$(grep -c '^<tr class=' classrep/index.html)" -eq 22
    check "the class: the last image's heat map" test -s classrep/heat_22.png
fi
# --neighbourhood excuses only an edge of the reference moved by a pixel: a highlight's exponent
# 12 for 8, whose flank a pixel's neighbourhood would excuse (1.1% off, 0.3% with every pixel
# against its neighbourhood), still fails (the one-pixel shift passes, above).
sed 's/  40  /  8  /' scene.ray >e8.ray
sed 's/  40  /  12  /' scene.ray >e12.ray
"$rt" e12.ray --width 64 --height 48 -q -o e12.png
"$rc" e8.ray e12.png >out.txt 2>&1
check "a highlight's exponent 12 for 8 fails" test $? -eq 1
"$rc" e8.ray e12.png --neighbourhood >out.txt 2>&1
check "--neighbourhood: and still fails" test $? -eq 1
check "--neighbourhood: its row says FAIL" grep -qE "^e12 .*FAIL$" out.txt
"$rc" scene.ray wrong.ppm --neighbourhood >out.txt 2>&1
check "--neighbourhood: exponent 4 for 40 fails too" test $? -eq 1

# A class laid out as one folder per student: the names are the folders (never the path),
# aligned by the columns they take (non-ASCII names too); a summary and the rule head the table.
mkdir -p folders/ann folders/chloé folders/李明 folders/zoë
cp same.png folders/ann/scene.png && cp wrong.ppm folders/chloé/scene.ppm
cp small.png folders/zoë/scene.png && : >folders/李明/scene.png
"$rc" scene.ray folders/*/scene.* --gradescope results.json --html folderrep >out.txt 2>&1
check "folders: exit 1" test $? -eq 1
check "folders: the summary" grep -qx "4 images: 1 pass, 2 fail, 1 cannot be read" out.txt
check "folders: the rule" grep -qE "^rule: a pixel is off when a channel differs by more than 8 of 255; an image passes with at most 0.5% of its pixels off;.* every image 64x48$" out.txt
check "folders: named by folder" grep -qE "^ann +64x48 .*PASS$" out.txt
check "folders: no path in the table" bash -c "! grep -q 'folders/ann' out.txt"
check "folders: an empty file says so" grep -qF "FAIL: cannot read 'folders/李明/scene.png': empty file" out.txt
check "folders: the wrong size fails, saying so" grep -qF "FAIL: the image is 40x30, not the expected 64x48 (the first image's size; set it with --size WxH)" out.txt
python3 - out.txt >align.txt 2>&1 <<'PY'
import sys, unicodedata
def cols(s):
    return sum(0 if unicodedata.combining(c) else 2 if unicodedata.east_asian_width(c) in 'WF' else 1 for c in s)
lines = [l.rstrip('\n') for l in open(sys.argv[1], encoding='utf-8')]
rows = [l for l in lines if l.split(' ')[0] in ('student', 'ann', 'chloé', '李明', 'zoë')]
at = {cols(l[:l.index('  ')]) + len(l[l.index('  '):]) - len(l[l.index('  '):].lstrip(' ')) for l in rows}
print('ok' if len(rows) == 5 and len(at) == 1 else f'no: {rows} {at}')
PY
check "folders: the columns align (display width, not bytes)" grep -qx ok align.txt
check "folders: the page names the folders" grep -q '>李明</td>' folderrep/index.html
check "folders: a signed view" test -s folderrep/signed_2.png -a -s folderrep/signed_scale.png
check "folders: the worst pixel's --inspect command" grep -qE 'raytrace scene.ray --width 64 --height 48 --inspect [0-9]+,[0-9]+</code>' folderrep/index.html
python3 - results.json >gs.txt 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1], encoding='utf-8'))
t = {x['name']: x for x in r['tests']}
ok = (r['score'] == 1 and r['max_score'] == 4 and sorted(t) == ['ann', 'chloé', 'zoë', '李明']
      and t['ann']['status'] == 'passed' and t['ann']['score'] == 1
      and t['chloé']['status'] == 'failed' and t['chloé']['score'] == 0
      and '% of pixels off by more than 8' in t['chloé']['output']
      and '--inspect' in t['chloé']['output'] and 'empty file' in t['李明']['output']
      and 'not the expected 64x48' in t['zoë']['output']
      and '1 pass, 2 fail, 1 cannot be read' in r['output'])
print('ok' if ok else f'no: {r}')
PY
check "--gradescope: score, max_score, one test per image with its reason" grep -qx ok gs.txt
"$rc" scene.ray same.png --gradescope same.png >out.txt 2>&1
check "--gradescope naming an image: refused (exit 2)" test $? -eq 2
check "the image stays" cmp -s same.png folders/ann/scene.png

# --size: the expected size, not the first image's.
"$rc" scene.ray same.png small.png --size 40x30 >out.txt 2>&1
check "--size 40x30: the 64x48 image fails" grep -qF "FAIL: the image is 64x48, not the expected 40x30 (--size)" out.txt
check "--size 40x30: the 40x30 one passes" grep -qE "^small +40x30 .*PASS$" out.txt
check "--size 40x30: one reference" test "$(grep -c 'rendered the .* reference' out.txt)" -eq 1
"$rc" scene.ray same.png --size 40 >out.txt 2>&1
check "--size 40: usage error" test $? -eq 2

# JPEG: the lossy rule. A correct render at quality 90 and 95 passes; mistakes saved at
# quality 95 (a dimmer light, no shadows, a refraction index, gamma) fail. Needs ImageMagick.
if command -v /usr/bin/convert >/dev/null && /usr/bin/convert -version 2>/dev/null | grep -q ImageMagick; then
    cp -r "$src/scenes" show
    r="--width 160 --height 120 -q"
    sed 's/^#light_point 0.35 0.4 0.7/#light_point 0.25 0.3 0.5/' show/showpiece.ray >show/light.ray
    sed 's/  300  0.88 0.9 0.95  1.52/  300  0.88 0.9 0.95  1.45/' show/showpiece.ray >show/ring.ray
    "$rt" show/showpiece.ray $r -o ok.png
    "$rt" show/light.ray $r -o light.png
    "$rt" show/ring.ray $r -o ring.png
    "$rt" show/showpiece.ray $r --no-shadows -o noshadow.png
    /usr/bin/convert ok.png -gamma 1.15 gamma.png
    for q in 90 95; do /usr/bin/convert ok.png -quality $q ok$q.jpg; done
    for m in light ring noshadow gamma; do /usr/bin/convert $m.png -quality 95 $m.jpg; done
    "$rc" show/showpiece.ray ok90.jpg ok95.jpg light.jpg ring.jpg noshadow.jpg gamma.jpg >out.txt 2>&1
    check "lossy: quality 90 passes" grep -qE "^ok90 .*PASS \(lossy rule\)$" out.txt
    check "lossy: quality 95 passes" grep -qE "^ok95 .*PASS \(lossy rule\)$" out.txt
    for m in light ring noshadow gamma; do
        check "lossy: the $m mistake fails" grep -qE "^$m .*FAIL \(lossy rule\)$" out.txt
    done
    /usr/bin/convert ok90.jpg ok90.png
    "$rc" show/showpiece.ray ok90.png >out.txt 2>&1
    check "the same pixels as PNG fail the exact rule" grep -qE "^ok90 .*FAIL$" out.txt
    "$rc" show/showpiece.ray ok90.png --lossy >out.txt 2>&1
    check "and pass with --lossy" grep -qE "^ok90 .*PASS \(lossy rule\)$" out.txt
    # --diagnose (docs/tools.md): a correct render as PNG, PPM, BMP and JPEG at quality 90 passes
    # and gets no diagnosis; shadows left out, as PNG and as JPEG, are named.
    mkdir -p dg
    "$rt" show/showpiece.ray $r -o dg/png.png
    "$rt" show/showpiece.ray $r -o dg/ppm.ppm
    "$rt" show/showpiece.ray $r -o dg/bmp.bmp
    cp ok90.jpg dg/jpeg90.jpg
    cp noshadow.png dg/noshadow.png
    cp noshadow.jpg dg/noshadow95.jpg
    "$rc" show/showpiece.ray dg/png.png dg/ppm.ppm dg/bmp.bmp dg/jpeg90.jpg dg/noshadow.png \
        dg/noshadow95.jpg --diagnose --csv dg.csv >out.txt 2>&1
    for f in png ppm bmp jpeg90; do
        check "--diagnose: the correct $f passes" grep -qE "^$f .*PASS" out.txt
        check "and gets no diagnosis" sh -c "grep -A1 -E '^$f ' out.txt | tail -1 | grep -qvE '^    [0-9]'"
    done
    check "--diagnose: no shadows named" sh -c "grep -A1 -E '^noshadow ' out.txt | grep -qE '^    1\. no-shadows \(explains'"
    check "--diagnose: and through a JPEG too" sh -c "grep -A1 -E '^noshadow95 ' out.txt | grep -qE '^    1\. no-shadows \(explains'"
    check "--diagnose: the CSV's column" grep -qE ',1\. no-shadows \(explains [0-9]+%\)' dg.csv
else
    echo "(the lossy rule on JPEG files: skipped, ImageMagick's convert is not installed)"
fi
summary "raycompare"
