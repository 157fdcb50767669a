// Shape tests: hits, outward normals and texture coordinates of spec §5, in the local frame and
// through groups with rotation and non-uniform scale; the inside test of each solid; the one
// dispatch on a primitive's kind (visit_shape) and the bounds of a described shape; the torus of
// spec §13.7 (hits, normals, uv, inside, preview, bounds).
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "rt/accel/intersect.h"
#include "rt/format/writer.h"
#include "test_util.h"

namespace rt {
namespace {

constexpr double kTol = 1e-9;

TEST(Sphere, HitsNormalAndUv) {
    const Sphere s{{1, 2, 3}, 2};
    const Ray r{{1, 2, 10}, {0, 0, -1}};
    const ShapeHits h = intersect(s, r, {0, kInf});
    ASSERT_EQ(h.count, 2);
    EXPECT_NEAR(h.t[0], 5, kTol);
    EXPECT_NEAR(h.t[1], 9, kTol);
    const SurfacePoint sp = surface_at(s, r, h.t[0], h.part[0]);
    EXPECT_VEC_NEAR(sp.p, Vec3(1, 2, 5), kTol);
    EXPECT_VEC_NEAR(sp.n_geometric, Vec3(0, 0, 1), kTol);
    // +z: azimuth atan2(-0, -1) = pi -> u = 0.5; equator -> v = 0.5.
    EXPECT_NEAR(sp.uv.x, 0.5, kTol);
    EXPECT_NEAR(sp.uv.y, 0.5, kTol);
    // From -z the azimuth is 0; from +x it is 3pi/2 (atan2(-1, 0) + 2pi).
    const SurfacePoint back = surface_at(s, r, h.t[1], 0);
    EXPECT_NEAR(back.uv.x, 0.0, kTol);
    const Ray rx{{10, 2, 3}, {-1, 0, 0}};
    const SurfacePoint px = surface_at(s, rx, intersect(s, rx, {0, kInf}).t[0], 0);
    EXPECT_NEAR(px.uv.x, 0.75, kTol);
    // Bottom pole: v = 0; top pole: v = 1.
    const Ray down{{1, -10, 3}, {0, 1, 0}};
    EXPECT_NEAR(surface_at(s, down, intersect(s, down, {0, kInf}).t[0], 0).uv.y, 0.0, 1e-7);
}

TEST(Sphere, RayFromInsideHitsOnceAndMissesWork) {
    const Sphere s{{0, 0, 0}, 1};
    EXPECT_EQ(intersect(s, {{0, 0, 0}, {0, 1, 0}}, {0, kInf}).count, 1);
    EXPECT_EQ(intersect(s, {{0, 2, 5}, {0, 0, -1}}, {0, kInf}).count, 0);
    EXPECT_EQ(intersect(s, {{0, 0, 5}, {0, 0, 1}}, {0, kInf}).count, 0);
}

TEST(Box, FacesNormalsAndUv) {
    const Box b{{0, 0, 0}, {1, 2, 3}};  // sizes 2, 4, 6
    struct Case {
        Ray ray;
        Vec3 normal;
        Vec2 uv;
    };
    // Each ray hits a face at local q; uv per the spec's face table.
    const Case cases[] = {
        {{{5, 1, 1.5}, {-1, 0, 0}}, {1, 0, 0}, {(3 - 1.5) / 6, (1 + 2) / 4.0}},     // +x
        {{{-5, 1, 1.5}, {1, 0, 0}}, {-1, 0, 0}, {(1.5 + 3) / 6, (1 + 2) / 4.0}},    // -x
        {{{0.5, 5, 1.5}, {0, -1, 0}}, {0, 1, 0}, {(0.5 + 1) / 2, (3 - 1.5) / 6}},   // +y
        {{{0.5, -5, 1.5}, {0, 1, 0}}, {0, -1, 0}, {(0.5 + 1) / 2, (1.5 + 3) / 6}},  // -y
        {{{0.5, 1, 5}, {0, 0, -1}}, {0, 0, 1}, {(0.5 + 1) / 2, (1 + 2) / 4.0}},     // +z
        {{{0.5, 1, -5}, {0, 0, 1}}, {0, 0, -1}, {(1 - 0.5) / 2, (1 + 2) / 4.0}},    // -z
    };
    for (const Case& c : cases) {
        const ShapeHits h = intersect(b, c.ray, {0, kInf});
        ASSERT_EQ(h.count, 2);
        const SurfacePoint sp = surface_at(b, c.ray, h.t[0], h.part[0]);
        EXPECT_VEC_NEAR(sp.n_geometric, c.normal, kTol);
        EXPECT_NEAR(sp.uv.x, c.uv.x, kTol);
        EXPECT_NEAR(sp.uv.y, c.uv.y, kTol);
    }
}

TEST(Box, AxisParallelRayOnSlabPlaneHasNoNaN) {
    const Box b{{0, 0, 0}, {1, 1, 1}};
    const ShapeHits h = intersect(b, {{1, 0.5, 5}, {0, 0, -1}}, {0, kInf});  // on x = 1
    EXPECT_EQ(h.count, 2);
    EXPECT_EQ(intersect(b, {{1.0000001, 0.5, 5}, {0, 0, -1}}, {0, kInf}).count, 0);
}

TEST(Cylinder, SideAndCaps) {
    const Cylinder c{{0, 1, 0}, 2, 4};  // y in [-1, 3]
    const Ray side{{0, 1, 10}, {0, 0, -1}};
    ShapeHits h = intersect(c, side, {0, kInf});
    ASSERT_EQ(h.count, 2);
    EXPECT_NEAR(h.t[0], 8, kTol);
    SurfacePoint sp = surface_at(c, side, h.t[0], h.part[0]);
    EXPECT_VEC_NEAR(sp.n_geometric, Vec3(0, 0, 1), kTol);
    EXPECT_NEAR(sp.uv.x, 0.5, kTol);
    EXPECT_NEAR(sp.uv.y, 0.5, kTol);  // (p_y - y0)/h = (1 - -1)/4

    const Ray top{{1, 10, -1}, {0, -1, 0}};
    h = intersect(c, top, {0, kInf});
    ASSERT_EQ(h.count, 2);
    EXPECT_NEAR(h.t[0], 7, kTol);
    sp = surface_at(c, top, h.t[0], h.part[0]);
    EXPECT_VEC_NEAR(sp.n_geometric, Vec3(0, 1, 0), kTol);
    EXPECT_NEAR(sp.uv.x, (1 + 2) / 4.0, kTol);   // (q_x + r)/2r
    EXPECT_NEAR(sp.uv.y, (2 - -1) / 4.0, kTol);  // (r - q_z)/2r
    sp = surface_at(c, top, h.t[1], h.part[1]);
    EXPECT_VEC_NEAR(sp.n_geometric, Vec3(0, -1, 0), kTol);
    EXPECT_NEAR(sp.uv.y, (-1 + 2) / 4.0, kTol);  // bottom: (q_z + r)/2r

    // Through the rim: one entry on the cap edge, no NaN, at most two hits.
    const Ray rim{{2, 10, 0}, {0, -1, 0}};
    h = intersect(c, rim, {0, kInf});
    EXPECT_GE(h.count, 1);
    EXPECT_NEAR(h.t[0], 7, kTol);
}

TEST(Cone, SideBaseAndApex) {
    const Cone c{{0, 0, 0}, 1, 2};           // base y = -1 radius 1, apex (0, 1, 0)
    const Ray side{{0, 0, 10}, {0, 0, -1}};  // at y = 0 the radius is 0.5
    ShapeHits h = intersect(c, side, {0, kInf});
    ASSERT_EQ(h.count, 2);
    EXPECT_NEAR(h.t[0], 9.5, kTol);
    SurfacePoint sp = surface_at(c, side, h.t[0], h.part[0]);
    EXPECT_VEC_NEAR(sp.n_geometric, glm::normalize(Vec3(0, 1, 2)), kTol);  // (h q/rho, r, ...)
    EXPECT_NEAR(sp.uv.y, 0.5, kTol);

    const Ray up{{0.5, -5, 0}, {0, 1, 0}};
    h = intersect(c, up, {0, kInf});
    ASSERT_EQ(h.count, 2);
    sp = surface_at(c, up, h.t[0], h.part[0]);
    EXPECT_VEC_NEAR(sp.n_geometric, Vec3(0, -1, 0), kTol);
    EXPECT_NEAR(sp.uv.x, 0.75, kTol);
    EXPECT_NEAR(sp.uv.y, 0.5, kTol);

    // Exactly through the apex along the axis.
    const Ray apex{{0, 5, 0}, {0, -1, 0}};
    h = intersect(c, apex, {0, kInf});
    ASSERT_GE(h.count, 1);
    EXPECT_NEAR(h.t[0], 4, kTol);
    sp = surface_at(c, apex, h.t[0], h.part[0]);
    EXPECT_TRUE(is_finite(sp.n_geometric));
}

TEST(Triangle, BarycentricsNormalsAndUv) {
    const Triangle t{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
    TriangleAttribs a;
    a.uv[0] = {0, 0};
    a.uv[1] = {1, 0};
    a.uv[2] = {0, 1};
    const Ray r{{0.5, 0.5, 3}, {0, 0, -1}};
    const ShapeHits h = intersect(t, r, {0, kInf});
    ASSERT_EQ(h.count, 1);
    EXPECT_NEAR(h.t[0], 3, kTol);
    SurfacePoint sp = surface_at(t, a, r, h.t[0]);
    EXPECT_VEC_NEAR(sp.n_geometric, Vec3(0, 0, 1), kTol);
    EXPECT_NEAR(sp.uv.x, 0.25, kTol);
    EXPECT_NEAR(sp.uv.y, 0.25, kTol);
    a.has_normals = true;
    a.n[0] = a.n[1] = Vec3(0, 0, 1);
    a.n[2] = Vec3(0, 1, 0);
    sp = surface_at(t, a, r, h.t[0]);
    EXPECT_VEC_NEAR(sp.n_shading, glm::normalize(Vec3(0, 0.25, 0.75)), kTol);
    EXPECT_EQ(intersect(t, {{1.5, 1.5, 3}, {0, 0, -1}}, {0, kInf}).count, 0);
}

// Through the whole pipeline: a group with rotation and non-uniform scale.
TEST(Transforms, NonUniformScaleAndRotationMapHitsNormalsAndKeepUv) {
    // The ellipsoid of spec §4.1: radii (0.5, 1, 0.5) centred at (0, 2.5, 0).
    const RenderScene s = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#group_begin 0.5 0 0 0  0 1 0 2.5  0 0 0.5 0  0 0 0 1\n"
        "#shape_sphere 0 0 0 0 1\n#group_end\n");
    const Ray r{{0, 2.5, 10}, {0, 0, -1}};
    Hit hit;
    ASSERT_TRUE(intersect(s, r, {0, kInf}, &hit));
    EXPECT_NEAR(hit.t, 9.5, kTol);
    // An oblique ray: the normal is (A^-1)^T n, renormalised.
    const Ray o{{0, 2.5 + 0.5, 10}, {0, 0, -1}};
    ASSERT_TRUE(intersect(s, o, {0, kInf}, &hit));
    const SurfaceInteraction si = interaction(s, o, hit);
    const double z = 0.5 * std::sqrt(1 - 0.25);  // local point (0, .5, sqrt(.75))
    EXPECT_NEAR(si.p.z, z, kTol);
    EXPECT_VEC_NEAR(si.n_geometric, glm::normalize(Vec3(0, 0.5, std::sqrt(0.75) / 0.5)), 1e-9);
    // uv comes from the local frame: local point (0, 0.5, 0.866), azimuth pi.
    EXPECT_NEAR(si.uv.x, 0.5, kTol);
    EXPECT_NEAR(si.uv.y, std::acos(-0.5) / kPi, kTol);

    // Rotation by 45 degrees about y with scale sqrt(2) in x and z (spec §4.1's second example).
    const RenderScene b = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#group_begin 1 0 1 0  0 1 0 0  -1 0 1 0  0 0 0 1\n"
        "#shape_box 0 0 0 0 2 2 2\n#group_end\n");
    // The unit box's +x face corner (1, y, 1) maps to (2, y, 0): a ray along -x hits an edge at 2.
    ASSERT_TRUE(intersect(b, {{10, 0.2, 0}, {-1, 0, 0}}, {0, kInf}, &hit));
    EXPECT_NEAR(hit.t, 8, 1e-9);
    const Ray face{{10, 0.2, 10}, glm::normalize(Vec3(-1, 0, -1))};
    ASSERT_TRUE(intersect(b, face, {0, kInf}, &hit));
    const SurfaceInteraction sf = interaction(b, face, hit);
    EXPECT_VEC_NEAR(sf.n_geometric, glm::normalize(Vec3(1, 0, 1)), 1e-9);
}

TEST(Transforms, MirrorKeepsTriangleNormalAsInverseTranspose) {
    // Triangle with normal +z, mirrored in z: the normal must become -z ((A^-1)^T n).
    const RenderScene s = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 0 0 0 0 0 1 0\n#vertex 0 1 0 0 0 0 0 1\n"
        "#group_begin 1 0 0 0  0 1 0 0  0 0 -1 0  0 0 0 1\n"
        "#shape_triangle 0 0 1 2\n#group_end\n");
    const Ray r{{0.2, 0.3, 5}, {0, 0, -1}};
    Hit hit;
    ASSERT_TRUE(intersect(s, r, {0, kInf}, &hit));
    const SurfaceInteraction si = interaction(s, r, hit);
    EXPECT_VEC_NEAR(si.n_geometric, Vec3(0, 0, -1), kTol);
    EXPECT_NEAR(si.uv.x, 0.2, kTol);
    EXPECT_NEAR(si.uv.y, 0.3, kTol);
}

