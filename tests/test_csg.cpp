// Constructive solid geometry (spec §13.8) from the description to the queries: the valid
// surfaces of union, intersection and difference (the lens and ring of _lens.ray), their
// normals and materials, transforms and instances under CSG nodes, empty operands, shadows
// through transparent CSG, the BVH walk against brute force, the plan's leave-out, and the
// extreme cases (scales 1e-6 and 1e6, far and grazing rays, acne, deep nesting). Scenes are
// SceneDesc values built in code.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "render/variants.h"
#include "rt/accel/intersect.h"
#include "rt/compile/compile.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/scene/scene_desc.h"
#include "test_util.h"

namespace rt {
namespace {

// ---------------------------------------------------------------------------------------------
// Building descriptions.

MaterialDesc material(const Vec3& diffuse, double t = 0.0) {
    MaterialDesc m;
    m.diffuse = diffuse;
    m.transparent = Vec3(t);
    return m;
}

ShapeDesc sphere(int m, const Vec3& c, double r) { return {{}, m, Sphere{c, r}}; }
ShapeDesc box(int m, const Vec3& c, const Vec3& size) { return {{}, m, BoxDesc{c, size}}; }
ShapeDesc cylinder(int m, const Vec3& c, double r, double h) { return {{}, m, Cylinder{c, r, h}}; }
ShapeDesc torus(int m, const Vec3& c, double tube, double ring) {
    return {{}, m, Torus{c, tube, ring}};
}

GroupDesc of(const ShapeDesc& s, const Mat4& m = Mat4(1.0)) {
    GroupDesc g;
    g.matrix = m;
    g.shapes.push_back(s);
    return g;
}
GroupDesc of(const CsgDesc& c, const Mat4& m = Mat4(1.0)) {
    GroupDesc g;
    g.matrix = m;
    g.csgs.push_back(c);
    return g;
}
CsgDesc csg(CsgOp op, std::vector<GroupDesc> operands) {
    CsgDesc c;
    c.op = op;
    c.operands = std::move(operands);
    return c;
}

// A V3 scene of one file with two materials: 0 red, 1 green (transparency t for both).
SceneDesc scene_of(GroupDesc root, double t = 0.0) {
    SceneDesc d;
    d.dialect = Dialect::V3;
    FileDesc f;
    f.path = "test.ray";
    f.materials = {material({1, 0, 0}, t), material({0, 1, 0}, t)};
    f.root = std::move(root);
    d.files.push_back(std::move(f));
    return d;
}

// The lens of _lens.ray: two spheres and a cylinder intersected (material 0).
CsgDesc lens(double s = 1.0, const Vec3& c = Vec3(0.0)) {
    return csg(CsgOp::Intersection,
               {of(sphere(0, c + s * Vec3(0, -0.95, 0), 1.5 * s)),
                of(sphere(0, c + s * Vec3(0, 0.95, 0), 1.5 * s)), of(cylinder(0, c, s, 2 * s))});
}
// The ring of _lens.ray: a cylinder minus a thinner, taller one (material 1).
CsgDesc ring(double s = 1.0, const Vec3& c = Vec3(0.0)) {
    return csg(CsgOp::Difference, {of(cylinder(1, c, 1.1 * s, 0.3 * s)), of(cylinder(1, c, s, s))});
}

GroupDesc lens_file() {
    GroupDesc root;
    root.csgs = {lens(), ring()};
    return root;
}

struct Probe {
    bool hit = false;
    double t = 0.0;
    SurfaceInteraction si;
};
Probe probe(const RenderScene& scene, const Vec3& o, const Vec3& d) {
    Probe p;
    Hit h;
    const Ray r{o, d};
    p.hit = intersect(scene, r, {0.0, kInf}, &h);
    if (p.hit) {
        p.t = h.t;
        p.si = interaction(scene, r, h);
    }
    return p;
}

// ---------------------------------------------------------------------------------------------
// Compiled structure.

TEST(Csg, CompilesToOnePrimitivePerNodeWithItsBounds) {
    const RenderScene s = compile_scene(scene_of(lens_file()));
    ASSERT_EQ(s.sets.size(), 1u);
    const GeometrySet& set = s.sets[0];
    EXPECT_EQ(set.layout, SetLayout::Mixed);
    ASSERT_EQ(set.prims.size(), 2u);
    ASSERT_EQ(set.csg.roots.size(), 2u);
    EXPECT_EQ(set.csg.leaves.size(), 5u);
    EXPECT_EQ(set.csg.operations(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        const Primitive& p = set.prims[i];
        ASSERT_GE(p.csg, 0);
        const CsgRoot& r = set.csg.roots[static_cast<size_t>(p.csg)];
        const Bounds3 b = set.prim_bounds(i);
        if (r.leaf_count == 3) {  // the lens: the intersection of the boxes
            EXPECT_VEC_NEAR(b.lo, Vec3(-1, -0.55, -1), 1e-6);  // grown by the tolerance
            EXPECT_VEC_NEAR(b.hi, Vec3(1, 0.55, 1), 1e-6);
            EXPECT_LE(b.hi.x, 1 + 1e-6);
        } else {  // the ring: A's box
            EXPECT_EQ(r.leaf_count, 2u);
            EXPECT_VEC_NEAR(b.lo, Vec3(-1.1, -0.15, -1.1), 1e-12);
            EXPECT_VEC_NEAR(b.hi, Vec3(1.1, 0.15, 1.1), 1e-12);
        }
    }
    // No camera: the default camera frames the CSG boxes.
    EXPECT_VEC_NEAR(s.world_bounds.lo, Vec3(-1.1, -0.55, -1.1), 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Valid surfaces, normals, materials (spec §13.8).

TEST(Csg, LensAndRingHitsNormalsAndMaterials) {
    const RenderScene s = compile_scene(scene_of(lens_file()));
    // Down the axis: the lens top, on the sphere centred below (the spheres' other halves and
    // the cylinder's caps are outside the other operands).
    Probe p = probe(s, {0, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.45, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-12);
    EXPECT_EQ(p.si.material, 0);
    p = probe(s, {0, -10, 0}, {0, 1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.45, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, -1, 0), 1e-12);
    // Off axis, over the ring's hole: the ring's caps there are inside B, B's caps outside A.
    p = probe(s, {0.5, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10 - (std::sqrt(2.0) - 0.95), 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0.5, std::sqrt(2.0), 0) / 1.5, 1e-12);
    EXPECT_EQ(p.si.material, 0);
    p = probe(s, {0.99, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10 - (std::sqrt(2.25 - 0.99 * 0.99) - 0.95), 1e-12);
    // The ring's top cap, material 1.
    p = probe(s, {1.05, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.85, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-12);
    EXPECT_EQ(p.si.material, 1);
    // Sideways: the ring's outer wall, then (above the ring) the lens rim, the cylinder's side.
    p = probe(s, {-10, 0.1, 0}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 8.9, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(-1, 0, 0), 1e-12);
    EXPECT_EQ(p.si.material, 1);
    p = probe(s, {-10, 0.16, 0}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.0, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(-1, 0, 0), 1e-12);
    EXPECT_EQ(p.si.material, 0);
    // Over the lens rim's height: the spheres there are outside each other, the cylinder's side
    // outside the spheres: nothing.
    EXPECT_FALSE(probe(s, {-10, 0.9, 0}, {1, 0, 0}).hit);
    EXPECT_FALSE(occluded(s, Ray{{-10, 0.9, 0}, {1, 0, 0}}, 20.0));
}

TEST(Csg, DifferenceInnerWallFacesIntoTheHole) {
    GroupDesc root;
    root.csgs = {ring()};
    const RenderScene s = compile_scene(scene_of(root));
    Probe p = probe(s, {0, 0, 0}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 1.0, 1e-12);
    // B's outward normal (1,0,0), negated: it faces out of A - B, into the hole.
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(-1, 0, 0), 1e-12);
    EXPECT_VEC_NEAR(p.si.n_shading, Vec3(-1, 0, 0), 1e-12);
    EXPECT_EQ(p.si.material, 1);
    // Down through the hole: B's caps are outside A, A's caps inside B.
    EXPECT_FALSE(probe(s, {0.5, 10, 0}, {0, -1, 0}).hit);
    EXPECT_FALSE(occluded(s, Ray{{0.5, 10, 0}, {0, -1, 0}}, 20.0));
}

TEST(Csg, UnionOfCoplanarFacesHasNoHoles) {
    // Two overlapping boxes sharing their top, bottom and side planes, and two that only touch.
    GroupDesc root;
    root.csgs = {
        csg(CsgOp::Union, {of(box(0, {-0.25, 0, 0}, Vec3(1))), of(box(1, {0.25, 0, 0}, Vec3(1)))}),
        csg(CsgOp::Union, {of(box(0, {-0.5, 0, 5}, Vec3(1))), of(box(1, {0.5, 0, 5}, Vec3(1)))})};
    const RenderScene s = compile_scene(scene_of(root));
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.99, 0.99), v(-0.49, 0.49);
    int holes = 0, wrong_normal = 0;
    for (int i = 0; i < 4000; ++i) {
        const double x = i < 2 ? (i - 0.5) * 1e-16 : u(rng);  // both sides of the seam
        const double z = (i % 2) * 5 + v(rng);
        const double xx = i % 2 ? x : 0.75 * x;
        const Probe p = probe(s, {xx, 10, z}, {0, -1, 0});
        if (!p.hit || std::abs(p.t - 9.5) > 1e-12) ++holes;
        if (p.hit && glm::length(p.si.n_geometric - Vec3(0, 1, 0)) > 1e-12) ++wrong_normal;
    }
    EXPECT_EQ(holes, 0);
    EXPECT_EQ(wrong_normal, 0);
}

// A = [-1,1]^3 minus B, B a unit box at (0, b_y, 0) scaled by s about c.
GroupDesc pocket(double s, const Vec3& c, double b_y) {
    GroupDesc root;
    root.csgs = {csg(CsgOp::Difference,
                     {of(box(0, c, Vec3(2 * s))), of(box(1, c + Vec3(0, b_y * s, 0), Vec3(s)))})};
    return root;
}

TEST(Csg, DifferenceKeepsAsFaceWhereItCoincidesWithB) {
    // B's top lies in A's top: the lid stays (the point is on B, not strictly inside it).
    const RenderScene lid = compile_scene(scene_of(pocket(1, Vec3(0.0), 0.5)));
    Probe p = probe(lid, {0, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.0, 1e-12);
    EXPECT_EQ(p.si.material, 0);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-12);
    // Through the lid: B's bottom (strictly inside A), facing up out of A - B.
    p = probe(lid, {0, 0.9, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 0.9, 1e-12);
    EXPECT_EQ(p.si.material, 1);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-12);
    // B one half higher: a pocket, open at the top.
    const RenderScene open = compile_scene(scene_of(pocket(1, Vec3(0.0), 1.0)));
    p = probe(open, {0.2, 10, 0.1}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.5, 1e-12);
    EXPECT_EQ(p.si.material, 1);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-12);
    // B's side wall, seen from inside the pocket, faces into it.
    p = probe(open, {0, 0.75, 0}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 0.5, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(-1, 0, 0), 1e-12);
}

TEST(Csg, NestedNodesFilterAtEveryLevel) {
    // (big sphere - small sphere) intersected with a box cutting the top off, minus nothing else.
    const CsgDesc shell =
        csg(CsgOp::Difference, {of(sphere(0, Vec3(0), 2)), of(sphere(1, Vec3(0), 1))});
    GroupDesc root;
    root.csgs = {csg(CsgOp::Intersection, {of(shell), of(box(1, {0, -2, 0}, Vec3(6, 4, 6)))})};
    const RenderScene s = compile_scene(scene_of(root));
    // From above: the box's top at y = 0 where it is inside the shell (1 < |p| < 2).
    Probe p = probe(s, {1.5, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10.0, 1e-12);
    EXPECT_EQ(p.si.material, 1);
    // On the axis the box's top is inside the inner sphere, the hole (outside A - B), so the ray
    // falls through the hole onto the inner sphere's bottom half, whose normal is negated once
    // (one difference with it in B).
    p = probe(s, {0, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 11.0, 1e-9);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-9);
    EXPECT_EQ(p.si.material, 1);
    // The outer sphere's bottom from below: kept by both nodes.
    p = probe(s, {0, -10, 0}, {0, 1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 8.0, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, -1, 0), 1e-12);
    EXPECT_EQ(p.si.material, 0);
    // A difference inside the B of a difference: its B's surface is negated twice.
    const CsgDesc inner =
        csg(CsgOp::Difference, {of(box(0, Vec3(0), Vec3(2))), of(sphere(1, Vec3(0), 0.5))});
    GroupDesc root2;
    root2.csgs = {csg(CsgOp::Difference, {of(sphere(0, Vec3(0), 3)), of(inner)})};
    const RenderScene s2 = compile_scene(scene_of(root2));
    // Inside the big sphere's cavity (the box) a ball of the big sphere's material remains:
    // the small sphere's surface, in B of the inner and in B of the outer difference.
    p = probe(s2, {0, 0.9, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 0.4, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-12);
    EXPECT_EQ(p.si.material, 1);
    // The box's wall faces into the cavity.
    p = probe(s2, {0, 0.75, 0}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 1.0, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(-1, 0, 0), 1e-12);
}

TEST(Csg, TransformsAndInstancesUnderCsgNodes) {
    // Union of a sphere at the origin and, through a translate-scale, a sphere of radius 2 at
    // x = 3 (locally r = 1 at the origin); the whole CSG inside a group moved by z = -5.
    const Mat4 move = glm::scale(glm::translate(Mat4(1.0), Vec3(3, 0, 0)), Vec3(2.0));
    GroupDesc g;
    g.matrix = glm::translate(Mat4(1.0), Vec3(0, 0, -5));
    g.csgs = {csg(CsgOp::Union, {of(sphere(0, Vec3(0), 1.5)), of(sphere(1, Vec3(0), 1), move)})};
    GroupDesc root;
    root.groups = {g};
    RenderScene s = compile_scene(scene_of(root));
    // Along x at z = -5: the small sphere's far half is inside the big one; the big one's
    // near half is not inside the small one.
    Probe p = probe(s, {-10, 0, -5}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 8.5, 1e-12);
    EXPECT_EQ(p.si.material, 0);
    p = probe(s, {0, 0, -5}, {1, 0, 0});  // from inside: the small sphere's exit is inside
    ASSERT_TRUE(p.hit);                   // the big one: it hits the big sphere's far side
    EXPECT_NEAR(p.t, 5.0, 1e-12);
    EXPECT_EQ(p.si.material, 1);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(1, 0, 0), 1e-12);

    // An instance as an operand: file 1 (its own materials) holds a box; the difference of the
    // top file's sphere minus the instance, itself moved by x = 10.
    SceneDesc d = scene_of(GroupDesc{});
    FileDesc f1;
    f1.path = "part.ray";
    f1.materials = {material({0, 0, 1})};
    f1.root.shapes = {box(0, Vec3(0), Vec3(2))};
    d.files.push_back(f1);
    d.files[0].ray_files = {1};
    GroupDesc inst;
    inst.matrix = glm::translate(Mat4(1.0), Vec3(1, 0, 0));
    inst.instances = {InstanceDesc{{}, 0}};
    GroupDesc top;
    top.matrix = glm::translate(Mat4(1.0), Vec3(10, 0, 0));
    top.csgs = {csg(CsgOp::Difference, {of(sphere(0, Vec3(0), 1.5)), inst})};
    d.files[0].root.groups = {top};
    s = compile_scene(d);
    ASSERT_EQ(s.instances.size(), 1u);  // the instance under the CSG is flattened into its set
    p = probe(s, {20, 0, 0}, {-1, 0, 0});
    ASSERT_TRUE(p.hit);  // the instanced box's face x = -1 (moved to x = 10), facing +x
    EXPECT_NEAR(p.t, 10.0, 1e-12);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(1, 0, 0), 1e-12);
    EXPECT_GE(p.si.material, 2);  // file 1's material
    EXPECT_EQ(s.materials[static_cast<size_t>(p.si.material)].diffuse, Vec3(0, 0, 1));
    p = probe(s, {9.5, 0, 10}, {0, 0, -1});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10 - std::sqrt(2.25 - 0.25), 1e-12);
    EXPECT_EQ(p.si.material, 0);

    // A CSG file instanced twice: each copy filters in its own frame.
    SceneDesc d2 = scene_of(GroupDesc{});
    FileDesc lensf;
    lensf.path = "lens.ray";
    lensf.materials = d2.files[0].materials;
    lensf.root = lens_file();
    d2.files.push_back(lensf);
    d2.files[0].ray_files = {1};
    for (double x : {-5.0, 5.0}) {
        GroupDesc gi;
        gi.matrix = glm::scale(glm::translate(Mat4(1.0), Vec3(x, 0, 0)), Vec3(2.0));
        gi.instances = {InstanceDesc{{}, 0}};
        d2.files[0].root.groups.push_back(gi);
    }
    s = compile_scene(d2);
    ASSERT_EQ(s.instances.size(), 2u);
    for (double x : {-5.0, 5.0}) {
        p = probe(s, {x, 10, 0}, {0, -1, 0});
        ASSERT_TRUE(p.hit);
        EXPECT_NEAR(p.t, 10 - 1.1, 1e-12);
        EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-12);
        p = probe(s, {x, 0, 0}, {1, 0, 0});  // the ring's inner wall from the lens: a tie
        ASSERT_TRUE(p.hit);                  // between coincident surfaces, either is fine
        EXPECT_NEAR(p.t, 2.0, 1e-12);
    }
}

TEST(Csg, EmptyOperands) {
    const GroupDesc empty;
    GroupDesc root;
    root.csgs = {csg(CsgOp::Union, {empty, of(sphere(0, {0, 0, 0}, 1))}),
                 csg(CsgOp::Intersection, {empty, of(sphere(0, {5, 0, 0}, 1))}),
                 csg(CsgOp::Difference, {of(sphere(1, {10, 0, 0}, 1)), empty}),
                 csg(CsgOp::Difference, {empty, of(sphere(1, {15, 0, 0}, 1))}),
                 csg(CsgOp::Union, {}),
                 csg(CsgOp::Intersection, {})};
    const RenderScene s = compile_scene(scene_of(root));
    ASSERT_EQ(s.sets.size(), 1u);
    EXPECT_EQ(s.sets[0].prims.size(), 2u);  // the nodes without a surface are left out
    EXPECT_TRUE(probe(s, {0, 10, 0}, {0, -1, 0}).hit);
    EXPECT_FALSE(probe(s, {5, 10, 0}, {0, -1, 0}).hit);
    const Probe p = probe(s, {10, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.0, 1e-12);
    EXPECT_FALSE(probe(s, {15, 10, 0}, {0, -1, 0}).hit);
    // Only empty nodes: no set at all.
    GroupDesc none;
    none.csgs = {
        csg(CsgOp::Union, {empty}),
        csg(CsgOp::Intersection, {of(sphere(0, {0, 0, 0}, 1)), of(sphere(0, {9, 0, 0}, 1))})};
    EXPECT_TRUE(compile_scene(scene_of(none)).instances.empty());
}

// A CSG tree's triangles from two files, each numbering its own vertices from 0: the instanced
// file's triangle has its own corners, not the top file's vertices of the same numbers.
TEST(Csg, TrianglesOfAnInstancedFileKeepTheirOwnVertices) {
    auto triangle_file = [](double z) {
        FileDesc f;
        f.vertices = {VertexDesc{{-1, -1, z}}, VertexDesc{{1, -1, z}}, VertexDesc{{0, 1, z}}};
        f.root.shapes = {ShapeDesc{{}, 0, TriangleDesc{{0, 1, 2}}}};
        return f;
    };
    SceneDesc d = scene_of(GroupDesc{});
    FileDesc part = triangle_file(-5);
    part.path = "part.ray";
    part.materials = {material({0, 0, 1})};
    d.files.push_back(part);
    FileDesc& top = d.files[0];
    top.vertices = triangle_file(0).vertices;
    top.ray_files = {1};
    GroupDesc inst;
    inst.instances = {InstanceDesc{{}, 0}};
    top.root.csgs = {csg(CsgOp::Union, {of(ShapeDesc{{}, 0, TriangleDesc{{0, 1, 2}}}), inst})};
    const RenderScene s = compile_scene(d);
    for (const double z : {0.0, -5.0}) {
        const Probe p = probe(s, {0, 0, z - 0.5}, {0, 0, 1});
        ASSERT_TRUE(p.hit) << "nothing at z = " << z;
        EXPECT_NEAR(p.t, 0.5, 1e-12) << "the triangle at z = " << z;
    }
}

// A tree dropped for having no surface takes its leaves' shapes back: here its triangle would
// sit in front of the floor's in a triangles-only set, where prims[i] is triangles[i].
TEST(Csg, ADroppedTreeLeavesNoShapesBehind) {
    const std::string head =
        "#camera 0 4 4  0 -1 -1  0 1 0  0.5\n#light_dir 0 0 0  1 1 1  1 1 1  0 -1 0\n"
        "#material 0 0 0  0 0 0  0.8 0.8 0.8  0 0 0  1  0 0 0  1  -1 !!\n"
        "#vertex -2 0 -2  0 0 0  0 0\n#vertex 2 0 -2  0 0 0  0 0\n"
        "#vertex 2 0 2  0 0 0  0 0\n#vertex -2 0 2  0 0 0  0 0\n"
        "#vertex 9 0 9  0 0 0  0 0\n#vertex 10 0 9  0 0 0  0 0\n#vertex 9 0 10  0 0 0  0 0\n";
    const std::string floor =
        "#shape_triangles 0 #shape_list_begin #shape_triangle 0 2 1 #shape_triangle 0 3 2 "
        "#shape_list_end\n";
    const std::string dropped =
        "#shape_intersection #shape_list_begin\n"
        "  #shape_triangles 0 #shape_list_begin #shape_triangle 4 5 6 #shape_list_end\n"
        "  #shape_sphere 0 -20 0 0 1\n#shape_list_end\n";
    const RenderScene with = test::compile(head + dropped + floor);
    const RenderScene without = test::compile(head + floor);
    ASSERT_EQ(with.sets.size(), 1u);
    EXPECT_EQ(with.sets[0].triangle_count(), 2u);
    EXPECT_EQ(with.sets[0].prims.size(), 2u);
    EXPECT_EQ(test::render(with, 32, 24).rgb, test::render(without, 32, 24).rgb);
}

// Boxes 1e-10 apart: each one's face is "on" the other within the tolerance (spec §13.8), so the
// intersection is that face, and its box, grown by more than the tolerance, does not cull it.
TEST(Csg, AnIntersectionOfTouchingBoxesKeepsTheFace) {
    const RenderScene s = test::compile(
        "#material 0 0 0  0 0 0  0.8 0.8 0.8  0 0 0  1  0 0 0  1  -1 !!\n"
        "#shape_intersection #shape_list_begin\n"
        "  #shape_box 0  0 -0.5 0  1 1 1\n  #shape_box 0  0 0.5000000001 0  1 1 1\n"
        "#shape_list_end\n");
    ASSERT_EQ(s.instances.size(), 1u);
    const Probe p = probe(s, {0.2, 5, 0.3}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 5.0, 1e-9);
    EXPECT_FALSE(probe(s, {0.2, 5, 0.7}, {0, -1, 0}).hit);  // beside the boxes
}

TEST(Csg, TorusInACsgNode) {
    // Spec §13.7's torus (r = 1, R = 3) minus the half space x > 0 (a big box).
    GroupDesc root;
    root.csgs = {
        csg(CsgOp::Difference, {of(torus(0, Vec3(0), 1, 3)), of(box(1, {5, 0, 0}, Vec3(10)))})};
    const RenderScene s = compile_scene(scene_of(root));
    Probe p = probe(s, {-10, 0, 0}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 6.0, 1e-9);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(-1, 0, 0), 1e-9);
    // From the cut side: the torus's hits at x = 4 and 2 are inside B, B's face x = 0 at the
    // centre is outside A, so the first valid surface is the tube's inside at x = -2.
    p = probe(s, {10, 0, 0}, {-1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 12.0, 1e-9);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(1, 0, 0), 1e-9);
    EXPECT_EQ(p.si.material, 0);
    // Through the cut tube at x = 3: B's face at x = 0 is not there; at z = 3 it is the cut face
    // (strictly inside the tube), facing out of A - B (-x).
    p = probe(s, {10, 0, 3}, {-1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10.0, 1e-9);
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(1, 0, 0), 1e-12);
    EXPECT_EQ(p.si.material, 1);
    // A torus as the cutter: a box minus the torus leaves the tube's groove.
    GroupDesc root2;
    root2.csgs = {csg(CsgOp::Difference,
                      {of(box(0, {0, -1, 0}, Vec3(10, 2, 10))), of(torus(1, Vec3(0), 0.5, 3))})};
    const RenderScene s2 = compile_scene(scene_of(root2));
    p = probe(s2, {3, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10.5, 1e-9);  // the groove's bottom, the tube's bottom
    EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-9);
    p = probe(s2, {0, 10, 0}, {0, -1, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10.0, 1e-12);
}

TEST(Csg, TrianglesAreNeverInside) {
    // A big triangle through a unit sphere, in a union and as the B of a difference.
    auto scene = [](CsgOp op) {
        ShapeDesc tri{{}, 1, TriangleDesc{{0, 1, 2}}};
        GroupDesc root;
        root.csgs = {csg(op, {of(sphere(0, Vec3(0), 1)), of(tri)})};
        SceneDesc d = scene_of(root);
        for (const Vec3& v : {Vec3(-3, -3, 0), Vec3(3, -3, 0), Vec3(0, 3, 0)}) {
            VertexDesc vd;
            vd.position = v;
            d.files[0].vertices.push_back(vd);
        }
        return compile_scene(d);
    };
    const RenderScene u = scene(CsgOp::Union), d = scene(CsgOp::Difference);
    // Union: the triangle inside the sphere is dropped, outside kept; the sphere everywhere.
    Probe p = probe(u, {0, 0, 0.5}, {0, 0, -1});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 1.5, 1e-12);
    EXPECT_EQ(p.si.material, 0);
    p = probe(u, {2, -2, 10}, {0, 0, -1});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10.0, 1e-6);
    EXPECT_EQ(p.si.material, 1);
    const Vec3 n = p.si.n_geometric;
    EXPECT_NEAR(std::abs(n.z), 1.0, 1e-6);
    EXPECT_NEAR(probe(u, {0, 0, 10}, {0, 0, -1}).t, 9.0, 1e-12);
    // Difference: the sphere is never inside the triangle, so all of it stays; the triangle
    // inside the sphere stays too, its normal negated; outside it is gone.
    EXPECT_NEAR(probe(d, {0, 0, 10}, {0, 0, -1}).t, 9.0, 1e-12);
    p = probe(d, {0, 0, 0.5}, {0, 0, -1});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 0.5, 1e-6);
    EXPECT_EQ(p.si.material, 1);
    EXPECT_VEC_NEAR(p.si.n_geometric, -n, 1e-6);
    EXPECT_FALSE(probe(d, {2, -2, 10}, {0, 0, -1}).hit);
}

TEST(Csg, ShadowsCountOnlyValidCrossings) {
    const RenderScene s = compile_scene(scene_of(lens_file(), 0.5));
    // Down the axis: the lens's top and bottom only (the leaves cross six times).
    const Ray down{{0, 10, 0}, {0, -1, 0}};
    EXPECT_VEC_NEAR(transmittance(s, down, 20.0), Vec3(0.25), 1e-15);
    // Through the ring's wall, sideways: outer wall, inner wall (B), then the lens's rim tie
    // is avoided at y = 0.16 (above the ring): the lens rim twice.
    EXPECT_VEC_NEAR(transmittance(s, Ray{{-10, 0.16, 0}, {1, 0, 0}}, 20.0), Vec3(0.25), 1e-15);
    EXPECT_VEC_NEAR(transmittance(s, Ray{{-10, 0.9, 0}, {1, 0, 0}}, 20.0), Vec3(1.0), 0);
    // The plan's walk gives the same.
    RenderSettings rs;
    rs.width = rs.height = 8;
    const RenderPlan plan = make_render_plan(s, rs);
    EXPECT_VEC_NEAR(transmittance(s, plan, down, 20.0), Vec3(0.25), 1e-15);
    EXPECT_VEC_NEAR(transmittance(s, plan, Ray{{-10, 0.9, 0}, {1, 0, 0}}, 20.0), Vec3(1.0), 0);
    EXPECT_FALSE(occluded(s, plan, Ray{{-10, 0.9, 0}, {1, 0, 0}}, 20.0));
    EXPECT_TRUE(occluded(s, plan, down, 20.0));
    EXPECT_FALSE(occluded(s, plan, down, 9.0));
}

// A scene of many CSG nodes, plain shapes and an instance, for walk comparisons.
SceneDesc busy_scene() {
    GroupDesc root = lens_file();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-4, 4);
    for (int i = 0; i < 12; ++i) {
        const Vec3 c(u(rng), u(rng), u(rng));
        std::vector<GroupDesc> ops = {of(sphere(0, c, 0.8)), of(box(1, c + Vec3(0.4), Vec3(1)))};
        if (i % 3 != 2) ops.push_back(of(cylinder(0, c, 0.3, 3)));  // a difference has two
        root.csgs.push_back(csg(static_cast<CsgOp>(i % 3), ops));
        root.shapes.push_back(sphere(1, Vec3(u(rng), u(rng), u(rng)), 0.3));
    }
    GroupDesc rot;
    rot.matrix = glm::rotate(Mat4(1.0), 0.7, Vec3(1, 2, 3));
    rot.csgs = {
        csg(CsgOp::Difference, {of(torus(0, Vec3(0), 0.4, 1.5)), of(sphere(1, {1.5, 0, 0}, 0.6))})};
    root.groups.push_back(rot);
    return scene_of(root, 0.5);
}

