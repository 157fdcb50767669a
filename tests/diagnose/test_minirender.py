#!/usr/bin/env python3
"""CTest test of the independent renderer (tests/diagnose/README.md):

1. minirender reproduces the specification's worked examples 7.6 and 7.7 (its own correctness,
   without our renderer);
2. for each scene of tests/diagnose/scenes/, minirender's correct image and our `raytrace` agree
   under raycompare's default rule (raycompare renders the reference with raytrace);
3. every mistaken image (each mistake, and the pairs of make_class.py) that its scene is designed
   for fails that rule: a mistake that changes nothing would be a bad scene for it; a pair
   of mistakes differs from each of its two alone; and `raycompare --diagnose` names them:
   the first explanation right on at least 80% of them, one of the first three on 95%, and the
   correct images (which pass) get no diagnosis;
4. the default camera and a V0 file agree with raytrace too;
5. the command line: --list-mistakes, an unsupported directive (exit 2, no output file), more than
   two mistakes (exit 2), PPM output.

    test_minirender.py --bin DIR_OF_RAYCOMPARE [--out DIR] [--size WxH]
"""

import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_class  # noqa: E402
import minirender as mr  # noqa: E402

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: " + what)


def worked_examples(tmp):
    plane = ("#vertex -1000 0 -1000 0 0 0 0 0\n#vertex 1000 0 -1000 0 0 0 0 0\n"
             "#vertex 1000 0 1000 0 0 0 0 0\n#vertex -1000 0 1000 0 0 0 0 0\n"
             "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n")
    ex76 = ("#camera 0 10 10  0 -1 -1  0 1 0  0.5\n#background 0.2 0.2 0.2\n#ambient 0.5 0.5 0.5\n"
            "#light_point 1 1 1  5 5 5  0.01 0.02 0.03\n"
            "#material 0 0 0  .3 .3 .3  .1 .1 .5  1 1 1  100  0 0 0  1 -1 !!\n" + plane)
    ex77 = ("#camera 0 10 10  0 -1 -1  0 1 0  0.5\n#ambient 0.5 0.5 0.5\n"
            "#light_spot 1 1 1  5 5 5  -2 -5 1  0.3 0.02 0  0.5 0.5\n"
            "#material 0.3 0.3 0.3  0.1 0.1 0.5  1 1 1  0 0 0  0.78125 0 1.05 -1 !!\n" + plane)
    cases = [(ex76, (3, 0, 6), (0.566933, 0.566933, 0.925082), b"\x91\x91\xec"),
             (ex77, (3, 0, 7), (0.718841, 0.718841, 1.042928), b"\xb7\xb7\xff"),
             (ex77, (0, 0, 0), (0.15, 0.15, 0.15), b"\x26\x26\x26")]
    for k, (text, p, want, want_bytes) in enumerate(cases):
        path = os.path.join(tmp, "example%d.ray" % k)
        with open(path, "w") as f:
            f.write(text)
        r = mr.Renderer(mr.parse(path))
        eye = (0.0, 10.0, 10.0)
        c = r.trace(eye, mr.norm(mr.sub(p, eye)), 5, (1.0, 1.0, 1.0))
        check(all(abs(a - b) < 2e-6 for a, b in zip(c, want)), "worked example %d: %s, spec %s" % (k, c, want))
        check(mr.to_bytes([[c]])[0] == want_bytes, "worked example %d bytes" % k)