// ---- inside ---------------------------------------------------------------------------------

TEST(Inside, SphereInteriorOnlyTheBoundaryIsOutside) {
    const Sphere s{{1, 2, 3}, 2};
    EXPECT_TRUE(inside(s, {1, 2, 3}));
    EXPECT_TRUE(inside(s, {2, 3, 4}));
    EXPECT_FALSE(inside(s, {1, 2, 6}));
    EXPECT_FALSE(inside(s, {-5, 2, 3}));
    // On the surface (exact in double): not inside; a hair either side decides.
    EXPECT_FALSE(inside(s, {3, 2, 3}));
    EXPECT_FALSE(inside(s, {1, 0, 3}));
    EXPECT_TRUE(inside(s, {3 - 1e-9, 2, 3}));
    EXPECT_FALSE(inside(s, {3 + 1e-9, 2, 3}));
}

TEST(Inside, BoxUsesHalfExtentsOnEveryAxis) {
    const Box b{{1, 0, -1}, {0.5, 1, 2}};
    EXPECT_TRUE(inside(b, {1, 0, -1}));
    EXPECT_TRUE(inside(b, {1.4, 0.9, 0.9}));
    EXPECT_FALSE(inside(b, {1.6, 0, -1}));   // past +x only
    EXPECT_FALSE(inside(b, {1, -1.1, -1}));  // past -y only
    EXPECT_FALSE(inside(b, {1, 0, 1.1}));    // past +z only
    // Faces, edges and corners are the boundary.
    EXPECT_FALSE(inside(b, {1.5, 0, -1}));
    EXPECT_FALSE(inside(b, {1, 1, -1}));
    EXPECT_FALSE(inside(b, {1.5, 1, 1}));
    EXPECT_TRUE(inside(b, {1.5 - 1e-9, 1 - 1e-9, 1 - 1e-9}));
    EXPECT_FALSE(inside(b, {1.5 + 1e-9, 0, -1}));
}

