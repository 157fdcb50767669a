#!/usr/bin/env python3
"""minirender: a small, independent .ray renderer for testing the mistake diagnosis.

Written from the format specification only (../shared/spec/ray-format.md sections 3, 5, 6, 7, 8
and 9), never from the C++ renderer, so that the images it makes with a mistake switched on are
not the catalogue's own renders. Pure Python 3, standard library only.

    minirender.py SCENE.ray OUT.png|OUT.ppm [--width W] [--height H] [--mistake NAME]...
    minirender.py --list-mistakes

Supported: a V1 (or V0) file without includes, groups or textures: #camera, #background,
#ambient, #light_num, #light_dir, #light_point, #light_spot, #material_num, #material,
#vertex_num, #vertex, #shape_sphere, #shape_triangle. Any other directive: a message on stderr
and exit status 2.
"""

import argparse
import math
import os
import re
import struct
import sys
import zlib

# The catalogue's names (docs/mistakes.md); the value says what the student did. The texture mistakes
# (NOT_IMPLEMENTED) are not rendered: minirender has no textures.
MISTAKES = {
    "full-angle": "camera: ha read as the full angle (tan(ha/2))",
    "angle-on-width": "camera: ha applied to the width (tan_w = tan(ha), tan_h = tan(ha)/aspect)",
    "flip-vertical": "output: rows written bottom-up",
    "gamma": "output: a 1/2.2 gamma before the 8 bits",
    "bgr": "output: red and blue swapped",
    "wrap-overflow": "output: no clamp, byte = int(255 c) mod 256",
    "no-ambient": "shading: K_A * A left out",
    "no-emissive": "shading: K_E left out",
    "no-diffuse-clamp": "shading: lights with N.L <= 0 still add (negative diffuse)",
    "one-sided": "shading: the normal is not turned toward the ray (no two-sided rule)",
    "no-specular": "shading: K_S * spec left out",
    "blinn": "shading: highlight (N.H)^e with the half vector instead of (R_v.L)^e",
    "light-dir-reversed": "lights: a directional light's direction used as L (not -dir)",
    "no-attenuation": "lights: point/spot colour not divided by ca + la d + qa d^2",
    "spot-no-dropoff": "lights: the spot's cos_a^p factor left out",
    "spot-cutoff-full-angle": "lights: the spot cut-off read as the full cone angle",
    "no-shadows": "shadows: none (S_l = 1)",
    "opaque-shadows": "shadows: transparent surfaces cast full shadows",
    "shadow-past-light": "shadows: shadow rays not stopped at a point/spot light",
    "no-offset": "rays: secondary rays start at P itself (no offset)",
    "no-reflection": "recursion: no reflected ray",
    "no-refraction": "recursion: no refracted ray",
    "ior-inverted": "refraction: eta = refind entering, 1/refind leaving",
    "depth-off-by-one": "recursion: children traced while depth - 1 >= 0",
    "no-cutoff": "recursion: the cutoff ignored",
}
NOT_IMPLEMENTED = {"texture-v-flipped", "texture-diffuse-only"}

INF = float("inf")


class SceneError(Exception):
    """A scene minirender cannot read (unsupported or malformed): exit status 2."""


# ---------------------------------------------------------------------------------------------
# Vectors as 3-tuples.


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


# ---------------------------------------------------------------------------------------------
# Parsing (spec §2, §3): tokens are comments, !strings! and whitespace-separated words.

TOKEN = re.compile(r"//[^\n\r]*|![^!\n\r]*!|\S+")


class Material:
    def __init__(self, ke, ka, kd, ks, e, t, refind):
        self.ke, self.ka, self.kd, self.ks, self.e, self.t = ke, ka, kd, ks, e, t
        self.refind = refind if refind > 0 else 1.0
        self.has_ks = max(ks) > 0
        self.has_t = max(t) > 0


V0_DEFAULT = Material((0, 0, 0), (.2, .2, .2), (.8, .8, .8), (.8, .8, .8), 128.0, (0, 0, 0), 1.0)


