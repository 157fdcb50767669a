// Extreme cases (issue 6): shadow acne against scene scale, tiny/huge/far spheres against a
// long-double oracle, re-intersection of spawned rays under extreme non-uniform scale, watertight
// meshes, grazing and tangent rays, and degenerate input that must still render finite images.
// Geometry is generated in code; every test counts failures and asserts the exact count (zero
// unless stated).
//
// Tangent convention (what "agrees with the oracle" means): surfaces are closed sets. A ray whose
// exact (long-double) distance to a surface is zero -- a tangent ray, a ray through a cylinder's
// rim or a cone's apex, an axis-parallel ray lying in a box's slab plane -- hits. Elsewhere hit or
// miss must equal the oracle's unless the oracle's own margin (chord length, or distance of
// closest approach minus radius) is below kBand relative to the shape's size: inside that band of
// double rounding either answer is accepted, but never NaN. A tangent ray is reported as one hit
// (the double root once). A ray lying in a triangle's plane does not hit it (zero projected area:
// the determinant of Woop, Benthin and Wald's test is zero).
#include <array>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <random>

#include "rt/accel/intersect.h"
#include "test_util.h"

namespace rt {
namespace {

using LD = long double;
constexpr double kBand = 1e-9;

std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
std::string vec(const Vec3& v) {
    std::string s = num(v.x);
    s += ' ';
    s += num(v.y);
    s += ' ';
    s += num(v.z);
    return s;
}
std::string group_begin(const Mat4& m) {
    std::string s = "#group_begin";
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            s += ' ';
            s += num(m[c][r]);
        }
    s += '\n';
    return s;
}
// V1 materials: opaque grey, and half transparent (transmittance counts crossings: 0.5^k).
const char* kOpaque = "#material 0 0 0  0.2 0.2 0.2  0.8 0.8 0.8  0 0 0  10  0 0 0  1 -1 !!\n";
const char* kHalf = "#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0.5 0.5 0.5  1 -1 !!\n";

std::string vertex(const Vec3& p) {
    std::string s = "#vertex ";
    s += vec(p);
    s += " 0 0 0 0 0\n";
    return s;
}
std::string triangle(int a, int b, int c, int m = 0) {
    std::string s = "#shape_triangle ";
    s += std::to_string(m);
    s += ' ';
    s += std::to_string(a);
    s += ' ';
    s += std::to_string(b);
    s += ' ';
    s += std::to_string(c);
    s += '\n';
    return s;
}

Vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    for (;;) {
        const Vec3 v(g(rng), g(rng), g(rng));
        const double l = glm::length(v);
        if (l > 1e-6) return v / l;
    }
}
// A random unit direction with dot(d, n) >= min_cos (n unit).
Vec3 random_in_hemisphere(std::mt19937& rng, const Vec3& n, double min_cos) {
    for (;;) {
        Vec3 d = random_unit(rng);
        if (glm::dot(d, n) < 0) d = -d;
        if (glm::dot(d, n) >= min_cos) return d;
    }
}
Mat4 random_rotation(std::mt19937& rng) {
    std::normal_distribution<double> g;
    glm::dquat q(g(rng), g(rng), g(rng), g(rng));
    return Mat4(glm::mat3_cast(glm::normalize(q)));
}

// ---------------------------------------------------------------------------------------------
// Shadow acne against scale.

struct AcneCount {
    int plane_hits = 0, wrong = 0, wrong_fixed_eps = 0;
};