TEST(Inside, CylinderSideAndCaps) {
    const Cylinder c{{0, 1, 0}, 1, 2};  // y in [0, 2]
    EXPECT_TRUE(inside(c, {0, 1, 0}));
    EXPECT_TRUE(inside(c, {0.6, 0.1, -0.6}));
    EXPECT_FALSE(inside(c, {0.8, 1, 0.8}));  // outside the side, between the caps
    EXPECT_FALSE(inside(c, {0, 2.5, 0}));    // above the top cap, on the axis
    EXPECT_FALSE(inside(c, {0, -0.5, 0}));   // below the bottom cap
    EXPECT_FALSE(inside(c, {1, 1, 0}));      // on the side
    EXPECT_FALSE(inside(c, {0, 2, 0}));      // on the top cap
    EXPECT_FALSE(inside(c, {0, 0, 0}));      // on the bottom cap
    EXPECT_FALSE(inside(c, {0, 0, 1}));      // on the bottom rim
    EXPECT_TRUE(inside(c, {0, 1e-9, 1 - 1e-9}));
    EXPECT_FALSE(inside(c, {0, 1, 1 + 1e-9}));
}

TEST(Inside, ConeNarrowsToTheApex) {
    const Cone k{{0, 0, 0}, 1, 2};  // base at y = -1 (radius 1), apex at y = 1
    EXPECT_TRUE(inside(k, {0, 0, 0}));
    EXPECT_TRUE(inside(k, {0.9, -0.9, 0}));
    EXPECT_FALSE(inside(k, {0.9, 0.5, 0}));  // within the base radius, outside the side
    EXPECT_FALSE(inside(k, {0, 1.5, 0}));    // above the apex
    EXPECT_FALSE(inside(k, {0, -1.5, 0}));   // below the base
    EXPECT_FALSE(inside(k, {0.5, 0, 0}));    // on the side: r (y1 - y)/h = 0.5
    EXPECT_FALSE(inside(k, {0, 1, 0}));      // the apex
    EXPECT_FALSE(inside(k, {0, -1, 0}));     // on the base disc
    EXPECT_TRUE(inside(k, {0, 1 - 1e-9, 0}));
    EXPECT_TRUE(inside(k, {0.5 - 1e-9, 0, 0}));
    EXPECT_FALSE(inside(k, {0.5 + 1e-9, 0, 0}));
}

