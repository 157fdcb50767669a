// The preview's mesh of a whole geometry set (state/preview_geometry.h): the tessellated
// silhouette agreeing with the traced one (intersection over union), materials, windings and
// normals under transforms, CSG leaves tagged, and what each primitive is; the draw ranges the
// preview makes of it (state/preview_ranges.h): solids read from the kinds, flat faces.
#include "rt/accel/intersect.h"
#include "rt/shapes/tessellate.h"
#include "state/preview_geometry.h"
#include "state/preview_ranges.h"
#include "test_util.h"

namespace rt {
namespace {

// Coverage of a 160x120 view: traced analytic shapes against the tessellated triangles.
double coverage_iou(const RenderScene& scene, int detail) {
    PreviewMesh world;
    for (const Instance& inst : scene.instances)
        world.append(view::tessellate_set(scene.sets[static_cast<size_t>(inst.set)], detail),
                     inst.identity ? nullptr : &inst.world_from_set);
    const Camera cam = make_camera(scene, 160, 120);
    int both = 0, either = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            const Ray r = cam.generate(x, y, 0.5, 0.5);
            Hit h;
            const bool traced = intersect(scene, r, {0, kInf}, &h);
            bool raster = false;
            for (size_t t = 0; t < world.indices.size() && !raster; t += 3) {
                const Triangle tri{world.positions[world.indices[t]],
                                   world.positions[world.indices[t + 1]],
                                   world.positions[world.indices[t + 2]]};
                raster = intersect(tri, r, {0, kInf}).count > 0;
            }
            both += traced && raster;
            either += traced || raster;
        }
    return either ? static_cast<double>(both) / either : 1.0;
}

TEST(PreviewGeometry, SilhouettesAgreeWithTheTraceUnderTransforms) {
    const RenderScene scene = test::compile(
        "#camera 0 1 9  0 -0.1 -1  0 1 0  0.4\n"
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#vertex -3 -1 -2 0 0 0 0 0\n#vertex 3 -1 -2 0 0 0 1 0\n#vertex 0 3 -2 0 0 0 0.5 1\n"
        "#shape_triangle 0 0 1 2\n"
        "#group_begin 0.8 0.3 0 -2  -0.2 1.2 0 0.5  0 0 0.6 0  0 0 0 1\n"
        "#shape_sphere 0 0 0 0 1\n#group_end\n"
        "#group_begin 0.7071 0 0.7071 0  0 1 0 0  -0.7071 0 0.7071 0  0 0 0 1\n"
        "#shape_box 0 0 0 1 1 1.5 1\n#group_end\n"
        "#group_begin 1 0 0 2  0 1 0 0  0 0 1 0  0 0 0 1\n"
        "#shape_cylinder 0 0 0 0 0.6 1.5\n#shape_cone 0 0 1.5 0 0.5 1\n#group_end\n");
    EXPECT_GE(coverage_iou(scene, 48), 0.98);
}

TEST(PreviewGeometry, SetCarriesMaterialsAndMirroredInstancesKeepOutwardNormals) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !a!\n"
        "#material 0 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 1 -1 !b!\n"
        "#group_begin -1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n"
        "#shape_sphere 1 2 0 0 1\n#group_end\n#shape_box 0 0 0 0 1 1 1\n");
    const PreviewMesh m = view::tessellate_set(scene.sets[0], 16);
    ASSERT_EQ(m.materials.size(), m.triangle_count());
    EXPECT_NE(std::find(m.materials.begin(), m.materials.end(), scene.sets[0].prims[0].material),
              m.materials.end());
    // The mirrored sphere sits at x = -2: every normal points away from its centre, and the
    // winding (cross product) agrees with the normals.
    for (size_t t = 0; t < m.indices.size(); t += 3) {
        const Vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                   c = m.positions[m.indices[t + 2]];
        const Vec3 n =
            m.normals[m.indices[t]] + m.normals[m.indices[t + 1]] + m.normals[m.indices[t + 2]];
        EXPECT_GT(glm::dot(glm::cross(b - a, c - a), n), 0.0);
    }
}

