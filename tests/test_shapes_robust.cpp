// Each shape's intersection at the extremes, against long-double oracles: tiny, huge and far
// spheres, a far mesh, grazing and tangent rays on every kind, rays through cylinder rims and
// cone apexes, and axis-parallel rays on a box's slab planes.
//
// Tangent convention (what "agrees with the oracle" means): surfaces are closed sets. A ray whose
// exact (long-double) distance to a surface is zero -- a tangent ray, a ray through a cylinder's
// rim or a cone's apex, an axis-parallel ray lying in a box's slab plane -- hits. Elsewhere hit or
// miss must equal the oracle's unless the oracle's own margin (chord length, or distance of
// closest approach minus radius) is below kBand relative to the shape's size: inside that band of
// double rounding either answer is accepted, but never NaN. A tangent ray is reported as one hit
// (the double root once). A ray lying in a triangle's plane does not hit it (zero projected area:
// the determinant of Woop, Benthin and Wald's test is zero).
#include <algorithm>
#include <vector>

#include "extreme_util.h"

namespace rt {
namespace {

using namespace test;  // the helpers of extreme_util.h
using LD = long double;

constexpr double kBand = 1e-9;  // the band of double rounding of the convention above

// ---------------------------------------------------------------------------------------------
// Tiny, huge and far spheres against a long-double oracle.

struct OracleHit {
    bool hit = false;
    LD t = 0;
    LD margin = 0;  // (r - closest approach) / r: how far from the silhouette
};

OracleHit sphere_oracle(const Vec3& centre, double radius, const Ray& ray) {
    LD f[3], d[3];
    for (int i = 0; i < 3; ++i) f[i] = LD(ray.o[i]) - LD(centre[i]), d[i] = LD(ray.d[i]);
    const LD a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const LD b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
    LD l2 = 0;
    for (int i = 0; i < 3; ++i) {
        const LD li = f[i] - (b / a) * d[i];
        l2 += li * li;
    }
    const LD r = radius, l = std::sqrt(l2);
    OracleHit o;
    o.margin = (r - l) / r;
    if (l > r) return o;
    const LD half_chord = std::sqrt((r - l) * (r + l) / a);
    const LD tc = -b / a;
    o.t = tc - half_chord > 0 ? tc - half_chord : tc + half_chord;
    o.hit = o.t > 0;
    return o;
}

struct SphereStats {
    int rays = 0, hits = 0, mismatches = 0;
    double max_rel = 0;
};

// Rays from `eye` through a square of half size 1.3 r (seen from the eye) around the sphere.
SphereStats check_sphere(const Vec3& centre, double radius, const Vec3& eye, int res,
                         double spread = 1.3) {
    const RenderScene scene = test::compile(std::string(kOpaque) + "#shape_sphere 0 " +
                                            vec(centre) + " " + num(radius) + "\n");
    const Vec3 w = glm::normalize(centre - eye);
    const Vec3 u =
        glm::normalize(glm::cross(w, std::abs(w.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0)));
    const Vec3 v = glm::cross(u, w);
    SphereStats s;
    for (int j = 0; j < res; ++j)
        for (int i = 0; i < res; ++i) {
            const double x = spread * radius * (2.0 * (i + 0.5) / res - 1);
            const double y = spread * radius * (2.0 * (j + 0.5) / res - 1);
            const Ray r{eye, glm::normalize(centre + x * u + y * v - eye)};
            const OracleHit o = sphere_oracle(centre, radius, r);
            Hit h;
            const bool hit = intersect(scene, r, {0, kInf}, &h);
            ++s.rays;
            EXPECT_FALSE(std::isnan(h.t));
            if (std::abs(static_cast<double>(o.margin)) < 1e-6) continue;  // silhouette
            if (hit != o.hit) {
                ++s.mismatches;
                continue;
            }
            if (!hit) continue;
            ++s.hits;
            s.max_rel = std::max(s.max_rel, static_cast<double>(std::abs((LD(h.t) - o.t) / o.t)));
        }
    return s;
}

// A small mesh far from the origin: its float copy is relative to the centre of its bounds, so
// hit distances resolve the mesh, not its distance from the origin (stored absolutely, a mesh at
// 1e4 snaps to a float grid of 1e-3: relative distance errors of 1e-3 seen from 1 unit away).
TEST(ShapesRobust, FarMeshHitDistancesResolveTheMesh) {
    for (const double dist : {1e4, 1e6}) {
        const Vec3 c = dist * glm::normalize(Vec3(1, 0.7, 0.4)) + Vec3(0.123456789, 0, 0);
        std::string text = kOpaque;
        const Vec3 p0 = c + Vec3(-1, -1, 0.01), p1 = c + Vec3(1, -1, -0.02),
                   p2 = c + Vec3(0.1, 1, 0.015);
        text += vertex(p0) + vertex(p1) + vertex(p2) + triangle(0, 1, 2);
        const RenderScene scene = test::compile(text);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-0.4, 0.4);
        double worst = 0;
        int hits = 0;
        for (int i = 0; i < 2000; ++i) {
            const Vec3 eye = c + Vec3(u(rng), u(rng), 1.5);
            const Vec3 target = c + Vec3(0.75 * u(rng), 0.5 * u(rng) - 0.4, 0);  // inside
            const Ray r{eye, glm::normalize(target - eye)};
            Hit hit;
            if (!intersect(scene, r, {0, kInf}, &hit)) continue;
            ++hits;
            // The double oracle: the ray against the triangle's plane.
            const Vec3 n = glm::cross(p1 - p0, p2 - p0);
            const double t = glm::dot(n, p0 - r.o) / glm::dot(n, r.d);
            worst = std::max(worst, std::abs(hit.t - t) / t);
        }
        std::printf("[ far mesh ] at %g: %d hits, worst relative distance error %.3g\n", dist, hits,
                    worst);
        EXPECT_EQ(hits, 2000);
        EXPECT_LT(worst, 1e-5);
    }
}

TEST(ShapesRobust, TinyHugeAndFarSpheresMatchALongDoubleOracle) {
    struct Case {
        const char* name;
        Vec3 centre;
        double radius;
        Vec3 eye;
        double spread;
    };
    const Vec3 far_dir = glm::normalize(Vec3(0.3, 0.5, -0.8));
    const Case cases[] = {
        {"r=1e-3 at 1e3", 1e3 * far_dir, 1e-3, Vec3(0.0), 1.3},
        {"r=1e-3 at 1e3, eye 1e3 off", 1e3 * far_dir + Vec3(1e3, 0, 0), 1e-3, Vec3(1e3, 0, 0), 1.3},
        {"r=1e4 ground", Vec3(0, -1e4, 0), 1e4, Vec3(3.3, 1.7, -2.1), 1.02},
        {"r=1 at 1e6, eye 10 away", Vec3(1e6, -3e5, 2e5), 1, Vec3(1e6 + 6, -3e5 + 5, 2e5 + 5.5),
         1.3},
        {"r=1 at 1e6, eye at 0", Vec3(1e6, -3e5, 2e5), 1, Vec3(0.0), 1.3},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const SphereStats s = check_sphere(c.centre, c.radius, c.eye, 160, c.spread);
        std::printf("[ sphere ] %-28s %d rays, %d hits, %d coverage mismatches, max rel err %.3g\n",
                    c.name, s.rays, s.hits, s.mismatches, s.max_rel);
        EXPECT_EQ(s.mismatches, 0);
        EXPECT_GT(s.hits, s.rays / 4);
        EXPECT_LE(s.max_rel, 1e-5);
    }
}

// ---------------------------------------------------------------------------------------------
// Grazing and tangent rays against long-double oracles (the convention is at the top).

struct Span {
    bool hit = false;
    LD lo = 0, hi = 0;  // the line's parameter interval inside the solid
};
Span intersect_spans(Span a, LD lo, LD hi) {
    if (!a.hit) return a;
    a.lo = std::max(a.lo, lo);
    a.hi = std::min(a.hi, hi);
    a.hit = a.lo <= a.hi;
    return a;
}
// {t : lo <= o + t d <= hi} along one axis.
Span slab(LD o, LD d, LD lo, LD hi) {
    if (d == 0) return {o >= lo && o <= hi, -1e300L, 1e300L};
    LD a = (lo - o) / d, b = (hi - o) / d;
    if (a > b) std::swap(a, b);
    return {true, a, b};
}
// The solid, scaled by `s` about its centre (s = 1 +- kBand: the band of the convention).
Span oracle(const Box& b, const Ray& r, LD s) {
    Span sp{true, -1e300L, 1e300L};
    for (int a = 0; a < 3; ++a) {
        const Span k = slab(r.o[a], r.d[a], LD(b.centre[a]) - s * LD(b.half[a]),
                            LD(b.centre[a]) + s * LD(b.half[a]));
        if (!k.hit) return {};
        sp = intersect_spans(sp, k.lo, k.hi);
    }
    return sp;
}
// {t : q(t) = a t^2 + 2 b t + c <= 0} as up to two spans.
int quadric_spans(LD a, LD b, LD c, Span out[2]) {
    if (a == 0) {
        if (b == 0) return c <= 0 ? (out[0] = {true, -1e300L, 1e300L}, 1) : 0;
        const LD t = -c / (2 * b);
        out[0] = b > 0 ? Span{true, -1e300L, t} : Span{true, t, 1e300L};
        return 1;
    }
    const LD disc = b * b - a * c;
    if (disc < 0) return a < 0 ? (out[0] = {true, -1e300L, 1e300L}, 1) : 0;
    const LD sq = std::sqrt(disc);
    LD t0 = (-b - sq) / a, t1 = (-b + sq) / a;
    if (t0 > t1) std::swap(t0, t1);
    if (a > 0) {
        out[0] = {true, t0, t1};
        return 1;
    }
    out[0] = {true, -1e300L, t0};
    out[1] = {true, t1, 1e300L};
    return 2;
}
Span oracle(const Cylinder& cy, const Ray& r, LD s) {
    LD f[3], d[3];
    for (int i = 0; i < 3; ++i) f[i] = LD(r.o[i]) - LD(cy.centre[i]), d[i] = r.d[i];
    const LD rr = s * LD(cy.radius), h2 = s * LD(cy.height) / 2;
    Span q[2];
    const int n = quadric_spans(d[0] * d[0] + d[2] * d[2], f[0] * d[0] + f[2] * d[2],
                                f[0] * f[0] + f[2] * f[2] - rr * rr, q);
    if (n == 0) return {};
    const Span y = slab(f[1], d[1], -h2, h2);
    if (!y.hit) return {};
    return intersect_spans(q[0], y.lo, y.hi);
}
Span oracle(const Cone& co, const Ray& r, LD s) {
    const LD h = s * LD(co.height), k = LD(co.radius) / LD(co.height);
    LD f[3], d[3];
    for (int i = 0; i < 3; ++i) f[i] = LD(r.o[i]) - LD(co.centre[i]), d[i] = r.d[i];
    f[1] -= h / 2;  // relative to the apex
    Span q[2];
    const int n = quadric_spans(d[0] * d[0] + d[2] * d[2] - k * k * d[1] * d[1],
                                f[0] * d[0] + f[2] * d[2] - k * k * f[1] * d[1],
                                f[0] * f[0] + f[2] * f[2] - k * k * f[1] * f[1], q);
    const Span y = slab(f[1], d[1], -h, 0);
    Span out;
    for (int i = 0; i < n && y.hit; ++i) {
        const Span p = intersect_spans(q[i], y.lo, y.hi);
        if (!p.hit) continue;
        out = out.hit ? Span{true, std::min(out.lo, p.lo), std::max(out.hi, p.hi)} : p;
    }
    return out;
}

struct GrazeStats {
    int rays = 0, must_hit = 0, must_miss = 0, band = 0, disagree = 0, nan = 0;
    double max_rel = 0;
};

// One ray through a one-shape scene against the oracle: must hit when the solid shrunk by kBand
// is hit ahead of the origin, must miss when the solid grown by kBand is missed (or is behind).
template <class Shape>
void check_graze(const RenderScene& scene, const Shape& shape, const Ray& r, GrazeStats& st) {
    ++st.rays;
    Hit h;
    const bool hit = intersect(scene, r, {0, kInf}, &h);
    if (hit && !std::isfinite(h.t)) ++st.nan;
    const Span in = oracle(shape, r, 1 - LD(kBand)), out = oracle(shape, r, 1 + LD(kBand));
    const Span exact = oracle(shape, r, 1);
    if (in.hit && in.hi > 0 && (in.lo > 0 || in.hi > 0)) {
        ++st.must_hit;
        if (!hit) {
            ++st.disagree;
            return;
        }
        // The nearest surface crossing ahead: entry, or exit when starting inside.
        const LD t_ref = exact.lo > 0 ? exact.lo : exact.hi;
        st.max_rel = std::max(st.max_rel, static_cast<double>(std::abs((h.t - t_ref) / t_ref)));
    } else if (!out.hit || out.hi <= 0) {
        ++st.must_miss;
        if (hit) ++st.disagree;
    } else {
        ++st.band;
    }
}

// d = cos(theta) T - sin(theta) n through P, from 1 unit before it; theta = +-1e-6.
Ray grazing_ray(const Vec3& p, const Vec3& n, const Vec3& t_dir, double theta) {
    const Vec3 d = std::cos(theta) * t_dir - std::sin(theta) * n;
    return {p - d, d};
}
Vec3 random_tangent(std::mt19937& rng, const Vec3& n) {
    const Vec3 v = random_unit(rng);
    return glm::normalize(v - glm::dot(v, n) * n);
}

TEST(ShapesRobust, GrazingRaysAgreeWithALongDoubleOracle) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1), u01(0, 1);
    const double theta = 1e-6;
    auto report = [](const char* name, const GrazeStats& st) {
        std::printf(
            "[ graze ] %-14s %d rays: %d must hit, %d must miss, %d in the band; %d "
            "disagree, %d NaN; max rel t err %.3g\n",
            name, st.rays, st.must_hit, st.must_miss, st.band, st.disagree, st.nan, st.max_rel);
        EXPECT_EQ(st.disagree, 0) << name;
        EXPECT_EQ(st.nan, 0) << name;
        EXPECT_GT(st.must_hit, st.rays / 5) << name;
        EXPECT_GT(st.must_miss, st.rays / 20) << name;
        EXPECT_LE(st.max_rel, 1e-6) << name;
    };
    const int kRays = 20000;
    {
        const Box b{{0.3, -0.2, 0.1}, {1.0, 0.5, 0.75}};
        const RenderScene scene = test::compile(std::string(kOpaque) + "#shape_box 0 " +
                                                vec(b.centre) + " " + vec(2.0 * b.half) + "\n");
        GrazeStats st;
        for (int i = 0; i < kRays; ++i) {
            const int axis = i % 3;
            const double side = (i / 3) % 2 ? 1.0 : -1.0;
            Vec3 n(0.0), p = b.centre;
            n[axis] = side;
            for (int a = 0; a < 3; ++a)
                p[a] += a == axis ? side * b.half[a] : 1.2 * u(rng) * b.half[a];
            check_graze(scene, b,
                        grazing_ray(p, n, random_tangent(rng, n), u(rng) < 0 ? theta : -theta), st);
        }
        report("box faces", st);
    }
    {
        const Cylinder c{{0.3, -0.2, 0.1}, 0.8, 1.7};
        const RenderScene scene =
            test::compile(std::string(kOpaque) + "#shape_cylinder 0 " + vec(c.centre) + " " +
                          num(c.radius) + " " + num(c.height) + "\n");
        GrazeStats st;
        for (int i = 0; i < kRays; ++i) {
            const double phi = 2 * kPi * u01(rng);
            Vec3 n, p;
            if (i % 3) {  // side
                n = Vec3(std::cos(phi), 0, std::sin(phi));
                p = c.centre + c.radius * n + Vec3(0, 0.6 * c.height * u(rng), 0);
            } else {  // caps
                const double side = u(rng) < 0 ? 1.0 : -1.0;
                n = Vec3(0, side, 0);
                p = c.centre + Vec3(0, side * 0.5 * c.height, 0) +
                    1.2 * c.radius * std::sqrt(u01(rng)) * Vec3(std::cos(phi), 0, std::sin(phi));
            }
            check_graze(scene, c,
                        grazing_ray(p, n, random_tangent(rng, n), u(rng) < 0 ? theta : -theta), st);
        }
        report("cylinder", st);
    }
    {
        const Cone c{{0.3, -0.2, 0.1}, 0.8, 1.7};
        const RenderScene scene =
            test::compile(std::string(kOpaque) + "#shape_cone 0 " + vec(c.centre) + " " +
                          num(c.radius) + " " + num(c.height) + "\n");
        GrazeStats st;
        for (int i = 0; i < kRays; ++i) {
            const double phi = 2 * kPi * u01(rng);
            const Vec3 radial(std::cos(phi), 0, std::sin(phi));
            Vec3 n, p;
            if (i % 3) {  // side, from near the apex to the base
                const double y = c.height * (0.5 - 0.9 * u01(rng));
                p = c.centre + Vec3(0, y, 0) + c.radius * (0.5 * c.height - y) / c.height * radial;
                n = glm::normalize(c.height * radial + Vec3(0, c.radius, 0));
            } else {  // base
                n = Vec3(0, -1, 0);
                p = c.centre - Vec3(0, 0.5 * c.height, 0) +
                    1.2 * c.radius * std::sqrt(u01(rng)) * radial;
            }
            check_graze(scene, c,
                        grazing_ray(p, n, random_tangent(rng, n), u(rng) < 0 ? theta : -theta), st);
        }
        report("cone", st);
    }
}