TEST(Csg, BruteForceAndEveryWalkAgree) {
    const RenderScene s = compile_scene(busy_scene());
    RenderSettings rs;
    rs.width = rs.height = 8;
    const RenderPlan plan = make_render_plan(s, rs);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-6, 6);
    std::normal_distribution<double> g;
    int hits = 0, differ = 0, differ_plan = 0, differ_shadow = 0;
    for (int i = 0; i < 20000; ++i) {
        const Ray r{{u(rng), u(rng), u(rng)}, glm::normalize(Vec3(g(rng), g(rng), g(rng)))};
        Hit a, b, c;
        const bool ha = intersect(s, r, {0, kInf}, &a),
                   hb = intersect_brute_force(s, r, {0, kInf}, &b),
                   hc = intersect(s, plan, r, {0, kInf}, &c);
        hits += ha;
        if (ha != hb || (ha && (a.t != b.t || a.leaf != b.leaf || a.prim != b.prim))) ++differ;
        if (ha != hc || (ha && (a.t != c.t || a.leaf != c.leaf))) ++differ_plan;
        // The nearest hit is also the first crossing that stops an opaque shadow ray.
        if (occluded(s, plan, r, 30.0) != (ha && a.t < 30.0)) ++differ_shadow;
    }
    EXPECT_GT(hits, 1500);
    EXPECT_EQ(differ, 0);
    EXPECT_EQ(differ_plan, 0);
    EXPECT_EQ(differ_shadow, 0);
}

