// Shape tests: hits, outward normals and texture coordinates of spec §5, in the local frame and
// through groups with rotation and non-uniform scale; the inside test of each solid; the one
// dispatch on a primitive's kind (visit_shape) and the bounds of a described shape.
#include <random>

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
        EXPECT_VEC_NEAR(b.lo, set.prim_bounds[&p - set.prims.data()].lo, 1e-9);
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