// A plane of two float triangles: the renderer tests the float copy of the vertices from a float
// origin, so a grazing hit moves along the plane by (origin rounding) / theta (about 0.06 here);
// hit and miss are asserted with a margin of 1 around the edges of a 20 x 20 plane.
TEST(ShapesRobust, GrazingRaysOnATrianglePlane) {
    const Mat4 tilt = glm::rotate(Mat4(1.0), 0.4, glm::normalize(Vec3(1, 0.2, 0.3)));
    auto world = [&](const Vec3& p) { return Vec3(tilt * glm::dvec4(p, 1)); };
    const double h = 10;
    const RenderScene scene =
        test::compile(std::string(kOpaque) + vertex(world({-h, 0, -h})) +
                      vertex(world({h, 0, -h})) + vertex(world({h, 0, h})) +
                      vertex(world({-h, 0, h})) + triangle(0, 2, 1) + triangle(0, 3, 2));
    const Vec3 n = Vec3(tilt * glm::dvec4(0, 1, 0, 0));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    int hits_expected = 0, misses_expected = 0, wrong = 0;
    for (int i = 0; i < 20000; ++i) {
        const bool inside = i % 2 == 0;
        // Inside: |x|, |z| <= 9 and the ray descends onto the plane. Outside: the point lies
        // beyond an edge by at least 1 and the ray moves away from the plane's square.
        Vec3 local(9 * u(rng), 0, 9 * u(rng));
        Vec3 t_local = glm::normalize(Vec3(u(rng), 0, u(rng)));
        if (!inside) {
            local.x = std::copysign(11 + 5 * std::abs(u(rng)), u(rng));
            if (t_local.x * local.x < 0) t_local.x = -t_local.x;
        }
        const Vec3 t_dir = glm::normalize(Vec3(tilt * glm::dvec4(t_local, 0)));
        const Vec3 side = u(rng) < 0 ? n : -n;  // from either side
        const Ray r = grazing_ray(world(local), side, t_dir, 1e-6);
        Hit hit;
        const bool got = intersect(scene, r, {0, kInf}, &hit);
        (inside ? hits_expected : misses_expected)++;
        if (got != inside || (got && !std::isfinite(hit.t))) ++wrong;
    }
    std::printf("[ graze ] triangle plane %d rays that must hit, %d that must miss: %d wrong\n",
                hits_expected, misses_expected, wrong);
    EXPECT_EQ(wrong, 0);
    // Rays lying in the plane of an axis-aligned pair (through its interior, along an edge and
    // the shared diagonal's line) do not hit it (convention above) and give no NaN.
    const RenderScene flat = test::compile(
        std::string(kOpaque) + vertex({-1, -1, 0}) + vertex({1, -1, 0}) + vertex({1, 1, 0}) +
        vertex({-1, 1, 0}) + triangle(0, 2, 1) + triangle(0, 3, 2));
    int in_plane_hits = 0;
    for (const Ray& r : {Ray{{-5, 0.3, 0}, {1, 0, 0}}, Ray{{-5, -1, 0}, {1, 0, 0}},
                         Ray{{-5, -5, 0}, {1, 1, 0}}, Ray{{0.2, -5, 0}, {0, 1, 0}}}) {
        Hit hit;
        if (intersect(flat, r, {0, kInf}, &hit)) ++in_plane_hits;
    }
    EXPECT_EQ(in_plane_hits, 0);
}