// ---------------------------------------------------------------------------------------------
// The plan.

TEST(Csg, PlanCountsNodesAndLeavesTheTestOutWithout) {
    const RenderScene s = compile_scene(scene_of(lens_file()));
    RenderSettings rs;
    rs.width = rs.height = 8;
    const SceneFeatures f = scene_features(s, rs);
    EXPECT_EQ(f.geometry.csg_nodes, 2u);
    EXPECT_NE(f.geometry.variant & kGeomCsg, 0u);
    EXPECT_EQ(f.geometry.prims[static_cast<int>(ShapeKind::Cylinder)], 3u);
    auto reason = [](const RenderPlan& p) {
        for (const PlanReason& r : p.reasons)
            if (r.feature == "CSG test") return reason_line(r);
        return std::string();
    };
    EXPECT_EQ(reason(make_render_plan(s, rs)),
              "kept: CSG test: 2 CSG node(s): a hit counts where every node above it keeps it "
              "(spec §13.8)");
    GroupDesc plain;
    plain.shapes = {sphere(0, Vec3(0), 1), box(1, Vec3(2), Vec3(1))};
    const RenderScene s2 = compile_scene(scene_of(plain));
    const SceneFeatures f2 = scene_features(s2, rs);
    EXPECT_EQ(f2.geometry.csg_nodes, 0u);
    EXPECT_EQ(f2.geometry.variant & kGeomCsg, 0u);
    EXPECT_EQ(reason(make_render_plan(s2, rs)),
              "left out: CSG test: no CSG node: every hit counts, no inside tests");
}