// A plane (a box top or two triangles) through `c`, tilted (an axis-aligned float plane shares
// the float grid of the ray origins, which hides the rounding), seen from 8.5 units away and lit
// by a point light about 5 degrees over it. Nothing can shadow the plane, so any occluded shadow
// ray is acne. The shadow ray is built as shading does (offset_origin, segment to the light); the
// witness offsets by a fixed 1e-4 along the normal instead.
AcneCount count_acne(const Vec3& c, bool triangles) {
    const Mat4 tilt = glm::rotate(glm::rotate(Mat4(1.0), 0.3, Vec3(1, 0, 0)), 0.2, Vec3(0, 0, 1));
    Mat4 m = tilt;
    m[3] = glm::dvec4(c, 1);
    auto world = [&](const Vec3& p) { return Vec3(m * glm::dvec4(p, 1)); };
    std::string text = kOpaque;
    if (triangles) {
        const double h = 10;
        text += vertex(world({-h, 0, -h})) + vertex(world({h, 0, -h})) + vertex(world({h, 0, h})) +
                vertex(world({-h, 0, h}));
        // Far away, a small triangle at the origin as well (out of the light's way): the scene
        // spans the whole distance, so the float copy of the triangles (relative to the centre
        // of their bounds) rounds at the scale of c, as a big world's would.
        const bool far = glm::length(c) > 100;
        if (far) text += vertex({0, 0, 0}) + vertex({1, 0, 0}) + vertex({0, 1, 0});
        text += triangle(0, 2, 1) + triangle(0, 3, 2);
        if (far) text += triangle(4, 5, 6);
    } else {
        text += group_begin(m) + "#shape_box 0 0 -0.5 0 20 1 20\n#group_end\n";
    }
    const RenderScene scene = test::compile(text);
    const Vec3 eye = world({0, 3, 8}), light = world({30, 3, -10});
    AcneCount n;
    const int res = 64;
    for (int j = 0; j < res; ++j)
        for (int i = 0; i < res; ++i) {
            const Vec3 target =
                world({-6 + 12.0 * (i + 0.5) / res, 0, -6 + 12.0 * (j + 0.5) / res});
            const Ray r{eye, glm::normalize(target - eye)};
            Hit hit;
            if (!intersect(scene, r, {0, kInf}, &hit)) continue;
            ++n.plane_hits;
            const SurfaceInteraction si = interaction(scene, r, hit);
            const Vec3 l = glm::normalize(light - si.p);
            const Vec3 o = offset_origin(si, l);
            if (transmittance(scene, {o, light - o}, 1.0) != Vec3(1.0)) ++n.wrong;
            const Vec3 n_l = glm::dot(si.n_geometric, l) > 0 ? si.n_geometric : -si.n_geometric;
            const Vec3 o_fixed = si.p + 1e-4 * n_l;
            if (transmittance(scene, {o_fixed, light - o_fixed}, 1.0) != Vec3(1.0))
                ++n.wrong_fixed_eps;
        }
    return n;
}