TEST(Inside, TrianglesBoundNoSolid) {
    const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_FALSE(inside(t, {0.25, 0.25, 0}));  // on the triangle
    EXPECT_FALSE(inside(t, {0.25, 0.25, 1e-9}));
    EXPECT_FALSE(inside(t, {5, 5, 5}));
}

// A point is inside a convex solid exactly when a ray from it leaves once (outside: no hit or an
// entry and an exit): the inside test agrees with the intersection for random points and
// directions around each kind.
TEST(Inside, AgreesWithTheHitCountOfRaysFromThePoint) {
    const Shape shapes[] = {Sphere{{0.2, -0.1, 0.3}, 0.9}, Box{{0.1, 0.2, -0.1}, {0.4, 0.9, 0.6}},
                            Cylinder{{0, 0.1, 0.2}, 0.7, 1.6}, Cone{{-0.1, 0, 0.1}, 0.8, 1.8}};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    for (const Shape& shape : shapes) {
        int in = 0, out = 0;
        for (int i = 0; i < 4000; ++i) {
            const Vec3 p(u(rng), u(rng), u(rng));
            const Vec3 d = glm::normalize(Vec3(u(rng), u(rng), u(rng)) + Vec3(1e-3));
            std::visit(
                [&](const auto& s) {
                    const int hits = intersect(s, Ray{p, d}, {0.0, kInf}).count;
                    const bool is_in = inside(s, p);
                    EXPECT_EQ(is_in, hits == 1) << s.kName << " at " << p.x << " " << p.y << " "
                                                << p.z << ": " << hits << " hits";
                    (is_in ? in : out) += 1;
                },
                shape);
        }
        EXPECT_GT(in, 200);  // both sides were exercised
        EXPECT_GT(out, 200);
    }
}