// ---------------------------------------------------------------------------------------------
// Extreme cases.

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

struct Extreme {
    int rays = 0, nan = 0, wrong = 0, acne = 0;
};

// The open pocket at scale s about c, seen from 1e3 sizes above: every ray lands on the pocket's
// bottom (B's face) or A's top, never in the removed lid; spawned rays do not re-hit.
Extreme pocket_rays(double s, const Vec3& c) {
    const RenderScene sc = compile_scene(scene_of(pocket(s, c, 1.0)));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.98, 0.98);
    Extreme e;
    for (int i = 0; i < 2000; ++i) {
        const double x = u(rng), z = u(rng);
        if (std::abs(std::abs(x) - 0.5) < 1e-6 || std::abs(std::abs(z) - 0.5) < 1e-6) continue;
        const bool in_pocket = std::abs(x) < 0.5 && std::abs(z) < 0.5;
        const Vec3 target = c + s * Vec3(x, in_pocket ? 0.5 : 1.0, z);
        const Vec3 o = c + s * Vec3(0.3 * x, 2000.0, 0.3 * z);
        const Ray r{o, glm::normalize(target - o)};
        ++e.rays;
        Hit h;
        if (!intersect(sc, r, {0, kInf}, &h)) {
            ++e.wrong;
            continue;
        }
        const SurfaceInteraction si = interaction(sc, r, h);
        if (!finite(si.p) || !finite(si.n_geometric) || !std::isfinite(h.t)) {
            ++e.nan;
            continue;
        }
        if (glm::length(si.p - target) > 1e-9 * (s * 2000 + glm::length(c)) ||
            glm::length(si.n_geometric - Vec3(0, 1, 0)) > 1e-9)
            ++e.wrong;
        // The reflected ray leaves upward (out of the pocket or off the top): nothing to hit
        // but the pocket's walls, never the surface it left at once.
        const Vec3 refl = r.d - 2 * glm::dot(r.d, si.n_geometric) * si.n_geometric;
        Hit h2;
        if (intersect(sc, spawn_ray(si, refl), {0, kInf}, &h2) && h2.t < 1e-6 * s) ++e.acne;
        // Straight on (refraction without bending): through the solid to A's bottom.
        if (intersect(sc, spawn_ray(si, r.d), {0, kInf}, &h2) && h2.t < 0.4 * s) ++e.acne;
    }
    return e;
}

