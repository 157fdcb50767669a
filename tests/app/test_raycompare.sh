#!/usr/bin/env bash
# raycompare end to end: an image equal to the reference passes with 0 difference; shifted by one
# pixel it fails, and passes with --neighbourhood; a wrong specular exponent fails and its largest
# difference is on a highlight; the HTML report's images exist and its table matches the CSV;
# unreadable and non-image files fail naming the file, an empty list is a usage error; images of
# two sizes get a reference each; PFM is compared linear.
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
check "with 0 difference" grep -qE "^same.png +64x48 +0\.000 +0\.000% +0\.0 .*PASS$" out.txt
"$rc" scene.ray same.pfm >out.txt 2>&1
check "a PFM, compared linear, passes" test $? -eq 0
check "also with 0 difference" grep -qE "^same.pfm +64x48 +0\.000 .*PASS$" out.txt

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
check "said FAIL" grep -qE "^shifted.ppm .*FAIL$" out.txt
"$rc" scene.ray shifted.ppm --neighbourhood >out.txt 2>&1
check "and passes with --neighbourhood" test $? -eq 0

# A wrong specular exponent: fails, and the largest difference is on the highlight.
"$rc" scene.ray wrong.ppm same.png small.png --csv table.csv --html report >out.txt 2>&1
check "a wrong exponent fails (the run exits 1)" test $? -eq 1
check "its row says FAIL" grep -qE "^wrong.ppm .*FAIL$" out.txt
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
check "report: the failing row says FAIL" grep -q '<td>wrong.ppm</td>.*FAIL' report/index.html

# Bad input: named, and the run fails; nothing half-written.
echo "not an image" >notes.txt
"$rc" scene.ray same.png notes.txt missing.png >out.txt 2>&1
check "a non-image and a missing file fail the run" test $? -eq 1
check "the non-image is named" grep -qE "^notes.txt .*FAIL: .*notes.txt" out.txt
check "the missing file is named" grep -qE "^missing.png .*FAIL: .*missing.png" out.txt
check "the good image still passes" grep -qE "^same.png .*PASS$" out.txt
"$rc" scene.ray >out.txt 2>&1
check "no image is a usage error" test $? -eq 2
printf '#shape_sphere 0 0 0 0 1 x\n' >bad.ray
"$rc" bad.ray same.png >out.txt 2>&1
check "a scene error exits 1" test $? -eq 1
check "with file:line:col" grep -qE "^bad.ray:1:[0-9]+: error: " out.txt
"$rc" scene.ray same.png --max-bad 2 >out.txt 2>&1
check "--max-bad beyond 1 is a usage error" test $? -eq 2

summary "raycompare"