// Exact touches: by the convention above they hit, at the touching point.
TEST(ShapesRobust, RaysThroughCylinderRimsAndConeApexesHit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1), u01(0, 1);
    // Cylinder rim: rays into the solid through a rim point enter there and leave once more.
    {
        const Cylinder c{{0.25, -0.5, 0.125}, 0.75, 1.5};
        const RenderScene scene = test::compile(std::string(kHalf) + "#shape_cylinder 0 " +
                                                vec(c.centre) + " 0.75 1.5\n");
        int rays = 0, wrong = 0;
        double max_rel = 0;
        for (int i = 0; i < 20000; ++i) {
            const double phi = 2 * kPi * u01(rng), side = i % 2 ? 1.0 : -1.0;
            const Vec3 radial(std::cos(phi), 0, std::sin(phi));
            const Vec3 p = c.centre + c.radius * radial + Vec3(0, side * 0.5 * c.height, 0);
            Vec3 d = random_unit(rng);
            if (glm::dot(d, radial) > -0.05 || d.y * side > -0.05) continue;
            const double len = 1 + 3 * u01(rng);
            const Ray r{p - len * d, d};
            ++rays;
            Hit h;
            const bool hit = intersect(scene, r, {0, kInf}, &h);
            if (!hit || transmittance(scene, r, kInf) != Vec3(0.25)) {
                ++wrong;
                continue;
            }
            max_rel = std::max(max_rel, std::abs(h.t - len) / len);
        }
        std::printf(
            "[ touch ] cylinder rim: %d rays into the solid, %d wrong, max rel t err %.3g\n", rays,
            wrong, max_rel);
        EXPECT_GT(rays, 1000);
        EXPECT_EQ(wrong, 0);
        EXPECT_LE(max_rel, 1e-9);
        // Tangent to the rim circle in the cap plane, and tangent to the side: exact in double.
        int tangent_misses = 0;
        for (int k = 0; k < 4; ++k) {
            const Vec3 radial = k % 2 ? Vec3(0, 0, k < 2 ? 1 : -1) : Vec3(k < 2 ? 1 : -1, 0, 0);
            const Vec3 along = Vec3(-radial.z, 0, radial.x);
            for (const double y : {0.5 * c.height, -0.5 * c.height, 0.3}) {
                const Vec3 p = c.centre + c.radius * radial + Vec3(0, y, 0);
                Hit h;
                if (!intersect(scene, {p - 2.0 * along, along}, {0, kInf}, &h)) ++tangent_misses;
            }
        }
        std::printf("[ touch ] cylinder: 12 exactly tangent rays, %d misses\n", tangent_misses);
        EXPECT_EQ(tangent_misses, 0);
    }
    // Cone apex: every ray through the apex hits it (into the solid, out of it, or touching).
    {
        const Cone c{{0.25, -0.5, 0.125}, 0.75, 1.5};
        const Vec3 apex = c.centre + Vec3(0, 0.75, 0);
        const RenderScene scene =
            test::compile(std::string(kHalf) + "#shape_cone 0 " + vec(c.centre) + " 0.75 1.5\n");
        const GeometrySet& set = scene.sets[0];
        int rays = 0, misses = 0, far = 0, into = 0, into_wrong = 0;
        for (int i = 0; i < 20000; ++i) {
            const Vec3 d = random_unit(rng);
            const double len = 1 + 3 * u01(rng);
            const Ray r{apex - len * d, d};
            ++rays;
            const ShapeHits hs = intersect_primitive(set, 0, r, {0, kInf});
            if (hs.count == 0) {
                ++misses;
                continue;
            }
            bool at_apex = false;
            for (int k = 0; k < hs.count; ++k) at_apex |= std::abs(hs.t[k] - len) <= 1e-9 * len;
            if (!at_apex) ++far;
            // Downward inside the cone's half angle (0.75 / 1.5): apex entry, then one exit.
            const double rho = std::sqrt(d.x * d.x + d.z * d.z);
            if (d.y < 0 && rho < 0.45 * -d.y) {
                ++into;
                if (hs.count != 2 || std::abs(hs.t[0] - len) > 1e-9 * len) ++into_wrong;
            }
        }
        std::printf(
            "[ touch ] cone apex: %d rays through it, %d misses, %d hits away from it; %d "
            "into the solid, %d without apex entry and one exit\n",
            rays, misses, far, into, into_wrong);
        EXPECT_EQ(misses, 0);
        EXPECT_EQ(far, 0);
        EXPECT_GT(into, 100);
        EXPECT_EQ(into_wrong, 0);
    }
}