TEST(CsgExtreme, TinyHugeAndFarPocket) {
    for (double s : {1e-6, 1.0, 1e6}) {
        for (const Vec3& c : {Vec3(0.0), Vec3(3.0, -2.0, 1.0)}) {
            const Extreme e = pocket_rays(s, c * s);
            SCOPED_TRACE(testing::Message() << "scale " << s << " centre " << c.x);
            EXPECT_GT(e.rays, 1900);
            EXPECT_EQ(e.nan, 0);
            EXPECT_EQ(e.wrong, 0);
            EXPECT_EQ(e.acne, 0);
        }
    }
}

TEST(CsgExtreme, LensAtEveryScaleFromFar) {
    for (double s : {1e-6, 1.0, 1e6}) {
        GroupDesc root;
        root.csgs = {lens(s), ring(s)};
        const RenderScene sc = compile_scene(scene_of(root));
        // From 1e3 sizes up the axis, and through the ring's hole (nothing but the lens).
        Probe p = probe(sc, {0, 1e3 * s, 0}, {0, -1, 0});
        ASSERT_TRUE(p.hit);
        EXPECT_NEAR(p.t, (1e3 - 0.55) * s, 1e-9 * 1e3 * s);
        EXPECT_VEC_NEAR(p.si.n_geometric, Vec3(0, 1, 0), 1e-9);
        p = probe(sc, {0.5 * s, 1e3 * s, 0}, {0, -1, 0});
        ASSERT_TRUE(p.hit);
        EXPECT_EQ(p.si.material, 0);
        EXPECT_NEAR(p.t, (1e3 - (std::sqrt(2.0) - 0.95)) * s, 1e-9 * 1e3 * s);
        // Sideways from 1e3 sizes: the ring's outer wall.
        p = probe(sc, {-1e3 * s, 0.1 * s, 0}, {1, 0, 0});
        ASSERT_TRUE(p.hit);
        EXPECT_EQ(p.si.material, 1);
        EXPECT_NEAR(p.t, (1e3 - 1.1) * s, 1e-9 * 1e3 * s);
        // Spawned on through the lens: the next surface is the lens's bottom, not its top again.
        const Ray r{{0.3 * s, 1e3 * s, 0.2 * s}, {0, -1, 0}};
        Hit h;
        ASSERT_TRUE(intersect(sc, r, {0, kInf}, &h));
        const SurfaceInteraction si = interaction(sc, r, h);
        Hit h2;
        ASSERT_TRUE(intersect(sc, spawn_ray(si, r.d), {0, kInf}, &h2));
        EXPECT_GT(h2.t, 0.5 * s);
        EXPECT_FALSE(intersect(sc, spawn_ray(si, -r.d), {0, kInf}, &h2));
    }
}