// The compile step keeps an analytic shape in its own frame with the group's transform: a
// world point is inside when its image under the inverse transform is.
TEST(Inside, UnderTheTransformsTheCompileStepApplies) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#group_begin 2 0 0 5  0 1 0 0  0 0 1 0  0 0 0 1\n"  // x scaled by 2, moved to x = 5
        "#shape_sphere 0 0 0 0 1\n#group_end\n"
        "#group_begin 0.7071067811865476 0 0.7071067811865476 0  0 1 0 0"
        "  -0.7071067811865476 0 0.7071067811865476 -5  0 0 0 1\n"  // 45 degrees about y
        "#shape_box 0 0 0 0 2 2 2\n#group_end\n");
    const GeometrySet& set = scene.sets[0];
    auto inside_world = [&](const Vec3& w) {
        for (const Primitive& p : set.prims) {
            const Vec3 q = set.transforms[static_cast<size_t>(p.transform)].inv_point(w);
            if (visit_shape(set, p, [&](const auto& s) { return inside(s, q); })) return true;
        }
        return false;
    };
    EXPECT_TRUE(inside_world({6.9, 0, 0}));   // the ellipsoid reaches x = 3..7
    EXPECT_FALSE(inside_world({5, 1.1, 0}));  // but only y = -1..1
    EXPECT_FALSE(inside_world({7.1, 0, 0}));
    // The rotated cube's corners point along x and z: (1.3, 0, -5) is inside it, (0.9, 0, -4.1)
    // past a face.
    EXPECT_TRUE(inside_world({1.3, 0, -5}));
    EXPECT_FALSE(inside_world({0.9, 0, -4.1}));
    EXPECT_FALSE(inside_world({0, 0, 0}));
}

// ---- torus (spec §13.7) ----------------------------------------------------------------------

// The hit distances of a torus along a ray (every crossing in (0, inf)).
std::vector<double> torus_hits(const Torus& tor, const Ray& r, Interval t = {0, kInf}) {
    const ShapeHits h = intersect(tor, r, t);
    return std::vector<double>(h.t, h.t + h.count);
}

TEST(Torus, TheSpecsCheckValues) {
    const Torus tor{{0, 0, 0}, 1, 3};
    const Ray rx{{-10, 0, 0}, {1, 0, 0}};
    const std::vector<double> hx = torus_hits(tor, rx);
    ASSERT_EQ(hx.size(), 4u);
    const double expect[] = {6, 8, 12, 14};
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(hx[i], expect[i], kTol);
    const SurfacePoint a = surface_at(tor, rx, hx[0], 0);
    EXPECT_VEC_NEAR(a.p, Vec3(-4, 0, 0), kTol);
    EXPECT_VEC_NEAR(a.n_geometric, Vec3(-1, 0, 0), kTol);
    EXPECT_NEAR(a.uv.x, 0.25, kTol);
    EXPECT_NEAR(a.uv.y, 0.0, kTol);
    // The inner equator faces the axis: v = 1/2.
    const SurfacePoint b = surface_at(tor, rx, hx[1], 0);
    EXPECT_VEC_NEAR(b.n_geometric, Vec3(1, 0, 0), kTol);
    EXPECT_NEAR(b.uv.y, 0.5, kTol);
    const Ray down{{3, 10, 0}, {0, -1, 0}};
    const std::vector<double> hd = torus_hits(tor, down);
    ASSERT_EQ(hd.size(), 2u);
    EXPECT_NEAR(hd[0], 9, kTol);
    EXPECT_NEAR(hd[1], 11, kTol);
    const SurfacePoint top = surface_at(tor, down, hd[0], 0);
    EXPECT_VEC_NEAR(top.n_geometric, Vec3(0, 1, 0), kTol);
    EXPECT_NEAR(top.uv.x, 0.75, kTol);
    EXPECT_NEAR(top.uv.y, 0.25, kTol);
    EXPECT_NEAR(surface_at(tor, down, hd[1], 0).uv.y, 0.75, kTol);            // the bottom circle
    EXPECT_EQ(intersect(tor, {{0, 10, 0}, {0, -1, 0}}, {0, kInf}).count, 0);  // the hole
}