// The preview's mesh normals follow the trace's rule (spec §5): interpolated, then normalised
// (the fragment shader's normalize), they give the trace's shading normal under a non-uniform
// scale, for a mesh triangle as for a tessellated shape's vertex.
TEST(PreviewGeometry, MeshNormalsInterpolateAsTheTraceDoesUnderANonUniformScale) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#vertex 0 0 0  1 0 1  0 0\n#vertex 1 0 0  0 1 1  0 0\n#vertex 0 1 0  -1 -1 1  0 0\n"
        "#group_begin 8 0 0 0  0 1 0 0  0 0 0.5 0  0 0 0 1\n#shape_triangle 0 0 1 2\n"
        "#group_end\n");
    const PreviewMesh m = view::tessellate_set(scene.sets[0], 16);
    ASSERT_EQ(m.triangle_count(), 1u);
    const double w[3] = {0.25, 0.25, 0.5};
    Vec3 p(0.0), n(0.0);
    for (int k = 0; k < 3; ++k) {
        p += w[k] * m.positions[m.indices[static_cast<size_t>(k)]];
        n += w[k] * m.normals[m.indices[static_cast<size_t>(k)]];
    }
    const Ray ray{p + Vec3(0, 0, 5), Vec3(0, 0, -1)};
    Hit hit;
    ASSERT_TRUE(intersect(scene, ray, {0, kInf}, &hit));
    const SurfaceInteraction si = interaction(scene, ray, hit, true);
    EXPECT_NEAR(glm::length(glm::normalize(n) - si.n_shading), 0.0, 1e-12);

    // A sphere under the same scale: inside each preview triangle, the interpolated normal is
    // the mapped interpolation of the unit sphere's normals at the corners (the map is applied
    // to the local rule, as for a mesh), not a mix of renormalised corner normals.
    const RenderScene ellipsoid = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n#group_begin 8 0 0 0  0 1 0 0  0 0 "
        "0.5 0  0 0 0 1\n#shape_sphere 0 0 0 0 1\n#group_end\n");
    const PreviewMesh e = view::tessellate_set(ellipsoid.sets[0], 16);
    const Vec3 scale(8, 1, 0.5);
    for (size_t t = 0; t < e.indices.size(); t += 3) {
        Vec3 mixed(0.0), local(0.0);
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = e.indices[t + static_cast<size_t>(k)];
            mixed += w[k] * e.normals[v];
            local += w[k] * (e.positions[v] / scale);  // the unit sphere's normal there
        }
        const Vec3 expected = glm::normalize(local / scale);  // (A^-1)^T = diag(1 / scale)
        EXPECT_NEAR(glm::length(glm::normalize(mixed) - expected), 0.0, 1e-9) << "triangle " << t;
    }
}

