// Shape tests: hits, outward normals and texture coordinates of spec §5, in the local frame and
// through groups with rotation and non-uniform scale.
#include "rt/accel/intersect.h"
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

}  // namespace
}  // namespace rt
