#!/usr/bin/env python3
"""make_class.py OUTDIR [--size WxH] [--scenes DIR] [--jobs N]: a labelled class of mistaken images.

For each scene of tests/diagnose/scenes/ (or --scenes DIR), renders with minirender (the
independent renderer beside this file) a correct image, one image per mistake and a few pairs of
two mistakes, into OUTDIR/<scene>/<mistake>.png (correct.png for none, A+B.png for a pair), and
writes OUTDIR/manifest.json and OUTDIR/manifest.csv: one row per image with its scene, file, the
mistakes it holds, whether the scene was designed to show them (a scene's
`// minirender-not-for:` comment lists those it was not), and how far it is from the correct
image (share of pixels off by more than 8 of 255 in a channel: raycompare's default tolerance;
mean absolute difference). This is the set the diagnosis is scored against.
"""

import argparse
import csv
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import minirender as mr  # noqa: E402

OUTPUT_MISTAKES = {"flip-vertical", "gamma", "bgr", "wrap-overflow"}  # applied when writing
PAIRS = [
    ("no-shadows", "gamma"),
    ("no-specular", "flip-vertical"),
    ("no-attenuation", "no-ambient"),
    ("blinn", "bgr"),
    ("no-reflection", "full-angle"),
    ("opaque-shadows", "light-dir-reversed"),
]
TOLERANCE = 8


def not_for(scene_path):
    """The mistakes a scene says it was not designed to show."""
    out = set()
    with open(scene_path, encoding="latin-1") as f:
        for line in f:
            if line.startswith("// minirender-not-for:"):
                out.update(line.split(":", 1)[1].split())
    return out


def difference(a, b):
    """(share of pixels off by more than TOLERANCE in a channel, mean absolute difference) of two
    lists of byte rows of the same size."""
    off = total = 0
    absum = 0
    for ra, rb in zip(a, b):
        for k in range(0, len(ra), 3):
            d = max(abs(ra[k] - rb[k]), abs(ra[k + 1] - rb[k + 1]), abs(ra[k + 2] - rb[k + 2]))
            absum += abs(ra[k] - rb[k]) + abs(ra[k + 1] - rb[k + 1]) + abs(ra[k + 2] - rb[k + 2])
            off += d > TOLERANCE
            total += 1
    return off / total, absum / (3 * total)


def images_for():
    """(file stem, mistakes) of every image of a scene: correct, each mistake, the pairs."""
    out = [("correct", ())]
    out += [(name, (name,)) for name in mr.MISTAKES]
    out += [("%s+%s" % p, p) for p in PAIRS]
    return out


def render_scene(scene_path, width, height, outdir, names=None):
    """Renders one scene's images; returns the manifest rows. The linear image of a set of
    shading mistakes is rendered once and written with each output mistake."""
    scene = mr.parse(scene_path)
    stem = os.path.splitext(os.path.basename(scene_path))[0]
    skip = not_for(scene_path)
    os.makedirs(os.path.join(outdir, stem), exist_ok=True)
    cache = {}
    rows = []
    correct = None
    for name, mistakes in images_for():
        if names is not None and name not in names and name != "correct":
            continue
        shading = tuple(sorted(m for m in mistakes if m not in OUTPUT_MISTAKES))
        t0 = time.perf_counter()
        if shading not in cache:
            cache[shading] = mr.Renderer(scene, shading).render(width, height)
        img = mr.to_bytes(cache[shading], mistakes)
        seconds = time.perf_counter() - t0
        path = os.path.join(outdir, stem, name + ".png")
        mr.write_image(path, img)
        if correct is None:
            correct = img
        share, mad = difference(img, correct)
        rows.append({
            "scene": stem, "scene_file": os.path.abspath(scene_path), "image": os.path.relpath(path, outdir),
            "mistakes": list(mistakes), "designed_for": not any(m in skip for m in mistakes),
            "share_off": round(share, 5), "mean_abs_diff": round(mad, 3),
            "width": width, "height": height, "seconds": round(seconds, 3),
        })
    return rows


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--size", default="160x120", help="WxH (default 160x120)")
    ap.add_argument("--scenes", default=os.path.join(here, "scenes"), help="folder of .ray scenes")
    ap.add_argument("--jobs", type=int, default=1, help="scenes rendered in parallel (processes)")
    ap.add_argument("--only", action="append", help="render only this image stem (repeatable)")
    args = ap.parse_args(argv)
    try:
        width, height = (int(x) for x in args.size.lower().split("x"))
        if width < 1 or height < 1:
            raise ValueError
    except ValueError:
        ap.error("--size must be WxH, e.g. 160x120")
    scenes = sorted(os.path.join(args.scenes, f) for f in os.listdir(args.scenes) if f.endswith(".ray"))
    if not scenes:
        ap.error("no .ray scenes in %s" % args.scenes)
    os.makedirs(args.outdir, exist_ok=True)
    t0 = time.perf_counter()
    jobs = [(s, width, height, args.outdir, set(args.only) if args.only else None) for s in scenes]
    try:
        if args.jobs > 1:
            import multiprocessing
            with multiprocessing.Pool(args.jobs) as pool:
                results = pool.starmap(render_scene, jobs)
        else:
            results = [render_scene(*j) for j in jobs]
    except mr.SceneError as e:
        print("make_class: error: %s" % e, file=sys.stderr)
        return 2
    rows = [r for rs in results for r in rs]
    with open(os.path.join(args.outdir, "manifest.json"), "w") as f:
        json.dump({"size": [width, height], "tolerance": TOLERANCE, "images": rows}, f, indent=1)
    with open(os.path.join(args.outdir, "manifest.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "image", "mistakes", "designed_for", "share_off", "mean_abs_diff"])
        for r in rows:
            w.writerow([r["scene"], r["image"], "+".join(r["mistakes"]) or "none", int(r["designed_for"]),
                        r["share_off"], r["mean_abs_diff"]])
    print("make_class: %d images of %d scenes at %dx%d in %s (%.1f s)" % (
        len(rows), len(scenes), width, height, args.outdir, time.perf_counter() - t0))
    return 0


if __name__ == "__main__":
    sys.exit(main())