// Rays in the plane of coincident faces: along the shared top of the two boxes of a union, along
// the lid of the pocket (B's top in A's top), along a pocket's rim. No NaN; every hit lies on a
// leaf's surface; none inside the removed part.
TEST(CsgExtreme, GrazingRaysAlongCoincidentFaces) {
    for (double s : {1e-6, 1.0, 1e6}) {
        GroupDesc uni;
        uni.csgs = {csg(CsgOp::Union, {of(box(0, s * Vec3(-0.25, 0, 0), Vec3(s))),
                                       of(box(1, s * Vec3(0.25, 0, 0), Vec3(s)))})};
        const RenderScene su = compile_scene(scene_of(uni));
        const RenderScene lid = compile_scene(scene_of(pocket(s, Vec3(0.0), 0.5)));
        const RenderScene open = compile_scene(scene_of(pocket(s, Vec3(0.0), 1.0)));
        std::mt19937 rng(9);
        std::uniform_real_distribution<double> u(-0.45, 0.45);
        int nan = 0, spurious = 0;
        for (int i = 0; i < 500; ++i) {
            const double z = u(rng);
            for (int k = 0; k < 3; ++k) {
                const RenderScene& sc = k == 0 ? su : k == 1 ? lid : open;
                const double y = k == 0 ? 0.5 : 1.0;
                const Ray r{s * Vec3(-1e3, y, z), {1, 0, 0}};
                Hit h;
                if (!intersect(sc, r, {0, kInf}, &h)) continue;
                const SurfaceInteraction si = interaction(sc, r, h);
                if (!finite(si.p) || !finite(si.n_geometric)) {
                    ++nan;
                    continue;
                }
                const Vec3 q = si.p / s;
                // The open pocket's removed lid: |x|, |z| < 0.5 at y = 1.
                if (k == 2 && std::abs(q.x) < 0.5 - 1e-6 && std::abs(q.z) < 0.5 - 1e-6) ++spurious;
                // The hit is on the solid's boundary: its x is an end of the box row.
                if (std::abs(std::abs(q.x) - (k == 0 ? 0.75 : 1.0)) > 1e-6 &&
                    std::abs(std::abs(q.x) - 0.5) > 1e-6)
                    ++spurious;
            }
        }
        EXPECT_EQ(nan, 0);
        EXPECT_EQ(spurious, 0);
    }
}