TEST(Extreme, NoShadowAcneAtAnyScaleWhileAFixedEpsilonFailsFarAway) {
    const Vec3 dir = glm::normalize(Vec3(1, 1, 1));
    for (const double dist : {1.0, 1e3, 1e5}) {
        // Not representable in float: the float triangles sit off the double plane.
        const Vec3 c = dist * dir + Vec3(0.1234567, 0.0765432, -0.0456789);
        for (const bool tris : {false, true}) {
            const AcneCount n = count_acne(c, tris);
            SCOPED_TRACE(std::string(tris ? "triangles" : "box") + " at " + num(dist));
            std::printf(
                "[ acne ] %-9s at %-6g: %d plane pixels, %d wrongly shadowed, %d with a "
                "fixed 1e-4 offset\n",
                tris ? "triangles" : "box", dist, n.plane_hits, n.wrong, n.wrong_fixed_eps);
            EXPECT_EQ(n.plane_hits, 64 * 64);
            EXPECT_EQ(n.wrong, 0);
            // The witness: at 1e5 a fixed epsilon is below the float rounding of the triangles.
            if (tris && dist == 1e5) {
                EXPECT_GT(n.wrong_fixed_eps, 64 * 64 / 10);
            }
        }
    }
}

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
TEST(Extreme, FarMeshHitDistancesResolveTheMesh) {
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

TEST(Extreme, TinyHugeAndFarSpheresMatchALongDoubleOracle) {
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
// Re-intersection under extreme non-uniform scale, through the group (transform) path.

std::string shape_text(ShapeKind k) {
    switch (k) {
        case ShapeKind::Sphere:
            return "#shape_sphere 0 0.1 -0.2 0.3 1\n";
        case ShapeKind::Box:
            return "#shape_box 0 0.1 -0.2 0.3 2 1 1.5\n";
        case ShapeKind::Cylinder:
            return "#shape_cylinder 0 0.1 -0.2 0.3 1 2\n";
        case ShapeKind::Cone:
            return "#shape_cone 0 0.1 -0.2 0.3 1 2\n";
        case ShapeKind::Triangle:
            return triangle(0, 1, 2);
    }
    return "";
}

TEST(Extreme, SpawnedRaysNeverReHitAndInwardRaysHitTheFarSideOnceUnderExtremeScale) {
    std::mt19937 rng(61);
    std::uniform_real_distribution<double> uni(-1, 1), expo(-4, 4);
    const ShapeKind kinds[] = {ShapeKind::Sphere, ShapeKind::Box, ShapeKind::Cylinder,
                               ShapeKind::Cone, ShapeKind::Triangle};
    const int kTransforms = 400, kRays = 100;
    for (const ShapeKind kind : kinds) {
        int hits = 0, outward = 0, rehit = 0, inward = 0, not_once = 0, wrong_side = 0;
        for (int k = 0; k < kTransforms; ++k) {
            const Vec3 scale(std::pow(10.0, expo(rng)), std::pow(10.0, expo(rng)),
                             std::pow(10.0, expo(rng)));
            Mat4 m = glm::scale(Mat4(1.0), scale);
            if (k % 2) m = random_rotation(rng) * m;  // half of them rotated as well
            m[3] = glm::dvec4(100 * uni(rng), 100 * uni(rng), 100 * uni(rng), 1);
            std::string text = kHalf;
            text += vertex({-1, -1, 0.1}) + vertex({1, -0.9, -0.1}) + vertex({0.1, 1, 0.3});
            text += group_begin(m) + shape_text(kind) + "#group_end\n";
            const RenderScene scene = test::compile(text);
            const Vec3 lo = scene.world_bounds.lo, hi = scene.world_bounds.hi;
            const double size = glm::length(hi - lo);
            for (int i = 0; i < kRays; ++i) {
                // Aim at the image of a random point inside the shape's local frame.
                const Vec3 local(0.4 * uni(rng), 0.4 * uni(rng), 0.1 * uni(rng));
                const Vec3 target = Vec3(m * glm::dvec4(local + Vec3(0.1, -0.2, 0.3), 1));
                const Vec3 d = random_unit(rng);
                const Ray r{target - 2 * size * d, d};
                Hit h;
                if (!intersect(scene, r, {0, kInf}, &h)) continue;
                ++hits;
                const SurfaceInteraction si = interaction(scene, r, h);
                ASSERT_TRUE(is_finite(si.p) && is_finite(si.n_geometric));
                const Vec3 n = glm::dot(r.d, si.n_geometric) < 0 ? si.n_geometric : -si.n_geometric;
                if (kind != ShapeKind::Triangle && n != si.n_geometric) ++wrong_side;
                // Outward: nothing at all may be hit (the only surface is convex).
                const Ray out = spawn_ray(si, random_in_hemisphere(rng, n, 0.01));
                ++outward;
                if (transmittance(scene, out, kInf) != Vec3(1.0)) ++rehit;
                // Inward: a closed shape's far side exactly once; a triangle nothing.
                const Ray in = spawn_ray(si, random_in_hemisphere(rng, -n, 0.01));
                ++inward;
                const Vec3 expect(kind == ShapeKind::Triangle ? 1.0 : 0.5);
                if (transmittance(scene, in, kInf) != expect) ++not_once;
            }
        }
        SCOPED_TRACE(shape_kind_name(kind));
        std::printf(
            "[ respawn ] %-8s %d hits, %d outward rays: %d re-hits; %d inward rays: %d not "
            "hitting the far side exactly once; %d inward normals\n",
            shape_kind_name(kind), hits, outward, rehit, inward, not_once, wrong_side);
        EXPECT_GT(hits, kTransforms * kRays / 5);
        EXPECT_EQ(rehit, 0);
        EXPECT_EQ(not_once, 0);
        EXPECT_EQ(wrong_side, 0);
    }
}

// ---------------------------------------------------------------------------------------------
// Watertight meshes.

struct Mesh {
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> t;
};

// A latitude-longitude sphere of radius about 1 with every vertex jittered (radius and
// position).
Mesh jittered_sphere(int n_lat, int n_lon, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    Mesh m;
    m.v.push_back({0, -1, 0});
    for (int i = 1; i < n_lat; ++i)
        for (int j = 0; j < n_lon; ++j) {
            const double th = kPi * (i + 0.3 * u(rng)) / n_lat;
            const double ph = 2 * kPi * (j + 0.3 * u(rng)) / n_lon;
            const double r = 1 + 0.05 * u(rng);
            m.v.push_back(
                r * Vec3(std::sin(th) * std::cos(ph), -std::cos(th), std::sin(th) * std::sin(ph)));
        }
    m.v.push_back({0, 1, 0});
    const int top = static_cast<int>(m.v.size()) - 1;
    auto id = [&](int i, int j) { return 1 + (i - 1) * n_lon + (j % n_lon); };
    for (int j = 0; j < n_lon; ++j) {
        m.t.push_back({0, id(1, j + 1), id(1, j)});
        m.t.push_back({top, id(n_lat - 1, j), id(n_lat - 1, j + 1)});
        for (int i = 1; i < n_lat - 1; ++i) {
            m.t.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
            m.t.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
        }
    }
    return m;
}

Mesh box_mesh() {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.v.push_back({(i & 1) ? 1.0 : -1.0, (i & 2) ? 0.7 : -0.7, (i & 4) ? 1.3 : -1.3});
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                             {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
        m.t.push_back({q[0], q[1], q[2]});
        m.t.push_back({q[0], q[2], q[3]});
    }
    return m;
}

struct LeakCount {
    long rays = 0, leaks = 0;
};

// Rays from random points inside (within `inner` of the centre) toward every vertex, every edge
// midpoint and random directions: each must hit the mesh.
LeakCount count_leaks(const Mesh& mesh, const Mat4& m, double inner, int origins, int random_dirs,
                      std::mt19937& rng) {
    std::string text = kOpaque;
    for (const Vec3& p : mesh.v) text += vertex(p);
    text += group_begin(m);
    for (const auto& t : mesh.t) text += triangle(t[0], t[1], t[2]);
    text += "#group_end\n";
    const RenderScene scene = test::compile(text);
    std::vector<Vec3> targets;
    for (const Vec3& p : mesh.v) targets.push_back(Vec3(m * glm::dvec4(p, 1)));
    for (const auto& t : mesh.t)
        for (int e = 0; e < 3; ++e)
            if (t[e] < t[(e + 1) % 3])  // each edge once
                targets.push_back(
                    Vec3(m * glm::dvec4(0.5 * (mesh.v[t[e]] + mesh.v[t[(e + 1) % 3]]), 1)));
    std::uniform_real_distribution<double> u(-1, 1);
    LeakCount n;
    for (int k = 0; k < origins; ++k) {
        const Vec3 o = Vec3(m * glm::dvec4(inner * Vec3(u(rng), u(rng), u(rng)), 1));
        auto shoot = [&](const Vec3& d) {
            Hit h;
            ++n.rays;
            if (!intersect(scene, {o, d}, {0, kInf}, &h)) ++n.leaks;
        };
        for (const Vec3& t : targets) shoot(t - o);
        for (int i = 0; i < random_dirs; ++i) shoot(random_unit(rng));
    }
    return n;
}

TEST(Extreme, ClosedMeshesNeverLeak) {
    std::mt19937 rng(7);
    const Mesh sphere = jittered_sphere(24, 48, rng);  // 2208 triangles
    const Mesh box = box_mesh();
    Mat4 far = random_rotation(rng);
    far[3] = glm::dvec4(1234.567, -987.6543, 345.678, 1);
    Mat4 rotated = random_rotation(rng);
    long total_rays = 0, total_leaks = 0;
    struct Case {
        const char* name;
        const Mesh* mesh;
        Mat4 m;
        double inner;
        int origins, random_dirs;
    };
    const Case cases[] = {
        {"sphere", &sphere, Mat4(1.0), 0.5, 60, 2000},
        {"sphere far+rotated", &sphere, far, 0.5, 60, 2000},
        {"box", &box, Mat4(1.0), 0.6, 20000, 10},
        {"box rotated", &box, rotated, 0.6, 20000, 10},
        {"box far+rotated", &box, far, 0.6, 20000, 10},
    };
    for (const Case& c : cases) {
        const LeakCount n = count_leaks(*c.mesh, c.m, c.inner, c.origins, c.random_dirs, rng);
        std::printf("[ watertight ] %-20s %ld rays, %ld leaks\n", c.name, n.rays, n.leaks);
        EXPECT_EQ(n.leaks, 0) << c.name;
        total_rays += n.rays;
        total_leaks += n.leaks;
    }
    std::printf("[ watertight ] total %ld rays, %ld leaks\n", total_rays, total_leaks);
    EXPECT_GT(total_rays, 2000000);
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

TEST(Extreme, GrazingRaysAgreeWithALongDoubleOracle) {
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
TEST(Extreme, GrazingRaysOnATrianglePlane) {
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
TEST(Extreme, RaysThroughCylinderRimsAndConeApexesHit) {
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

TEST(Extreme, AxisParallelRaysOnSlabPlanesHitTheBox) {
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
TEST(Extreme, AxisParallelRaysOnSlabPlanesHitThroughTheBvh) {
    int rays = 0;
    const int wrong = slab_plane_errors(true, &rays);
    std::printf("[ touch ] box slab planes through the BVH: %d rays, %d wrong\n", rays, wrong);
    EXPECT_EQ(wrong, 0);
}

// ---------------------------------------------------------------------------------------------
// Degenerate input: every image finite, every render finished.

bool all_finite(const Image& img) {
    for (const double v : img.rgb)
        if (!std::isfinite(v)) return false;
    return true;
}

TEST(Extreme, DegenerateInputRendersFiniteImages) {
    const std::string camera = "#camera 0 0.5 6  0 -0.08 -1  0 1 0  0.5\n";
    const std::string light = "#light_point 1 1 1  2 3 4  1 0 0\n";
    auto v1 = [](const std::string& spec, const std::string& n, const std::string& tr,
                 const std::string& ior) {
        std::string s = "#material 0 0 0  0.1 0.1 0.1  0.7 0.6 0.5  ";
        s += spec + "  " + n + "  " + tr + "  " + ior + " -1 !!\n";
        return s;
    };
    const std::string plain = v1("0.3 0.3 0.3", "20", "0 0 0", "1");
    const std::string body = "#shape_sphere 0 0 0.5 0 1\n#shape_box 0 0 -1 0 8 0.2 8\n";
    struct Case {
        const char* name;
        std::string text;
        int depth;
    };
    const Case cases[] = {
        {"zero-area and repeated-vertex triangles",
         camera + light + plain +
             "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 1 1 0 0 0 1 0\n#vertex 2 2 2 0 0 0 0 1\n"
             "#vertex 1e-9 0 0 0 0 0 0 0\n#vertex 0 1 0 0 0 0 0 0\n"
             "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 0 1\n#shape_triangle 0 0 3 4\n" +
             body,
         5},
        {"group scaled by 1e-6 on one axis",
         camera + light + plain + "#group_begin 1 0 0 0  0 1e-6 0 0  0 0 1 0  0 0 0 1\n" + body +
             "#shape_cylinder 0 0 0 0 1 2\n#shape_cone 0 1 0 0 1 2\n#group_end\n" + body,
         5},
        {"rotated group scaled by 1e-6",
         camera + light + plain +
             "#group_begin 0.6 -0.8e-6 0 0.1  0.8 0.6e-6 0 0.2  0 0 1 0  0 0 0 1\n" + body +
             "#group_end\n",
         5},
        {"light inside a sphere and a box",
         camera +
             "#light_point 1 1 1  0 0.5 0  1 0 0\n#light_spot 1 1 1  0 -1 0  0 -1 0  1 0 0  "
             "0.5 1\n" +
             plain + body,
         5},
        {"attenuation all zero", camera + "#light_point 1 1 1  2 3 4  0 0 0\n" + plain + body, 5},
        {"spot exponent 1e6",
         camera + "#light_spot 1 1 1  0 3 0  0 -1 0  1 0 0  1.5 1e6\n" + plain + body, 5},
        {"specular exponent 0", camera + light + v1("1 1 1", "0", "0 0 0", "1") + body, 5},
        {"specular exponent 1e4", camera + light + v1("1 1 1", "1e4", "0 0 0", "1") + body, 5},
        {"refraction index 1", camera + light + v1("0.1 0.1 0.1", "20", "0.9 0.9 0.9", "1") + body,
         8},
        {"refraction index 1e-3",
         camera + light + v1("0.1 0.1 0.1", "20", "0.9 0.9 0.9", "1e-3") + body, 8},
        {"refraction index 10",
         camera + light + v1("0.1 0.1 0.1", "20", "0.9 0.9 0.9", "10") + body, 8},
        {"mirror box, depth 0",
         "#camera 0 0 0  0 0.1 -1  0 1 0  0.6\n" + light +
             "#light_point 1 1 1  0.3 0.2 0.1  1 0 0\n" + v1("1 1 1", "50", "0 0 0", "1") +
             "#shape_box 0 0 0 0 4 3 5\n#shape_sphere 0 0.5 -0.3 -1 0.4\n",
         0},
        {"mirror box, depth 100",
         "#camera 0 0 0  0 0.1 -1  0 1 0  0.6\n" +
             std::string("#light_point 1 1 1  0.3 0.2 0.1  1 0 0\n") +
             v1("1 1 1", "50", "0 0 0", "1") +
             "#shape_box 0 0 0 0 4 3 5\n#shape_sphere 0 0.5 -0.3 -1 0.4\n",
         100},
    };
    for (const Case& c : cases) {
        const RenderScene scene = test::compile(c.text);
        RenderSettings s;
        s.width = s.height = 32;
        s.max_depth = c.depth;
        s.cutoff = 0.0;  // depth alone bounds the recursion
        s.threads = 1;
        RenderState state;
        ASSERT_TRUE(render_samples(state, scene, make_render_plan(scene, s), s, 1)) << c.name;
        const Image img = state.image();
        double sum = 0;
        for (const double v : img.rgb) sum += v;
        std::printf("[ degenerate ] %-40s finite %d, mean %.4g, %llu rays\n", c.name,
                    all_finite(img), sum / static_cast<double>(img.rgb.size()),
                    static_cast<unsigned long long>(state.rays.total()));
        EXPECT_TRUE(all_finite(img)) << c.name;
        EXPECT_EQ(img.width, 32);
    }
    // Zero-length directions are parse errors (spec §3.1: d != 0), reported clearly.
    const std::string errors[][2] = {
        {"#camera 0 0 5  0 0 0  0 1 0  0.5\n", "camera view direction is zero"},
        {"#light_dir 1 1 1  0 0 0\n", "light direction is zero"},
        {"#light_spot 1 1 1  0 3 0  0 0 0  1 0 0  0.5 1\n", "spot light direction is zero"},
    };
    for (const auto& e : errors) {
        const std::string msg = test::parse_error(e[0] + plain + body);
        EXPECT_NE(msg.find("test.ray:1:"), std::string::npos) << msg;
        EXPECT_NE(msg.find(e[1]), std::string::npos) << msg;
    }
}

}  // namespace
}  // namespace rt
