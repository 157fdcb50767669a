// The compile's loops on several threads (core/src/compile/compile.cpp): the primitives' bounds,
// the vertices' data and the packed triangle blocks of a mesh large enough to be cut into
// ranges, checked against the description, and the first error in order where two ranges fail.
#include <gtest/gtest.h>

#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <string>
#include <vector>

#include "rt/compile/compile.h"
#include "rt/scene/mesh_gen.h"
#include "rt/scene/scene_desc.h"
#include "rt/util/error.h"

namespace rt {
namespace {

// A V1 scene of one file: the blob mesh of about n triangles in a group of matrix m, and a
// sphere beside it when `sphere` (a set of mixed kinds, whose triangles are packed in order).
SceneDesc mesh_scene(size_t n, const Mat4& m, bool sphere) {
    const TriangleMesh mesh = make_blob_mesh(n);
    SceneDesc d;
    FileDesc f;
    f.path = "mesh.ray";
    f.materials.emplace_back();
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        f.vertices.push_back({mesh.positions[i], mesh.normals[i],
                              Vec2(static_cast<double>(i % 7), static_cast<double>(i % 5))});
    GroupDesc g;
    g.matrix = m;
    for (const std::array<int, 3>& t : mesh.triangles)
        g.shapes.push_back({{}, 0, TriangleDesc{{t[0], t[1], t[2]}}});
    if (sphere) g.shapes.push_back({{}, 0, Sphere{Vec3(3, 0, 0), 0.5}});
    f.root.groups.push_back(std::move(g));
    d.files.push_back(std::move(f));
    return d;
}

// A triangle's corners with their normals and uvs, as a key.
using Corners = std::array<double, 24>;
Corners corners(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& n,
                const std::array<Vec2, 3>& uv) {
    Corners c{};
    for (size_t k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) {
            c[k * 8 + static_cast<size_t>(a)] = p[k][a];
            c[k * 8 + 3 + static_cast<size_t>(a)] = n[k][a];
            if (a < 2) c[k * 8 + 6 + static_cast<size_t>(a)] = uv[k][a];
        }
    return c;
}

// The set's triangles with their vertices' data are the description's, each once, moved by the
// group's matrix as the serial compile moves them; every triangle sits in the lane of the block
// tri4_prim names (or, in a mixed set, triangle i in lane i % 4 of block i / 4); the BVH's root
// bounds hold every corner.
void expect_compiled_as_described(const SceneDesc& d, const Mat4& m) {
    const RenderScene s = compile_scene(d);
    ASSERT_EQ(s.sets.size(), 1u);
    const GeometrySet& set = s.sets[0];
    const FileDesc& f = d.files[0];
    const Transform xf = Transform::from_matrix(m);
    const bool identity = m == Mat4(1.0);
    std::map<Corners, int> expected;
    size_t triangles = 0;
    for (const ShapeDesc& shape : f.root.groups[0].shapes) {
        const TriangleDesc* t = std::get_if<TriangleDesc>(&shape.geometry);
        if (!t) continue;
        ++triangles;
        std::array<Vec3, 3> p, n;
        std::array<Vec2, 3> uv;
        for (size_t k = 0; k < 3; ++k) {
            const VertexDesc& v = f.vertices[static_cast<size_t>(t->v[k])];
            p[k] = identity ? v.position : xf.point(v.position);
            n[k] = identity ? v.normal : xf.interpolable_normal(v.normal);
            uv[k] = v.uv;
        }
        ++expected[corners(p, n, uv)];
    }
    ASSERT_EQ(set.triangle_count(), triangles);
    const Bounds3& root = set.bvh.root_bounds;
    std::map<Corners, int> found;
    for (size_t i = 0; i < set.triangle_count(); ++i) {
        const std::array<uint32_t, 3>& v = set.triangle_vertices[i];
        std::array<Vec3, 3> p, n;
        std::array<Vec2, 3> uv;
        for (size_t k = 0; k < 3; ++k) {
            p[k] = set.vertex_positions[v[k]];
            n[k] = set.vertex_normals[v[k]];
            uv[k] = set.vertex_uvs[v[k]];
            for (int a = 0; a < 3; ++a)
                EXPECT_TRUE(root.lo[a] <= p[k][a] && p[k][a] <= root.hi[a]) << "vertex " << v[k];
        }
        ++found[corners(p, n, uv)];
    }
    EXPECT_TRUE(found == expected) << "the set's triangles are not the description's";

    std::vector<int> packed(set.triangle_count(), 0);
    for (size_t b = 0; b < set.tri4.size(); ++b)
        for (int lane = 0; lane < 4; ++lane) {
            const size_t i = set.tri4_prim.empty() ? b * 4 + static_cast<size_t>(lane)
                                                   : set.tri4_prim[b][static_cast<size_t>(lane)];
            if (i >= set.triangle_count()) continue;
            ++packed[i];
            const Triangle t = set.triangle(i);
            const Vec3* p[3] = {&t.p0, &t.p1, &t.p2};
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a)
                    ASSERT_EQ(set.tri4[b].p[k][a][lane],
                              static_cast<float>((*p[k])[a] - set.tri_origin[a]))
                        << "triangle " << i << " in block " << b;
        }
    for (size_t i = 0; i < packed.size(); ++i) ASSERT_EQ(packed[i], 1) << "triangle " << i;
}

TEST(CompileThreads, AMeshOfTrianglesOnlyIsPackedAsDescribed) {
    expect_compiled_as_described(mesh_scene(100000, Mat4(1.0), false), Mat4(1.0));
}

TEST(CompileThreads, AMovedMeshBesideASphereIsPackedAsDescribed) {
    const Mat4 m = glm::scale(glm::translate(Mat4(1.0), Vec3(1, 2, 3)), Vec3(2, 1, 0.5));
    expect_compiled_as_described(mesh_scene(100000, m, true), m);
}

// One thread and every thread compile the same set, array for array (the walk in the BVH's
// order numbers the vertices; the threads only copy and pack).
TEST(CompileThreads, OneThreadAndAllMakeTheSameSet) {
    const Mat4 m = glm::rotate(Mat4(1.0), 0.3, Vec3(1, 2, 3));
    for (const bool sphere : {false, true}) {
        const SceneDesc d = mesh_scene(100000, m, sphere);
        const RenderScene one = compile_scene(d, nullptr, std::nullopt, nullptr, 1);
        const RenderScene all = compile_scene(d, nullptr, std::nullopt, nullptr, 4);
        ASSERT_EQ(one.sets.size(), 1u);
        const GeometrySet& a = one.sets[0];
        const GeometrySet& b = all.sets[0];
        EXPECT_TRUE(a.vertex_positions == b.vertex_positions);
        EXPECT_TRUE(a.vertex_normals == b.vertex_normals);
        EXPECT_TRUE(a.vertex_uvs == b.vertex_uvs);
        EXPECT_TRUE(a.triangle_vertices == b.triangle_vertices);
        ASSERT_EQ(a.tri4.size(), b.tri4.size());
        EXPECT_EQ(std::memcmp(a.tri4.data(), b.tri4.data(), a.tri4.size() * sizeof(Tri4)), 0);
        EXPECT_TRUE(a.tri4_prim == b.tri4_prim);
        EXPECT_EQ(a.bvh.nodes.size(), b.bvh.nodes.size());
        EXPECT_EQ(a.tri_origin, b.tri_origin);
    }
}

// Two shapes too large for the renderer, in different threads' ranges: the first is named.
TEST(CompileThreads, TheFirstShapeTooLargeIsTheError) {
    SceneDesc d = mesh_scene(100000, Mat4(1.0), false);
    auto& shapes = d.files[0].root.groups[0].shapes;
    const std::string file = "mesh.ray";
    for (const size_t i : {size_t{30000}, shapes.size() - 10}) {
        shapes[i] = {{&file, static_cast<int>(i), 1}, 0, Sphere{Vec3(0.0), 1e301}};
    }
    try {
        compile_scene(d);
        FAIL() << "compiled";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.loc().line, 30000) << e.what();
    }
}

}  // namespace
}  // namespace rt