def command_line(tmp):
    me = [sys.executable, os.path.join(HERE, "minirender.py")]
    out = subprocess.run(me + ["--list-mistakes"], capture_output=True, text=True)
    names = [line.split()[0] for line in out.stdout.splitlines()]
    check(out.returncode == 0 and len(names) >= 15 and "no-shadows" in names, "--list-mistakes")
    bad = os.path.join(tmp, "box.ray")
    with open(bad, "w") as f:
        f.write("#material 0 0 0 1 1 1 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n#shape_box 0  0 0 0  1 1 1\n")
    target = os.path.join(tmp, "box.png")
    r = subprocess.run(me + [bad, target, "--width", "8", "--height", "6"], capture_output=True, text=True)
    check(r.returncode == 2 and "'#shape_box' is not supported" in r.stderr and "box.ray:2" in r.stderr
          and not os.path.exists(target), "unsupported directive: exit 2 with a message, no file (%s)" % r.stderr)
    scene = os.path.join(HERE, "scenes", "spheres.ray")
    r = subprocess.run(me + [scene, target, "--mistake", "gamma", "--mistake", "bgr", "--mistake", "blinn"],
                       capture_output=True, text=True)
    check(r.returncode == 2 and "at most 2" in r.stderr and not os.path.exists(target), "three mistakes refused")
    r = subprocess.run(me + [scene, target, "--mistake", "no-such"], capture_output=True, text=True)
    check(r.returncode == 2 and "unknown mistake" in r.stderr, "unknown mistake refused")
    ppm, png = os.path.join(tmp, "s.ppm"), os.path.join(tmp, "s.png")
    for path in (ppm, png):
        r = subprocess.run(me + [scene, path, "--width", "16", "--height", "12", "--mistake", "bgr"])
        check(r.returncode == 0, "render %s" % path)
    check(mr.read_image(ppm) == mr.read_image(png), "PPM and PNG hold the same pixels")


def default_camera_and_v0(tmp, bindir):
    """The default camera (spec 6.3, no #camera) and a V0 file (worked example 7.7's spot light
    and material on a floor, seen whole) agree with raytrace too."""
    me = [sys.executable, os.path.join(HERE, "minirender.py")]
    with open(os.path.join(HERE, "scenes", "spheres.ray")) as f:
        nocam = "".join(line for line in f if not line.startswith("#camera"))
    v0 = ("#camera 0 10 10  0 -1 -1  0 1 0  0.5\n#ambient 0.5 0.5 0.5\n"
          "#light_spot 1 1 1  5 5 5  -2 -5 1  0.3 0.02 0  0.5 0.5\n"
          "#material 0.3 0.3 0.3  0.1 0.1 0.5  1 1 1  0 0 0  0.78125 0 1.05 -1 !!\n"
          "#vertex -20 0 -20 0 0 0 0 0\n#vertex 20 0 -20 0 0 0 0 0\n#vertex 20 0 20 0 0 0 0 0\n"
          "#vertex -20 0 20 0 0 0 0 0\n#shape_triangle -1 0 1 2\n#shape_triangle 0 0 2 3\n"
          "#shape_sphere 0 2 1 3  1\n")
    for name, text, warning in (("nocam", nocam, "default camera"), ("v0", v0, "")):
        scene, image = os.path.join(tmp, name + ".ray"), os.path.join(tmp, name + ".png")
        with open(scene, "w") as f:
            f.write(text)
        r = subprocess.run(me + [scene, image, "--width", "80", "--height", "60"], capture_output=True, text=True)
        check(r.returncode == 0 and warning in r.stderr, "%s: minirender (%s)" % (name, r.stderr))
        r = subprocess.run([os.path.join(bindir, "raycompare"), scene, image], capture_output=True, text=True)
        check(r.returncode == 0 and "PASS" in r.stdout, "%s: minirender and raytrace disagree\n%s" % (name, r.stdout))


def diagnosed(text):
    """The sets of mistakes of a diagnosis ("1. a + b (explains 97%); 2. gamma (exponent 2.2)
    (explains 80%)"), in rank order, each sorted; none for "none of the known mistakes ..."."""
    out = []
    for item in text.split("; "):
        m = re.match(r"^\d+\. (.*) \(explains \d+%\)$", item)
        if m:
            out.append(sorted(part.split(" (")[0] for part in m.group(1).split(" + ")))
    return out