TEST(PreviewGeometry, TheLeavesOfACsgNodeAreTessellatedWholeAndTagged) {
    // The lens of _lens.ray (two spheres and a cylinder intersected) and its ring (a cylinder
    // minus a thinner one), beside a plain sphere.
    const RenderScene s = test::compile(
        "#material 0 0 0  0 0 0  1 0 0  0 0 0  1  0 0 0  1  -1 !red!\n"
        "#material 0 0 0  0 0 0  0 1 0  0 0 0  1  0 0 0  1  -1 !green!\n"
        "#shape_intersection\n#shape_list_begin\n#shape_sphere 0  0 -0.95 0  1.5\n"
        "#shape_sphere 0  0 0.95 0  1.5\n#shape_cylinder 0  0 0 0  1  2\n#shape_list_end\n"
        "#shape_difference\n#shape_cylinder 1  0 0 0  1.1  0.3\n"
        "#shape_cylinder 1  0 0 0  1  1\n#shape_sphere 0  5 0 0  1\n");
    std::vector<PreviewShape> shapes;
    const PreviewMesh m = view::tessellate_set(s.sets[0], 16, &shapes);
    ASSERT_EQ(m.csg.size(), m.triangle_count());
    const size_t leaves = s.sets[0].csg.leaves.size();
    ASSERT_EQ(leaves, 5u);  // two spheres and a cylinder, two cylinders
    std::vector<size_t> tagged(leaves + 1, 0);
    for (int c : m.csg) {
        ASSERT_GE(c, -1);
        ASSERT_LT(c, static_cast<int>(leaves));
        ++tagged[static_cast<size_t>(c + 1)];
    }
    for (size_t i = 0; i <= leaves; ++i) EXPECT_GT(tagged[i], 0u) << i;  // 0: the plain sphere
    ASSERT_EQ(m.materials.size(), m.triangle_count());
    // One shape per leaf and one for the plain sphere, each its leaf's triangles.
    ASSERT_EQ(shapes.size(), leaves + 1);
    size_t next = 0;
    for (const PreviewShape& p : shapes) {
        EXPECT_EQ(p.first, next);
        next = p.first + p.count;
        for (size_t t = p.first + 1; t < next; ++t) EXPECT_EQ(m.csg[t], m.csg[p.first]);
    }
    EXPECT_EQ(next, m.triangle_count());
}

// What each primitive is, in the set's frame: the kinds in the mesh's order, a sphere under its
// group's even scale still one, and a mesh's run of triangles of one material one entry.
TEST(PreviewGeometry, ShapesNameEachPrimitiveAndARunOfTrianglesOnce) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !a!\n"
        "#material 0 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 1 -1 !b!\n"
        "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 0 0 0 0 0 0 0\n#vertex 0 1 0 0 0 0 0 0\n"
        "#vertex 1 1 0 0 0 0 0 0\n"
        "#shape_triangle 0 0 1 2\n#shape_triangle 0 1 3 2\n#shape_triangle 1 0 1 3\n"
        "#group_begin 2 0 0 1  0 2 0 0  0 0 2 0  0 0 0 1\n#shape_sphere 1 0 1 0 0.5\n#group_end\n"
        "#shape_box 0 3 0 0 1 1 1\n");
    std::vector<PreviewShape> shapes;
    const PreviewMesh m = view::tessellate_set(scene.sets[0], 16, &shapes);
    std::vector<ShapeKind> kinds;
    size_t triangles = 0, solids = 0;
    for (const PreviewShape& p : shapes) {
        kinds.push_back(p.kind);
        triangles += p.count;
        if (p.kind == ShapeKind::Sphere) {
            EXPECT_NEAR(glm::length(p.centre - Vec3(1, 2, 0)), 0.0, 1e-12);
            EXPECT_NEAR(p.radius, 1.0, 1e-12);
        }
        solids += p.solid;
    }
    EXPECT_EQ(triangles, m.triangle_count());
    EXPECT_EQ(solids, 2u);  // the sphere and the box
    EXPECT_EQ(std::count(kinds.begin(), kinds.end(), ShapeKind::Sphere), 1);
    EXPECT_EQ(std::count(kinds.begin(), kinds.end(), ShapeKind::Box), 1);
    std::vector<size_t> runs;
    for (const PreviewShape& p : shapes)
        if (p.kind == ShapeKind::Triangle) runs.push_back(p.count);
    EXPECT_EQ(runs, (std::vector<size_t>{2, 1}));  // the two of material a, the one of b
}