class Scene:
    def __init__(self):
        self.camera = None  # (p, d, up, ha)
        self.background = (0.0, 0.0, 0.0)
        self.ambient = (0.0, 0.0, 0.0)
        self.lights = []  # ("dir", colour, dir) / ("point", colour, pos, ca, la, qa) / ("spot", ...)
        self.materials = []
        self.vertices = []  # (p, n or None)
        self.spheres = []  # (centre, r, material)
        self.triangles = []  # (v1, e1, e2, n_g, normals or None, material)
        self.dialect = None


def parse(path):
    with open(path, "rb") as f:
        text = f.read().decode("latin-1")
    if text.startswith("\xef\xbb\xbf"):
        text = text[3:]
    toks = [(m.group(0), m.start()) for m in TOKEN.finditer(text) if not m.group(0).startswith("//")]

    def where(pos):
        return "%s:%d" % (path, text.count("\n", 0, pos) + 1)

    scene = Scene()
    spot_raw = []
    i = 0

    def numbers(k, directive, pos):
        nonlocal i
        out = []
        for _ in range(k):
            if i >= len(toks):
                raise SceneError("%s: expected %d numbers after %s" % (where(pos), k, directive))
            word, wpos = toks[i]
            try:
                v = float(word)
            except ValueError:
                raise SceneError("%s: expected %d numbers after %s, got '%s'" % (where(wpos), k, directive, word))
            if not math.isfinite(v):
                raise SceneError("%s: non-finite number '%s'" % (where(wpos), word))
            out.append(v)
            i += 1
        return out

    def index(v, n, what, pos, allow_minus=False):
        if v != int(v):
            raise SceneError("%s: expected an integer (%s)" % (where(pos), what))
        k = int(v)
        if not (0 <= k < n or (allow_minus and k == -1)):
            raise SceneError("%s: %s index %d out of range [0,%d)" % (where(pos), what, k, n))
        return k

    counts = {"#light_num", "#material_num", "#vertex_num", "#texture_num", "#ray_file_num", "#key_file_num"}
    while i < len(toks):
        word, pos = toks[i]
        i += 1
        if word in counts:
            numbers(1, word, pos)
        elif word == "#camera":
            v = numbers(10, word, pos)
            if scene.camera is None:
                scene.camera = (tuple(v[0:3]), tuple(v[3:6]), tuple(v[6:9]), v[9])
        elif word == "#background":
            v = numbers(3, word, pos)
            scene.background = tuple(v) if not scene.__dict__.get("_bg") else scene.background
            scene._bg = True
        elif word == "#ambient":
            v = numbers(3, word, pos)
            scene.ambient = tuple(v) if not scene.__dict__.get("_amb") else scene.ambient
            scene._amb = True
        elif word == "#light_dir":
            v = numbers(6, word, pos)
            scene.lights.append(("dir", tuple(v[0:3]), norm(tuple(v[3:6]))))
        elif word == "#light_point":
            v = numbers(9, word, pos)
            scene.lights.append(("point", tuple(v[0:3]), tuple(v[3:6]), v[6], v[7], v[8]))
        elif word == "#light_spot":
            v = numbers(14, word, pos)
            light = ["spot", tuple(v[0:3]), tuple(v[3:6]), v[9], v[10], v[11], norm(tuple(v[6:9])), v[12], v[13]]
            spot_raw.append(light)
            scene.lights.append(light)
        elif word == "#material":
            v = []
            while i < len(toks) and not toks[i][0].startswith("!") and len(v) < 19:
                v += numbers(1, word, pos)
            if i >= len(toks) or not toks[i][0].startswith("!"):
                raise SceneError("%s: #material needs its !...! string" % where(pos))
            i += 1
            if len(v) == 18:
                dialect = "v1"
                ke, ka, kd, ks = tuple(v[0:3]), tuple(v[3:6]), tuple(v[6:9]), tuple(v[9:12])
                m = Material(ke, ka, kd, ks, v[12], tuple(v[13:16]), v[16])
                tex = v[17]
            elif len(v) == 16:
                dialect = "v0"
                ka, kd, ks, ke = tuple(v[0:3]), tuple(v[3:6]), tuple(v[6:9]), tuple(v[9:12])
                m = Material(ke, ka, kd, ks, 128.0 * v[12], (v[13],) * 3, v[14])
                tex = v[15]
            else:
                raise SceneError("%s: #material needs 16 (V0) or 18 (V1) numbers, got %d" % (where(pos), len(v)))
            if scene.dialect and scene.dialect != dialect:
                raise SceneError("%s: mixed dialects (V0 and V1 materials)" % where(pos))
            scene.dialect = dialect
            if tex != -1:
                raise SceneError("%s: textures are not supported by minirender" % where(pos))
            scene.materials.append(m)
        elif word == "#vertex":
            v = numbers(8, word, pos)
            n = tuple(v[3:6])
            scene.vertices.append((tuple(v[0:3]), norm(n) if n != (0.0, 0.0, 0.0) else None))
        elif word == "#shape_sphere":
            v = numbers(5, word, pos)
            m = index(v[0], len(scene.materials), "material", pos, scene.dialect == "v0")
            if v[4] < 0:
                raise SceneError("%s: negative sphere radius" % where(pos))
            if v[4] > 0:
                scene.spheres.append((tuple(v[1:4]), v[4], scene.materials[m] if m >= 0 else V0_DEFAULT))
        elif word == "#shape_triangle":
            v = numbers(4, word, pos)
            m = index(v[0], len(scene.materials), "material", pos, scene.dialect == "v0")
            vs = [scene.vertices[index(x, len(scene.vertices), "vertex", pos)] for x in v[1:4]]
            e1, e2 = sub(vs[1][0], vs[0][0]), sub(vs[2][0], vs[0][0])
            c = cross(e1, e2)
            if math.sqrt(dot(c, c)) <= 1e-12 * math.sqrt(dot(e1, e1) * dot(e2, e2)):
                continue  # degenerate: skipped (spec §3.3)
            normals = tuple(x[1] for x in vs) if all(x[1] for x in vs) else None
            scene.triangles.append((vs[0][0], e1, e2, norm(c), normals, scene.materials[m] if m >= 0 else V0_DEFAULT))
        else:
            if word.startswith("#"):
                raise SceneError("%s: directive '%s' is not supported by minirender" % (where(pos), word))
            raise SceneError("%s: expected a directive, got '%s'" % (where(pos), word))
    for light in spot_raw:  # spot exponent p = 128 dor (V0) or dor (V1)
        if scene.dialect == "v0":
            light[8] *= 128.0
    scene.lights = [tuple(x) for x in scene.lights]
    return scene