// The quick rejections (a line that misses the outer cylinder rho = R + r, or stays in the hole's
// cylinder rho < R - r across the slab |y| <= r) keep their edges: near-vertical lines 1e-9
// inside the tube's inner and outer equators cross it over chords of 9e-5 r, 1e-9 outside they
// miss. Vertical lines (no horizontal direction) and lines tilted by 1e-12 (through rho at y = 0).
TEST(Torus, TheHoleAndCylinderRejectionsKeepTheirEdges) {
    const Vec3 c(0.5, -1, 2);
    const Torus tor{c, 1, 3};
    const double y = std::sqrt(1.0 - (1.0 - 1e-9) * (1.0 - 1e-9));  // the chord's half-height
    for (double tilt : {0.0, 1e-12}) {
        for (double rho : {2.0 + 1e-9, 4.0 - 1e-9}) {
            const Ray ray{c + Vec3(rho - 10 * tilt, 10, 0), {tilt, -1, 0}};
            const std::vector<double> h = torus_hits(tor, ray);
            ASSERT_EQ(h.size(), 2u) << rho << " " << tilt;
            EXPECT_NEAR(h[0], 10 - y, 1e-8);
            EXPECT_NEAR(h[1], 10 + y, 1e-8);
        }
        for (double rho : {2.0 - 1e-9, 4.0 + 1e-9})
            EXPECT_TRUE(torus_hits(tor, {c + Vec3(rho - 10 * tilt, 10, 0), {tilt, -1, 0}}).empty())
                << rho;
    }
}

TEST(Torus, IntervalsOriginsInsideAndUnnormalisedDirections) {
    const Torus tor{{1, 2, 3}, 1, 3};
    const Ray r{{-9, 2, 3}, {2, 0, 0}};  // |d| = 2: distances halve
    const std::vector<double> all = torus_hits(tor, r);
    ASSERT_EQ(all.size(), 4u);
    EXPECT_NEAR(all[0], 3, kTol);
    EXPECT_NEAR(all[3], 7, kTol);
    const std::vector<double> mid = torus_hits(tor, r, {3.5, 6.5});
    ASSERT_EQ(mid.size(), 2u);
    EXPECT_NEAR(mid[0], 4, kTol);
    EXPECT_NEAR(mid[1], 6, kTol);
    // From inside the tube at (-3, 0, 0) relative to c: exit at -2, in at 2, out at 4.
    const std::vector<double> in = torus_hits(tor, {{-2, 2, 3}, {1, 0, 0}});
    ASSERT_EQ(in.size(), 3u);
    EXPECT_NEAR(in[0], 1, kTol);
    EXPECT_NEAR(in[1], 5, kTol);
    EXPECT_NEAR(in[2], 7, kTol);
    EXPECT_EQ(intersect(tor, {{-9, 2, 3}, {0, 0, 0}}, {0, kInf}).count, 0);  // no direction
}

TEST(Torus, SpindleTorusIsItsOuterSurfaceOnly) {
    const Torus tor{{0, 0, 0}, 2, 1};  // r > R: the lemon (rho + 1)^2 + y^2 = 4 is not a surface
    const std::vector<double> hx = torus_hits(tor, {{-10, 0, 0}, {1, 0, 0}});
    ASSERT_EQ(hx.size(), 2u);
    EXPECT_NEAR(hx[0], 7, kTol);
    EXPECT_NEAR(hx[1], 13, kTol);
    // Along the axis: the dimples at y = +-sqrt(3), normals (0, +-1, 0).
    const Ray axis{{0, 10, 0}, {0, -1, 0}};
    const std::vector<double> hy = torus_hits(tor, axis);
    ASSERT_EQ(hy.size(), 2u);
    EXPECT_NEAR(hy[0], 10 - std::sqrt(3.0), 1e-7);
    EXPECT_NEAR(hy[1], 10 + std::sqrt(3.0), 1e-7);
    EXPECT_VEC_NEAR(surface_at(tor, axis, hy[0], 0).n_geometric, Vec3(0, 1, 0), 1e-6);
    EXPECT_TRUE(inside(tor, {0, 0, 0}));  // the lemon is inside the solid
    EXPECT_TRUE(inside(tor, {0.5, 1.5, 0}));
    EXPECT_FALSE(inside(tor, {0, 1.8, 0}));  // above the dimple
}

// Hits, outward normals and uv at points of known (u, v): a ray aimed at the point along -n
// from outside hits it first, with that normal and those coordinates.
TEST(Torus, NormalsAndUvAtKnownPoints) {
    const Torus tor{{0.5, -1, 2}, 0.4, 1.5};
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u01(0.02, 0.98);
    for (int i = 0; i < 500; ++i) {
        const double u = u01(rng), v = u01(rng);
        const double phi = 2 * kPi * u, theta = 2 * kPi * v;
        const Vec3 dir(-std::sin(phi), 0, -std::cos(phi));
        const Vec3 n(std::cos(theta) * dir.x, std::sin(theta), std::cos(theta) * dir.z);
        const Vec3 p = tor.centre + (tor.ring + tor.tube * std::cos(theta)) * dir +
                       Vec3(0, tor.tube * std::sin(theta), 0);
        const Ray r{p + 0.3 * n, -n};  // 0.3 < R - r: nothing is in between
        const ShapeHits h = intersect(tor, r, {0, kInf});
        ASSERT_GE(h.count, 2);
        EXPECT_NEAR(h.t[0], 0.3, 1e-9);
        const SurfacePoint sp = surface_at(tor, r, h.t[0], h.part[0]);
        EXPECT_VEC_NEAR(sp.p, p, 1e-9);
        EXPECT_VEC_NEAR(sp.n_geometric, n, 1e-9);
        EXPECT_NEAR(sp.uv.x, u, 1e-9);
        EXPECT_NEAR(sp.uv.y, v, 1e-9);
    }
}