// Axis-parallel rays lying in a box's slab planes (faces and edges) hit; one ulp out, they miss.
// `through_scene` false: the box's own test; true: the scene query (BVH first).
int slab_plane_errors(bool through_scene, int* rays) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> u(-1, 1);
    const Box b{{0.25, -0.5, 0.125}, {0.5, 0.25, 0.75}};
    const RenderScene scene = test::compile(std::string(kOpaque) + "#shape_box 0 " + vec(b.centre) +
                                            " " + vec(2.0 * b.half) + "\n");
    auto first_hit = [&](const Ray& r, double* t) {
        if (through_scene) {
            Hit h;
            const bool hit = intersect(scene, r, {0, kInf}, &h);
            *t = h.t;
            return hit;
        }
        const ShapeHits h = intersect(b, r, {0, kInf});
        *t = h.t[0];
        return h.count > 0;
    };
    int wrong = 0;
    *rays = 0;
    for (int i = 0; i < 6000; ++i) {
        const int a = i % 3, along = (a + 1 + (i / 3) % 2) % 3, other = 3 - a - along;
        const double s = (i / 6) % 2 ? 1.0 : -1.0;
        const bool edge = (i / 12) % 2;
        Vec3 o = b.centre;
        o[a] += s * b.half[a];
        o[other] += edge ? -s * b.half[other] : 0.9 * u(rng) * b.half[other];
        o[along] -= 3;
        Vec3 d(0.0);
        d[along] = 1;
        double t = 0;
        ++*rays;
        if (!first_hit({o, d}, &t) || std::abs(t - (3 - b.half[along])) > 1e-12) ++wrong;
        Vec3 off = o;
        off[a] = std::nextafter(o[a], s * kInf);
        if (first_hit({off, d}, &t)) ++wrong;
    }
    return wrong;
}