def default_camera(scene, aspect):
    """Spec §6.3, from the world bounding box."""
    pts = []
    for c, r, _ in scene.spheres:
        pts += [sub(c, (r, r, r)), (c[0] + r, c[1] + r, c[2] + r)]
    for v1, e1, e2, *_ in scene.triangles:
        pts += [v1, (v1[0] + e1[0], v1[1] + e1[1], v1[2] + e1[2]), (v1[0] + e2[0], v1[1] + e2[1], v1[2] + e2[2])]
    ha = math.pi / 6
    if pts:
        lo = tuple(min(p[k] for p in pts) for k in range(3))
        hi = tuple(max(p[k] for p in pts) for k in range(3))
        centre = tuple((lo[k] + hi[k]) / 2 for k in range(3))
        radius = math.sqrt(dot(sub(hi, lo), sub(hi, lo))) / 2
    else:
        centre, radius = (0.0, 0.0, 0.0), 1.0
    if radius == 0:
        radius = 1.0
    phi = min(ha, math.atan(aspect * math.tan(ha)))
    return ((centre[0], centre[1], centre[2] + radius / math.sin(phi)), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0), ha)


# ---------------------------------------------------------------------------------------------
# Rendering (spec §5-§8).


class Renderer:
    def __init__(self, scene, mistakes=(), depth=5, cutoff=0.001):
        self.s = scene
        self.m = set(mistakes)
        self.depth = depth
        self.cutoff = cutoff
        # The objects as flat tuples for speed.
        self.spheres = [(c[0], c[1], c[2], r * r, r, mat) for c, r, mat in scene.spheres]
        self.tris = [(v1[0], v1[1], v1[2], e1[0], e1[1], e1[2], e2[0], e2[1], e2[2], ng, normals, mat)
                     for v1, e1, e2, ng, normals, mat in scene.triangles]

    # Nearest hit with t in (0, tmax): (t, kind, object) or None.
    def nearest(self, ox, oy, oz, dx, dy, dz, tmax=INF):
        best_t, best = tmax, None
        for sp in self.spheres:
            cx, cy, cz = ox - sp[0], oy - sp[1], oz - sp[2]
            b = cx * dx + cy * dy + cz * dz
            c = cx * cx + cy * cy + cz * cz - sp[3]
            disc = b * b - c
            if disc < 0:
                continue
            q = math.sqrt(disc)
            t = -b - q
            if t <= 0:
                t = -b + q
            if 0 < t < best_t:
                best_t, best = t, (0, sp)
        for tr in self.tris:
            e1x, e1y, e1z, e2x, e2y, e2z = tr[3], tr[4], tr[5], tr[6], tr[7], tr[8]
            px, py, pz = dy * e2z - dz * e2y, dz * e2x - dx * e2z, dx * e2y - dy * e2x
            det = e1x * px + e1y * py + e1z * pz
            if det == 0:
                continue
            inv = 1.0 / det
            sx, sy, sz = ox - tr[0], oy - tr[1], oz - tr[2]
            u = (sx * px + sy * py + sz * pz) * inv
            if u < 0 or u > 1:
                continue
            qx, qy, qz = sy * e1z - sz * e1y, sz * e1x - sx * e1z, sx * e1y - sy * e1x
            v = (dx * qx + dy * qy + dz * qz) * inv
            if v < 0 or u + v > 1:
                continue
            t = (e2x * qx + e2y * qy + e2z * qz) * inv
            if 0 < t < best_t:
                best_t, best = t, (1, tr, u, v)
        return (best_t, best) if best else None

    # S_l along a shadow ray of length tmax (spec §7.2).
    def shadow(self, ox, oy, oz, dx, dy, dz, tmax):
        sr = sg = sb = 1.0
        opaque_rule = "opaque-shadows" in self.m
        for sp in self.spheres:
            cx, cy, cz = ox - sp[0], oy - sp[1], oz - sp[2]
            b = cx * dx + cy * dy + cz * dz
            c = cx * cx + cy * cy + cz * cz - sp[3]
            disc = b * b - c
            if disc < 0:
                continue
            q = math.sqrt(disc)
            for t in (-b - q, -b + q):  # both surface crossings count (entry and exit)
                if 0 < t < tmax:
                    tt = sp[5].t
                    if opaque_rule:
                        return (0.0, 0.0, 0.0)
                    sr, sg, sb = sr * tt[0], sg * tt[1], sb * tt[2]
                    if sr == sg == sb == 0:
                        return (0.0, 0.0, 0.0)
        for tr in self.tris:
            e1x, e1y, e1z, e2x, e2y, e2z = tr[3], tr[4], tr[5], tr[6], tr[7], tr[8]
            px, py, pz = dy * e2z - dz * e2y, dz * e2x - dx * e2z, dx * e2y - dy * e2x
            det = e1x * px + e1y * py + e1z * pz
            if det == 0:
                continue
            inv = 1.0 / det
            sx, sy, sz = ox - tr[0], oy - tr[1], oz - tr[2]
            u = (sx * px + sy * py + sz * pz) * inv
            if u < 0 or u > 1:
                continue
            qx, qy, qz = sy * e1z - sz * e1y, sz * e1x - sx * e1z, sx * e1y - sy * e1x
            v = (dx * qx + dy * qy + dz * qz) * inv
            if v < 0 or u + v > 1:
                continue
            t = (e2x * qx + e2y * qy + e2z * qz) * inv
            if 0 < t < tmax:
                tt = tr[11].t
                if opaque_rule:
                    return (0.0, 0.0, 0.0)
                sr, sg, sb = sr * tt[0], sg * tt[1], sb * tt[2]
                if sr == sg == sb == 0:
                    return (0.0, 0.0, 0.0)
        return (sr, sg, sb)

    def spawn(self, p, ng, direction):
        """Origin of a secondary ray (spec §7.5): P pushed to the side of n_g the ray leaves by.
        delta is relative to the size of P's coordinates (enough for small scenes in doubles)."""
        if "no-offset" in self.m:
            return p
        delta = 1e-7 * (1.0 + max(abs(p[0]), abs(p[1]), abs(p[2])))
        if dot(direction, ng) < 0:
            delta = -delta
        return (p[0] + delta * ng[0], p[1] + delta * ng[1], p[2] + delta * ng[2])

    def trace(self, o, d, depth, w):
        hit = self.nearest(o[0], o[1], o[2], d[0], d[1], d[2])
        if hit is None:
            return self.s.background
        t, h = hit
        p = (o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2])
        if h[0] == 0:
            sp = h[1]
            mat = sp[5]
            ng = ((p[0] - sp[0]) / sp[4], (p[1] - sp[1]) / sp[4], (p[2] - sp[2]) / sp[4])
            ns = ng
        else:
            tr, u, v = h[1], h[2], h[3]
            mat = tr[11]
            ng = tr[9]
            ns = ng
            if tr[10]:
                n1, n2, n3 = tr[10]
                w1 = 1.0 - u - v
                s_ = (w1 * n1[0] + u * n2[0] + v * n3[0], w1 * n1[1] + u * n2[1] + v * n3[1],
                      w1 * n1[2] + u * n2[2] + v * n3[2])
                if s_ != (0.0, 0.0, 0.0):
                    ns = norm(s_)
        dng = dot(d, ng)
        sgn = -1.0 if (dng > 0 and "one-sided" not in self.m) else 1.0
        n = (sgn * ns[0], sgn * ns[1], sgn * ns[2])
        m = self.m
        cr = cg = cb = 0.0
        if "no-emissive" not in m:
            cr, cg, cb = mat.ke
        if "no-ambient" not in m:
            a = self.s.ambient
            cr, cg, cb = cr + mat.ka[0] * a[0], cg + mat.ka[1] * a[1], cb + mat.ka[2] * a[2]
        dn = dot(d, n)
        rv = (d[0] - 2 * dn * n[0], d[1] - 2 * dn * n[1], d[2] - 2 * dn * n[2])  # R_v, also the mirror ray
        for light in self.s.lights:
            kind, col = light[0], light[1]
            if kind == "dir":
                L = light[2] if "light-dir-reversed" in m else (-light[2][0], -light[2][1], -light[2][2])
                dist = INF
                ir, ig, ib = col
            else:
                to = sub(light[2], p)
                dist = math.sqrt(dot(to, to))
                if dist == 0:
                    continue
                L = (to[0] / dist, to[1] / dist, to[2] / dist)
                factor = 1.0
                if kind == "spot":
                    axis, cutoff, pexp = light[6], light[7], light[8]
                    cos_a = -dot(axis, L)
                    limit = cutoff / 2 if "spot-cutoff-full-angle" in m else cutoff
                    if math.acos(max(-1.0, min(1.0, cos_a))) > limit:
                        continue
                    if pexp != 0 and "spot-no-dropoff" not in m:
                        factor = max(0.0, cos_a) ** pexp
                if "no-attenuation" not in m:
                    den = light[3] + light[4] * dist + light[5] * dist * dist
                    if not (den > 0) or not math.isfinite(den):
                        continue
                    factor /= den
                ir, ig, ib = col[0] * factor, col[1] * factor, col[2] * factor
                if "shadow-past-light" in m:
                    dist = INF
            nl = dot(n, L)
            if nl <= 0 and "no-diffuse-clamp" not in m:
                continue
            if "no-shadows" in m:
                sr = sg = sb = 1.0
            else:
                so = self.spawn(p, ng, L)
                sr, sg, sb = self.shadow(so[0], so[1], so[2], L[0], L[1], L[2], dist)
                if sr == sg == sb == 0:
                    continue
            spec = 0.0
            if "no-specular" not in m:
                if "blinn" in m:
                    hv = norm((L[0] - d[0], L[1] - d[1], L[2] - d[2]))
                    x = dot(n, hv)
                else:
                    x = dot(rv, L)
                if x > 0:
                    spec = x ** mat.e
            kd, ks = mat.kd, mat.ks
            cr += sr * ir * (kd[0] * nl + ks[0] * spec)
            cg += sg * ig * (kd[1] * nl + ks[1] * spec)
            cb += sb * ib * (kd[2] * nl + ks[2] * spec)
        child_depth = depth - 1
        if child_depth >= (0 if "depth-off-by-one" in m else 1):
            cutoff = 0.0 if "no-cutoff" in m else self.cutoff
            if mat.has_ks and "no-reflection" not in m:
                ks = mat.ks
                cw = (w[0] * ks[0], w[1] * ks[1], w[2] * ks[2])
                if max(cw) >= cutoff:
                    c = self.trace(self.spawn(p, ng, rv), rv, child_depth, cw)
                    cr, cg, cb = cr + ks[0] * c[0], cg + ks[1] * c[1], cb + ks[2] * c[2]
            if mat.has_t and "no-refraction" not in m:
                tt = mat.t
                cw = (w[0] * tt[0], w[1] * tt[1], w[2] * tt[2])
                if max(cw) >= cutoff:
                    entering = dng < 0
                    if "ior-inverted" in m:
                        entering = not entering
                    eta = 1.0 / mat.refind if entering else mat.refind
                    c = max(0.0, min(1.0, -dn))
                    k = 1.0 - eta * eta * (1.0 - c * c)
                    if k >= 0:
                        f = eta * c - math.sqrt(k)
                        rd = norm((eta * d[0] + f * n[0], eta * d[1] + f * n[1], eta * d[2] + f * n[2]))
                        c = self.trace(self.spawn(p, ng, rd), rd, child_depth, cw)
                        cr, cg, cb = cr + tt[0] * c[0], cg + tt[1] * c[1], cb + tt[2] * c[2]
        return (cr, cg, cb)

    def render(self, width, height):
        """Linear colours, rows top first (spec §6.2, one sample at the pixel centre)."""
        cam = self.s.camera
        if cam is None:
            print("minirender: warning: no #camera: using the default camera", file=sys.stderr)
            cam = default_camera(self.s, width / height)
        p, d, up, ha = cam
        f = norm(d)
        r = norm(cross(f, up))
        u = cross(r, f)
        aspect = width / height
        if "full-angle" in self.m:
            tan_h = math.tan(ha / 2)
            tan_w = aspect * tan_h
        elif "angle-on-width" in self.m:
            tan_w = math.tan(ha)
            tan_h = tan_w / aspect
        else:
            tan_h = math.tan(ha)
            tan_w = aspect * tan_h
        rows = []
        one = (1.0, 1.0, 1.0)
        for j in range(height):
            y = (1 - 2 * (j + 0.5) / height) * tan_h
            row = []
            for i in range(width):
                x = (2 * (i + 0.5) / width - 1) * tan_w
                ray = norm((f[0] + x * r[0] + y * u[0], f[1] + x * r[1] + y * u[1], f[2] + x * r[2] + y * u[2]))
                row.append(self.trace(p, ray, self.depth, one))
            rows.append(row)
        return rows