// A point is inside the (non-convex) torus exactly when a ray from it crosses the surface an odd
// number of times; ordinary, horn and spindle tori.
TEST(Torus, InsideAgreesWithTheParityOfTheCrossings) {
    const Torus tori[] = {
        {{0.1, 0.2, -0.1}, 0.35, 0.7}, {{0, 0, 0}, 0.5, 0.5}, {{0, 0, 0}, 0.8, 0.4}};
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.3, 1.3);
    for (const Torus& tor : tori) {
        int in = 0, out = 0;
        for (int i = 0; i < 4000; ++i) {
            const Vec3 p(u(rng), u(rng), u(rng));
            const Vec3 d = glm::normalize(Vec3(u(rng), u(rng), u(rng)) + Vec3(1e-3));
            const int hits = intersect(tor, Ray{p, d}, {0.0, kInf}).count;
            const bool is_in = inside(tor, p);
            EXPECT_EQ(is_in, hits % 2 == 1) << tor.tube << "/" << tor.ring << " at " << p.x << " "
                                            << p.y << " " << p.z << ": " << hits << " hits";
            (is_in ? in : out) += 1;
        }
        EXPECT_GT(in, 200);
        EXPECT_GT(out, 200);
    }
}

// The preview: every vertex on the surface (the outer one of a spindle torus) with the outward
// normal, every triangle wound counter-clockwise seen from outside; bounds hold the mesh.
TEST(Torus, TessellationHasOutwardNormalsOnTheSurface) {
    for (const Torus& tor : {Torus{{1, 2, 3}, 0.5, 2}, Torus{{0, 0, 0}, 1.5, 1}}) {
        const PreviewMesh m = tessellate(tor, 32);
        ASSERT_GT(m.triangle_count(), 32u * 8u);
        const Bounds3 b = bounds(tor);
        for (size_t i = 0; i < m.positions.size(); ++i) {
            const Vec3 q = m.positions[i] - tor.centre;
            const double rho = std::hypot(q.x, q.z);
            EXPECT_NEAR(std::hypot(rho - tor.ring, q.y), tor.tube, 1e-9);
            EXPECT_GE(rho * rho + q.y * q.y + tor.ring * tor.ring - tor.tube * tor.tube, -1e-9);
            // Outward: along the gradient of f.
            const Vec3 g = rho > 0
                               ? Vec3(q.x * (1 - tor.ring / rho), q.y, q.z * (1 - tor.ring / rho))
                               : Vec3(0, q.y, 0);
            EXPECT_GT(glm::dot(m.normals[i], g), 0.0);
            EXPECT_NEAR(glm::length(m.normals[i]), 1.0, 1e-12);
            for (int k = 0; k < 3; ++k) {
                EXPECT_GE(m.positions[i][k], b.lo[k] - 1e-12);
                EXPECT_LE(m.positions[i][k], b.hi[k] + 1e-12);
            }
        }
        for (size_t t = 0; t < m.triangle_count(); ++t) {
            const Vec3& a = m.positions[m.indices[3 * t]];
            const Vec3 c = glm::cross(m.positions[m.indices[3 * t + 1]] - a,
                                      m.positions[m.indices[3 * t + 2]] - a);
            EXPECT_GT(glm::dot(c, m.normals[m.indices[3 * t]]), 0.0);
        }
    }
}

TEST(Torus, BoundsUnderAMatrixAreTight) {
    const Torus tor{{0.3, -0.2, 1}, 0.25, 1.2};
    Mat4 m = glm::rotate(Mat4(1.0), 0.7, Vec3(1, 2, 0.5));
    m = glm::scale(m, Vec3(2, 0.5, 1.5));
    m[3] = glm::dvec4(4, -5, 6, 1);
    const Bounds3 b = bounds(tor, m);
    const PreviewMesh mesh = tessellate(tor, 720);
    Bounds3 seen;
    for (const Vec3& p : mesh.positions) seen.extend(Vec3(m * glm::dvec4(p, 1.0)));
    for (int k = 0; k < 3; ++k) {
        EXPECT_LE(b.lo[k], seen.lo[k] + 1e-12);
        EXPECT_GE(b.hi[k], seen.hi[k] - 1e-12);
        EXPECT_NEAR(b.lo[k], seen.lo[k], 1e-3);  // exact up to the mesh's sampling
        EXPECT_NEAR(b.hi[k], seen.hi[k], 1e-3);
    }
    const Bounds3 local = bounds(tor, Mat4(1.0));
    EXPECT_VEC_NEAR(local.lo, bounds(tor).lo, 1e-12);
    EXPECT_VEC_NEAR(local.hi, bounds(tor).hi, 1e-12);
}