TEST(CsgExtreme, DeepNestingRendersWithoutRecursion) {
    // A chain of 100 nested nodes: unions of spheres along x, with differences that remove a far
    // away sphere and intersections with a big sphere in between (neither changes the solid).
    CsgDesc node = csg(CsgOp::Union, {of(sphere(0, Vec3(0), 1))});
    for (int k = 1; k < 100; ++k) {
        const int op = k % 3;
        if (op == 0)
            node = csg(CsgOp::Union, {of(node), of(sphere(k % 2, Vec3(0.05 * k, 0, 0), 1))});
        else if (op == 1)
            node = csg(CsgOp::Difference, {of(node), of(sphere(1, Vec3(1000, 0, 0), 1))});
        else
            node = csg(CsgOp::Intersection, {of(node), of(sphere(1, Vec3(0), 100))});
    }
    GroupDesc root;
    root.csgs = {node};
    const RenderScene s = compile_scene(scene_of(root));
    ASSERT_EQ(s.sets.size(), 1u);
    EXPECT_EQ(s.sets[0].csg.operations(), 100u);
    Probe p = probe(s, {-10, 0, 0}, {1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 9.0, 1e-12);
    p = probe(s, {10, 0, 0}, {-1, 0, 0});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10 - (0.05 * 99 + 1), 1e-12);
    EXPECT_NE(p.si.material, -1);
    RenderSettings rs;
    rs.width = rs.height = 16;
    rs.threads = 1;
    const RenderPlan plan = make_render_plan(s, rs);
    RenderState st;
    st.reset(rs.width, rs.height);
    ASSERT_TRUE(render_samples(st, s, plan, rs, 1));
    const Image img = st.image();
    double sum = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) sum += img.at(x, y).x;
    EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
}  // namespace rt