# ---------------------------------------------------------------------------------------------
# Output (spec §9).


def to_bytes(rows, mistakes=()):
    """8-bit rows (bytes objects, RGB), with the output mistakes applied."""
    gamma, wrap, bgr = "gamma" in mistakes, "wrap-overflow" in mistakes, "bgr" in mistakes
    out = []
    for row in rows:
        line = bytearray()
        for px in row:
            vals = []
            for c in px:
                if not math.isfinite(c):
                    c = 0.0
                if wrap:
                    vals.append(int(255 * c) % 256)
                    continue
                c = min(1.0, max(0.0, c))
                if gamma:
                    c = c ** (1 / 2.2)
                vals.append(int(math.floor(255 * c + 0.5)))
            if bgr:
                vals.reverse()
            line += bytes(vals)
        out.append(bytes(line))
    if "flip-vertical" in mistakes:
        out.reverse()
    return out


def write_image(path, byte_rows):
    height = len(byte_rows)
    width = len(byte_rows[0]) // 3 if height else 0
    if path.lower().endswith(".ppm"):
        data = b"P6\n%d %d\n255\n" % (width, height) + b"".join(byte_rows)
    elif path.lower().endswith(".png"):
        def chunk(kind, body):
            return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
        raw = b"".join(b"\x00" + r for r in byte_rows)
        data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
    else:
        raise SceneError("output '%s': only .png and .ppm are written" % path)
    tmp = path + ".part"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def read_image(path):
    """Reads back a PNG (8-bit RGB, no interlace, as written above or by raytrace) or a PPM (P6):
    (width, height, list of byte rows)."""
    with open(path, "rb") as f:
        data = f.read()
    if data.startswith(b"P6"):
        parts = data.split(maxsplit=4)
        w, h = int(parts[1]), int(parts[2])
        body = parts[4][: w * h * 3]
        return w, h, [body[k * w * 3:(k + 1) * w * 3] for k in range(h)]
    if not data.startswith(b"\x89PNG"):
        raise ValueError("%s: not a PNG or PPM" % path)
    pos, idat = 8, b""
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            w, h, bits, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if bits != 8 or ctype not in (2, 6) or interlace:
                raise ValueError("%s: only 8-bit RGB/RGBA PNG" % path)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for k in range(h):
        ftype = raw[k * (stride + 1)]
        cur = bytearray(raw[k * (stride + 1) + 1:(k + 1) * (stride + 1)])
        for x in range(stride):
            a = cur[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if ftype == 1:
                cur[x] = (cur[x] + a) & 255
            elif ftype == 2:
                cur[x] = (cur[x] + b) & 255
            elif ftype == 3:
                cur[x] = (cur[x] + (a + b) // 2) & 255
            elif ftype == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (cur[x] + pr) & 255
        prev = cur
        rows.append(bytes(cur) if bpp == 3 else bytes(v for x in range(w) for v in cur[x * 4:x * 4 + 3]))
    return w, h, rows


def check_mistakes(names):
    for name in names:
        if name in NOT_IMPLEMENTED:
            raise SceneError("mistake '%s' is not implemented by minirender (no textures)" % name)
        if name not in MISTAKES:
            raise SceneError("unknown mistake '%s' (see --list-mistakes)" % name)
    if len(names) > 2:
        raise SceneError("at most 2 --mistake flags")
    if len(set(names)) != len(names):
        raise SceneError("a mistake given twice")


def render_file(scene_path, width, height, mistakes=(), depth=5, cutoff=0.001):
    """Linear rows of a scene file with the given mistakes (output mistakes are not applied)."""
    return Renderer(parse(scene_path), mistakes, depth, cutoff).render(width, height)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", nargs="?")
    ap.add_argument("output", nargs="?")
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--depth", type=int, default=5)
    ap.add_argument("--cutoff", type=float, default=0.001)
    ap.add_argument("--mistake", action="append", default=[], metavar="NAME")
    ap.add_argument("--list-mistakes", action="store_true")
    args = ap.parse_args(argv)
    if args.list_mistakes:
        for name, what in MISTAKES.items():
            print("%-24s %s" % (name, what))
        return 0
    if not args.scene or not args.output:
        ap.error("SCENE and OUTPUT are required")
    if args.width < 1 or args.height < 1 or args.depth < 1 or args.cutoff < 0:
        ap.error("--width, --height and --depth must be >= 1, --cutoff >= 0")
    try:
        check_mistakes(args.mistake)
        if not args.output.lower().endswith((".png", ".ppm")):
            raise SceneError("output '%s': only .png and .ppm are written" % args.output)
        rows = render_file(args.scene, args.width, args.height, args.mistake, args.depth, args.cutoff)
        write_image(args.output, to_bytes(rows, args.mistake))
    except SceneError as e:
        print("minirender: error: %s" % e, file=sys.stderr)
        return 2
    except OSError as e:
        print("minirender: error: %s" % e, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