// A torus reaches the renderer from code (V3 files are not parsed yet): through a compiled
// scene's BVH it is hit as directly; the V0/V1 writer refuses it.
TEST(Torus, ThroughACompiledSceneAndRefusedByTheWriter) {
    SceneDesc desc = test::parse(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#shape_sphere 0 0 0 -30 1\n#shape_sphere 0 0 0 0 1\n");
    desc.files[0].root.shapes[1].geometry = Torus{{0, 0, 0}, 1, 3};
    const RenderScene scene = compile_scene(desc);
    Hit hit;
    ASSERT_TRUE(intersect(scene, {{-10, 0, 0}, {1, 0, 0}}, {0, kInf}, &hit));
    EXPECT_NEAR(hit.t, 6, kTol);
    EXPECT_FALSE(occluded(scene, {{0, 10, 0}, {0, -1, 0}}, 20));  // through the hole
    EXPECT_TRUE(occluded(scene, {{3, 10, 0}, {0, -1, 0}}, 20));
    EXPECT_THROW(write_scene(desc), SceneError);
    EXPECT_STREQ(shape_kind_name(ShapeKind::Torus), "torus");
}

// ---- dispatch -------------------------------------------------------------------------------

TEST(VisitShape, CallsWithThePrimitivesConcreteShape) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 0 0 0 0 0 0 0\n#vertex 0 1 0 0 0 0 0 0\n"
        "#shape_sphere 0 0 0 0 1\n#shape_box 0 3 0 0 1 1 1\n#shape_cylinder 0 6 0 0 1 1\n"
        "#shape_cone 0 9 0 0 1 1\n#shape_triangle 0 0 1 2\n#shape_sphere 0 12 0 0 2\n");
    const GeometrySet& set = scene.sets[0];
    ASSERT_EQ(set.prims.size(), 6u);
    int spheres = 0;
    for (const Primitive& p : set.prims) {
        const ShapeKind k =
            visit_shape(set, p, [](const auto& s) { return std::decay_t<decltype(s)>::kKind; });
        EXPECT_EQ(k, p.kind);
        // The shape handed over is the primitive's own: its bounds are the set's.
        const Bounds3 b = visit_shape(set, p, [](const auto& s) { return bounds(s); });
        EXPECT_VEC_NEAR(b.lo, set.prim_bounds(static_cast<size_t>(&p - set.prims.data())).lo, 1e-9);
        if (p.kind == ShapeKind::Sphere) {
            // A dispatch narrowed to one kind calls without looking at the kind.
            const double r = visit_shape<kind_bit(ShapeKind::Sphere)>(
                set, p, [](const Sphere& s) { return s.radius; });
            EXPECT_TRUE(r == 1.0 || r == 2.0);
            ++spheres;
        }
    }
    EXPECT_EQ(spheres, 2);
    EXPECT_STREQ(shape_kind_name(ShapeKind::Cone), "cone");
    EXPECT_STREQ(shape_kind_name(ShapeKind::Triangle), "triangle");
}

TEST(VisitShape, BoundsOfADescribedShapeUnderAMatrix) {
    const SceneDesc desc = test::parse(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 0 0 0 0 0 0 0\n#vertex 0 1 0 0 0 0 0 0\n"
        "#shape_box 0 1 2 3 2 4 6\n#shape_cone 0 0 0 0 1 2\n#shape_triangle 0 0 1 2\n");
    const FileDesc& f = desc.files[0];
    Mat4 m(1.0);
    m[3] = glm::dvec4(10, 0, 0, 1);                      // translate by +10 x
    const Bounds3 box = bounds(f.root.shapes[0], f, m);  // full sizes: half extents 1, 2, 3
    EXPECT_VEC_NEAR(box.lo, Vec3(10, 0, 0), 1e-12);
    EXPECT_VEC_NEAR(box.hi, Vec3(12, 4, 6), 1e-12);
    const Bounds3 cone = bounds(f.root.shapes[1], f, m);
    EXPECT_VEC_NEAR(cone.lo, Vec3(9, -1, -1), 1e-12);
    EXPECT_VEC_NEAR(cone.hi, Vec3(11, 1, 1), 1e-12);
    const Bounds3 tri = bounds(f.root.shapes[2], f, m);
    EXPECT_VEC_NEAR(tri.lo, Vec3(10, 0, 0), 1e-12);
    EXPECT_VEC_NEAR(tri.hi, Vec3(11, 1, 0), 1e-12);
}

}  // namespace
}  // namespace rt