TEST(ShapesRobust, AxisParallelRaysOnSlabPlanesHitTheBox) {
    int rays = 0;
    const int wrong = slab_plane_errors(false, &rays);
    std::printf(
        "[ touch ] box slab planes: %d axis-parallel rays on faces and edges (and as many "
        "one ulp outside): %d wrong\n",
        rays, wrong);
    EXPECT_EQ(wrong, 0);
}

// The same rays through the BVH. Regression: BoxRay once gave a zero direction component a
// reciprocal of 1e30 and a slack of 2, so a ray whose origin lay exactly on a node's upper slab
// plane got a far distance of 2 and every node farther away was culled (4500 of these 6000 rays
// missed); a zero component is now a containment test of its own.
TEST(ShapesRobust, AxisParallelRaysOnSlabPlanesHitThroughTheBvh) {
    int rays = 0;
    const int wrong = slab_plane_errors(true, &rays);
    std::printf("[ touch ] box slab planes through the BVH: %d rays, %d wrong\n", rays, wrong);
    EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace rt

// ---------------------------------------------------------------------------------------------
// The torus (spec §13.7) against a long-double oracle: f(t) = (rho - R)^2 + y^2 - r^2 along the
// ray, sampled over the bounding sphere's chord; each sign change between samples is bisected,
// and each local minimum of the samples is refined by ternary search, so that a chord narrower
// than the sample spacing is found too. A ray is in the band (either answer accepted) when a
// local extremum of f lies within the band of a tangent: a chord shorter than kTorusBand times
// the tube radius (spec §13.7), or a distance from the surface within the rounding of double.

namespace rt {
namespace {

constexpr LD kTorusBand = 1e-6L;
constexpr LD kUlpBand = 4.4e-16L;  // 4 units of rounding of double

struct TorusOracle {
    std::vector<LD> roots;  // every crossing ahead of the origin, ascending
    bool band = false;      // a near-tangent: hit or miss both accepted there
};

TorusOracle torus_oracle(const Torus& tor, const Ray& ray) {
    const LD R = tor.ring, r = tor.tube;
    LD q0[3], d[3];
    for (int i = 0; i < 3; ++i) q0[i] = LD(ray.o[i]) - LD(tor.centre[i]), d[i] = LD(ray.d[i]);
    auto f = [&](LD t) {
        LD q[3];
        for (int i = 0; i < 3; ++i) q[i] = q0[i] + t * d[i];
        const LD dr = std::sqrt(q[0] * q[0] + q[2] * q[2]) - R;
        return dr * dr + q[1] * q[1] - r * r;
    };
    const LD dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const LD tc = -(q0[0] * d[0] + q0[1] * d[1] + q0[2] * d[2]) / dd;
    LD near2 = 0;
    for (int i = 0; i < 3; ++i) near2 += (q0[i] + tc * d[i]) * (q0[i] + tc * d[i]);
    TorusOracle o;
    const LD size = R + r;
    if (near2 >= size * size) return o;
    const LD half = std::sqrt((size * size - near2) / dd) * 1.001L;
    const LD lo = std::max(LD(0), tc - half), hi = tc + half;
    if (!(hi > lo)) return o;
    auto bisect = [&](LD a, LD b) {
        const bool neg_a = f(a) < 0;
        for (int k = 0; k < 200 && b - a > 0; ++k) {
            const LD m = 0.5L * (a + b);
            if (m <= a || m >= b) break;
            ((f(m) < 0) == neg_a ? a : b) = m;
        }
        return 0.5L * (a + b);
    };
    const int n = 4096;
    std::vector<LD> ts(n + 1), fs(n + 1);
    for (int i = 0; i <= n; ++i) ts[i] = lo + (hi - lo) * i / n, fs[i] = f(ts[i]);
    for (int i = 0; i < n; ++i)
        if ((fs[i] < 0) != (fs[i + 1] < 0)) o.roots.push_back(bisect(ts[i], ts[i + 1]));
    // Each discrete extremum of the samples (a minimum outside, a maximum inside: a chord, or a
    // gap between two chords, narrower than the spacing), refined by ternary search.
    for (int i = 1; i < n; ++i) {
        const LD sg = fs[i] < 0 ? -1 : 1;  // maximise -f inside, i.e. look for f's maximum
        if (!(sg * fs[i] <= sg * fs[i - 1] && sg * fs[i] <= sg * fs[i + 1])) continue;
        auto g = [&](LD t) { return sg * f(t); };
        LD a = ts[i - 1], b = ts[i + 1];
        for (int k = 0; k < 200; ++k) {
            const LD m1 = a + (b - a) / 3, m2 = b - (b - a) / 3;
            if (g(m1) < g(m2))
                b = m2;
            else
                a = m1;
        }
        const LD tm = 0.5L * (a + b), gm = g(tm);
        // |f| ~ 2 r delta at a distance delta from the surface, (chord / 2)^2 across a chord.
        // The band of a tangent: a chord shorter than kTorusBand r, or a distance from the surface
        // below kUlpBand (R + r), the rounding of a point in double (a chord of 1e-6 r in a tube of
        // r = 1e-3 R is a distance of one ulp of R from the tangent: the bound of double
        // precision).
        const LD band = kTorusBand * r, ulp = kUlpBand * size;
        if ((gm >= 0 && gm < 2 * r * std::max(band, ulp)) ||
            (gm < 0 && -gm < std::max(0.25L * band * band, 2 * r * ulp)))
            o.band = true;
        if (gm < 0 && (fs[i - 1] < 0) == (fs[i] < 0) && (fs[i + 1] < 0) == (fs[i] < 0)) {
            o.roots.push_back(bisect(ts[i - 1], tm));
            o.roots.push_back(bisect(tm, ts[i + 1]));
        }
    }
    std::sort(o.roots.begin(), o.roots.end());
    return o;
}

struct TorusStats {
    int rays = 0, hits = 0, band = 0, wrong_count = 0, nan = 0;
    double max_rel = 0;
};

void check_torus(const Torus& tor, const Ray& ray, TorusStats& st) {
    ++st.rays;
    const ShapeHits h = intersect(tor, ray, {0, kInf});
    for (int k = 0; k < h.count; ++k)
        if (!std::isfinite(h.t[k])) ++st.nan;
    const TorusOracle o = torus_oracle(tor, ray);
    if (o.band) {
        ++st.band;
        return;
    }
    if (h.count != static_cast<int>(o.roots.size())) {
        ++st.wrong_count;
        return;
    }
    st.hits += h.count;
    // |t - t*| <= 1e-9 max(t*, R + r) in distances: t is in units of |d|.
    const LD floor = LD(tor.ring + tor.tube) / std::sqrt(LD(glm::dot(ray.d, ray.d)));
    for (int k = 0; k < h.count; ++k) {
        const LD ts = o.roots[static_cast<size_t>(k)];
        st.max_rel = std::max(st.max_rel,
                              static_cast<double>(std::abs(LD(h.t[k]) - ts) / std::max(ts, floor)));
    }
}

// A point of the torus at (u, v) of spec §13.7, with its outward normal.
void torus_point(const Torus& tor, double u, double v, Vec3* p, Vec3* n) {
    const double phi = 2 * kPi * u, theta = 2 * kPi * v;
    const Vec3 dir(-std::sin(phi), 0, -std::cos(phi));
    *n = Vec3(std::cos(theta) * dir.x, std::sin(theta), std::cos(theta) * dir.z);
    *p = tor.centre + (tor.ring + tor.tube * std::cos(theta)) * dir +
         Vec3(0, tor.tube * std::sin(theta), 0);
}

void report_torus(const char* name, const TorusStats& st) {
    std::printf(
        "[ torus ] %-22s %d rays, %d hits, %d in the band; %d wrong counts, %d NaN; max rel "
        "t err %.3g\n",
        name, st.rays, st.hits, st.band, st.wrong_count, st.nan, st.max_rel);
    EXPECT_EQ(st.wrong_count, 0) << name;
    EXPECT_EQ(st.nan, 0) << name;
    EXPECT_LE(st.max_rel, 1e-9) << name;
    EXPECT_LT(st.band, st.rays / 2) << name;
    EXPECT_GT(st.hits, st.rays / 4) << name;
}

// Ordinary, thin (r/R = 1e-3), horn and spindle tori, off the origin.
std::vector<Torus> robust_tori() {
    return {{{0.3, -0.7, 1.1}, 0.4, 1.2},
            {{-2, 1, 0.5}, 1e-3, 1.0},
            {{0, 0, 0}, 0.75, 0.75},
            {{1, 2, 3}, 2.0, 1.0},
            {{5, -3, 2}, 1.5, 1.0}};
}

TEST(ShapesRobust, TorusRaysFromNearAndFarMatchALongDoubleOracle) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u01(0, 1);
    for (const Torus& tor : robust_tori()) {
        const double size = tor.ring + tor.tube;
        TorusStats st;
        for (int i = 0; i < 1500; ++i) {
            // Aimed at a point near the surface from 1 to 1e3 torus sizes away, |d| not 1.
            Vec3 p, n;
            torus_point(tor, u01(rng), u01(rng), &p, &n);
            const double dist = size * std::pow(10.0, 3.0 * u01(rng));
            const Vec3 aim = p + 0.5 * tor.tube * (u01(rng) - 0.5) * random_unit(rng);
            const Vec3 o = aim + dist * random_unit(rng);
            check_torus(tor, {o, (aim - o) * (0.1 + 10 * u01(rng)) / dist}, st);
        }
        char name[64];
        std::snprintf(name, sizeof name, "far r %g R %g", tor.tube, tor.ring);
        report_torus(name, st);
    }
}

// Rays through a surface point at angles of 1e-2 .. 1e-7 to its tangent plane (silhouettes, and
// chords inside thin tubes), from up to 1e3 torus sizes away.
TEST(ShapesRobust, TorusGrazingRaysMatchALongDoubleOracle) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u01(0, 1);
    for (const Torus& tor : robust_tori()) {
        const double size = tor.ring + tor.tube;
        TorusStats st;
        for (int i = 0; i < 1500; ++i) {
            Vec3 p, n;
            torus_point(tor, u01(rng), u01(rng), &p, &n);
            const Vec3 t_dir = random_tangent(rng, n);
            const double theta = std::pow(10.0, -2.0 - 5.0 * u01(rng)) * (i % 2 ? 1 : -1);
            const Vec3 d = std::cos(theta) * t_dir - std::sin(theta) * n;
            const double dist = size * std::pow(10.0, 3.0 * u01(rng));
            check_torus(tor, {p - dist * d, d}, st);
        }
        char name[64];
        std::snprintf(name, sizeof name, "graze r %g R %g", tor.tube, tor.ring);
        report_torus(name, st);
        EXPECT_LT(st.band, st.rays / 4);
    }
}

// Along the axis (the hole, or a spindle torus's dimples, where the quartic has double roots),
// nearly along it, and through the hole from afar.
TEST(ShapesRobust, TorusAxisAndHoleRays) {
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> u01(0, 1);
    for (const Torus& tor : robust_tori()) {
        const double size = tor.ring + tor.tube;
        for (double dist : {2.0, 1e3}) {
            for (double sy : {1.0, -1.0}) {
                const Ray axis{tor.centre + Vec3(0, sy * dist * size, 0), {0, -sy, 0}};
                const ShapeHits h = intersect(tor, axis, {0, kInf});
                if (tor.tube <= tor.ring) {
                    EXPECT_EQ(h.count, 0) << tor.tube << " " << tor.ring;
                } else {
                    const double y = std::sqrt(tor.tube * tor.tube - tor.ring * tor.ring);
                    ASSERT_EQ(h.count, 2) << tor.tube << " " << tor.ring;
                    EXPECT_NEAR(h.t[0], dist * size - y, 1e-7 * dist * size);
                    EXPECT_NEAR(h.t[1], dist * size + y, 1e-7 * dist * size);
                }
            }
        }
        TorusStats st;
        for (int i = 0; i < 600; ++i) {
            // Off the axis by up to the hole (or the tube), tilted by up to 1e-3.
            const double off = u01(rng) * (tor.ring > tor.tube ? tor.ring - tor.tube : tor.tube);
            const double phi = 2 * kPi * u01(rng);
            const Vec3 target = tor.centre + Vec3(off * std::cos(phi), 0, off * std::sin(phi));
            const double dist = size * std::pow(10.0, 3.0 * u01(rng));
            const Vec3 d =
                glm::normalize(Vec3(0, -1, 0) + 1e-3 * (u01(rng) - 0.5) * random_unit(rng));
            check_torus(tor, {target - dist * d, d}, st);
        }
        std::printf("[ torus ] axis r %g R %g: %d rays, %d hits, %d band, %d wrong, max rel %.3g\n",
                    tor.tube, tor.ring, st.rays, st.hits, st.band, st.wrong_count, st.max_rel);
        EXPECT_EQ(st.wrong_count, 0);
        EXPECT_EQ(st.nan, 0);
        EXPECT_LE(st.max_rel, 1e-9);
    }
}

// Rays spawned at torus hits (offset by the point's error bound, spec §7.5), reflected outward
// or refracted inward, never re-hit their own point, under a group transform with non-uniform
// scale and far from the origin; inward rays always find the far side.
TEST(ShapesRobust, TorusSpawnedRaysNeverReHit) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u01(0, 1);
    for (int grouped = 0; grouped < 2; ++grouped)
        for (const Torus& tor : robust_tori()) {
            // In the group's frame, or directly (the shape's own error bound alone then keeps the
            // spawned ray off its surface).
            SceneDesc desc =
                test::parse(std::string(kOpaque) +
                            (grouped ? "#group_begin 3 0 0 100  0 0.5 0 -50  0 0 1 20  0 0 0 1\n"
                                       "#shape_sphere 0 0 0 0 1\n#group_end\n"
                                     : "#shape_sphere 0 0 0 0 1\n"));
            (grouped ? desc.files[0].root.groups[0].shapes[0] : desc.files[0].root.shapes[0])
                .geometry = tor;
            const RenderScene scene = compile_scene(desc);
            const double size = tor.ring + tor.tube;
            int rehit = 0, lost = 0, spawned = 0;
            for (int i = 0; i < 3000; ++i) {
                Vec3 p, n;
                torus_point(tor, u01(rng), u01(rng), &p, &n);
                const Vec3 target = grouped ? Vec3(3 * p.x + 100, 0.5 * p.y - 50, p.z + 20) : p;
                const Vec3 eye = target + 30.0 * size * random_unit(rng);
                const Ray r{eye, glm::normalize(target - eye)};
                Hit h;
                if (!intersect(scene, r, {0, kInf}, &h)) continue;
                const SurfaceInteraction si = interaction(scene, r, h);
                // Outward (away from the surface) and inward directions.
                const Vec3 out = random_in_hemisphere(rng, si.n_geometric, 0.05);
                const Vec3 in = random_in_hemisphere(rng, -si.n_geometric, 0.05);
                Hit ho, hi;
                ++spawned;
                if (intersect(scene, {offset_origin(si, out), out}, {0, kInf}, &ho) &&
                    ho.t < 1e-6 * size)
                    ++rehit;
                if (!intersect(scene, {offset_origin(si, in), in}, {0, kInf}, &hi))
                    ++lost;
                else if (hi.t < 1e-6 * size)
                    ++rehit;
            }
            std::printf(
                "[ torus ] spawned %s r %g R %g: %d points, %d re-hits, %d inward rays lost\n",
                grouped ? "grouped" : "direct", tor.tube, tor.ring, spawned, rehit, lost);
            EXPECT_GT(spawned, 500);
            EXPECT_EQ(rehit, 0);
            EXPECT_EQ(lost, 0);
        }
}

}  // namespace
}  // namespace rt