// A material's range is a solid when its triangles are one primitive's that is one: the ball
// (its centre and radius), not the two boxes of one material, nor the box turned off the axes.
TEST(PreviewRanges, ARangeIsTheSolidOfItsOnePrimitive) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !two!\n"
        "#material 0 0 0 0 0 0 1 0 0 0 0 0 1 .5 .5 .5 1.5 -1 !ball!\n"
        "#material 0 0 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 -1 !turned!\n"
        "#material 0 0 0 0 0 0 0 0 1 0 0 0 1 0 0 0 1 -1 !box!\n"
        "#shape_box 0 0 0 0 1 1 1\n#shape_box 0 3 0 0 1 1 1\n"
        "#group_begin 3 0 0 0  0 3 0 1  0 0 3 0  0 0 0 1\n#shape_sphere 1 1 0 0 0.5\n#group_end\n"
        "#group_begin 0.7071 0 0.7071 0  0 1 0 0  -0.7071 0 0.7071 0  0 0 0 1\n"
        "#shape_box 2 0 5 0 1 1 1\n#group_end\n#shape_box 3 0 -5 0 1 2 3\n");
    std::vector<PreviewShape> shapes;
    const PreviewMesh m = view::tessellate_set(scene.sets[0], 16, &shapes);
    const view::MaterialRanges r = view::material_ranges(m, shapes);
    ASSERT_EQ(r.ranges.size(), 4u);
    EXPECT_EQ(r.indices.size(), m.indices.size());
    unsigned next = 0;
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(r.ranges[i].material, static_cast<int>(i));
        EXPECT_EQ(r.ranges[i].first, next);
        next += r.ranges[i].count;
        EXPECT_EQ(r.ranges[i].count,
                  3 * std::count(m.materials.begin(), m.materials.end(), static_cast<int>(i)));
    }
    EXPECT_FALSE(r.ranges[0].solid);
    ASSERT_TRUE(r.ranges[1].solid);
    EXPECT_EQ(r.ranges[1].solid->kind, ShapeKind::Sphere);
    EXPECT_NEAR(glm::length(r.ranges[1].solid->centre - Vec3(3, 1, 0)), 0.0, 1e-12);
    EXPECT_NEAR(r.ranges[1].solid->radius, 1.5, 1e-12);
    EXPECT_FALSE(r.ranges[2].solid);
    ASSERT_TRUE(r.ranges[3].solid);
    EXPECT_EQ(r.ranges[3].solid->kind, ShapeKind::Box);
    EXPECT_NEAR(glm::length(r.ranges[3].solid->box.lo - Vec3(-0.5, -6, -1.5)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(r.ranges[3].bounds.hi - Vec3(0.5, -4, 1.5)), 0.0, 1e-12);
    // Without the shapes (a coarse mesh) no range is a solid.
    for (const view::PreviewRange& range : view::material_ranges(m, {}).ranges)
        EXPECT_FALSE(range.solid);
}

// A box's range has its six faces as flat parts, the largest first; a ball's facets are none.
TEST(PreviewRanges, FlatFacesAreABoxsFacesNotABallsFacets) {
    PreviewMesh m;
    append_preview(Box{{0, 0, 0}, {0.5, 1, 1.5}}, nullptr, 0, 0, m);
    append_preview(Sphere{{5, 0, 0}, 1}, nullptr, 1, 32, m);
    const view::MaterialRanges r = view::material_ranges(m, {});
    ASSERT_EQ(r.ranges.size(), 2u);
    const std::vector<view::FlatFace>& faces = r.ranges[0].faces;
    ASSERT_EQ(faces.size(), 6u);
    EXPECT_NEAR(faces[0].area, 6.0, 1e-12);  // 2 x 3, twice (a face each side)
    EXPECT_NEAR(faces[1].area, 6.0, 1e-12);
    EXPECT_NEAR(faces[5].area, 2.0, 1e-12);           // 1 x 2
    EXPECT_NEAR(std::abs(faces[0].n.x), 1.0, 1e-12);  // the 2 x 3 faces face along x
    EXPECT_NEAR(std::abs(glm::dot(faces[0].n, faces[0].centroid) + faces[0].d), 0.0, 1e-12);
    EXPECT_TRUE(r.ranges[1].faces.empty());
}

}  // namespace
}  // namespace rt