def against_raytrace(tmp, bindir, size):
    scores = []  # per designed mistaken image: (first right, in the first three)
    classdir = os.path.join(tmp, "class")
    check(make_class.main([classdir, "--size", size]) == 0, "make_class")
    with open(os.path.join(classdir, "manifest.json")) as f:
        manifest = json.load(f)
    by_scene = {}
    for row in manifest["images"]:
        by_scene.setdefault(row["scene"], []).append(row)
    raycompare = os.path.join(bindir, "raycompare")
    for scene, rows in sorted(by_scene.items()):
        table = os.path.join(tmp, scene + ".csv")
        images = [os.path.join(classdir, r["image"]) for r in rows]
        subprocess.run([raycompare, rows[0]["scene_file"], *images, "--csv", table, "--quiet",
                        "--diagnose"], capture_output=True, text=True)
        with open(table, newline="") as f:
            verdict = {os.path.abspath(r["file"]): r for r in csv.DictReader(f)}
        for row, image in zip(rows, images):
            got = verdict.get(os.path.abspath(image))
            if got is None:
                check(False, "%s: raycompare gave no row" % image)
                continue
            name = "+".join(row["mistakes"]) or "correct"
            if not row["mistakes"]:
                check(got["result"] == "pass", "%s: minirender's correct image and raytrace disagree (%s%% off)"
                      % (scene, 100 * float(got["share_off"])))
                check(got["diagnosis"] == "", "%s: the correct image got a diagnosis" % scene)
            elif row["designed_for"]:
                check(got["result"] == "fail", "%s: the mistake %s does not fail the default rule (%.2f%% off)"
                      % (scene, name, 100 * float(got["share_off"])))
                ranked = diagnosed(got["diagnosis"])
                scores.append((sorted(row["mistakes"]) in ranked[:1], sorted(row["mistakes"]) in ranked[:3]))
                if sorted(row["mistakes"]) not in ranked[:1]:
                    print("diagnosis: %s/%s: %s" % (scene, name, got["diagnosis"]))
                # make_class's own measure of the change is the one raycompare finds.
                check(abs(float(got["share_off"]) - row["share_off"]) < 1e-3, "%s/%s: share off %s against %s"
                      % (scene, name, got["share_off"], row["share_off"]))
        # A pair must show both of its mistakes: differ from each one alone.
        files = {"+".join(r["mistakes"]): os.path.join(classdir, r["image"]) for r in rows}
        for row in rows:
            if len(row["mistakes"]) == 2 and row["designed_for"]:
                pair = mr.read_image(files["+".join(row["mistakes"])])[2]
                for one in row["mistakes"]:
                    share = make_class.difference(pair, mr.read_image(files[one])[2])[0]
                    check(share > 0.005, "%s: the pair %s is %.2f%% off %s alone"
                          % (scene, "+".join(row["mistakes"]), 100 * share, one))
    # The diagnosis (raycompare --diagnose) names the independent renderer's mistakes: the
    # first explanation right on at least 80% of the images, one of the first three on 95%.
    first = sum(f for f, _ in scores) / max(1, len(scores))
    top3 = sum(t for _, t in scores) / max(1, len(scores))
    print("diagnosis: %d mistaken images, first right %.0f%%, in the first three %.0f%%"
          % (len(scores), 100 * first, 100 * top3))
    check(first >= 0.8, "the first explanation is right on %.0f%% of the images (at least 80%%)" % (100 * first))
    check(top3 >= 0.95, "one of the first three is right on %.0f%% (at least 95%%)" % (100 * top3))
    designed = {m for rows in by_scene.values() for r in rows if r["designed_for"] for m in r["mistakes"]}
    check(len(designed) >= 15, "at least 15 mistakes shown by some scene (%d)" % len(designed))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True, help="folder of raycompare")
    ap.add_argument("--out", help="keep the images here (default: a temporary folder)")
    ap.add_argument("--size", default="80x60")
    args = ap.parse_args()
    tmp = args.out or tempfile.mkdtemp(prefix="minirender-")
    if args.out:
        shutil.rmtree(tmp, ignore_errors=True)
        os.makedirs(tmp)
    try:
        worked_examples(tmp)
        command_line(tmp)
        default_camera_and_v0(tmp, args.bin)
        against_raytrace(tmp, args.bin, args.size)
    finally:
        if not args.out:
            shutil.rmtree(tmp, ignore_errors=True)
    print("%d failure(s)" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
