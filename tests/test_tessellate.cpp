// Preview meshes: every vertex on the analytic surface with its outward normal and spec §5 uv,
// and the tessellated silhouette agreeing with the traced one (intersection over union).
#include "rt/accel/intersect.h"
#include "rt/shapes/tessellate.h"
#include "test_util.h"

namespace rt {
namespace {

// Vertices lie on the surface; normals are unit and point out; uv matches surface_at's.
// `skip_apex`: rays aimed within 1e-9 of a cone's apex graze a double root there, which the
// quadratic does not resolve yet (the numerical-stability issue's case); such vertices are
// checked by position only.
template <class Shape>
void expect_on_surface(const Shape& shape, const PreviewMesh& m, double tol = 1e-9,
                       const Vec3* skip_apex = nullptr) {
    ASSERT_EQ(m.positions.size(), m.normals.size());
    ASSERT_EQ(m.positions.size(), m.uvs.size());
    ASSERT_EQ(m.indices.size() % 3, 0u);
    const Bounds3 b = bounds(shape);
    for (size_t i = 0; i < m.positions.size(); ++i) {
        // A ray from outside along -normal must hit the shape at the vertex (aimed a hair
        // inside, so rims and apexes are not decided by rounding).
        const Vec3 n = m.normals[i];
        const Vec3 p = m.positions[i] - 1e-9 * (m.positions[i] - b.centre());
        EXPECT_NEAR(glm::length(n), 1.0, 1e-12);
        if (skip_apex && glm::length(m.positions[i] - *skip_apex) < 1e-12) continue;
        const double far = 2 * glm::length(b.diagonal()) + 1;
        const Ray r{p + far * n, -n};
        const ShapeHits h = intersect(shape, r, {0, kInf});
        ASSERT_GT(h.count, 0) << "vertex " << i;
        EXPECT_NEAR(h.t[0], far, tol * far + 1e-8) << "vertex " << i;
    }
}

TEST(Tessellate, SphereVerticesNormalsAndUv) {
    const Sphere s{{1, 2, 3}, 2};
    const PreviewMesh m = tessellate(s, 32);
    expect_on_surface(s, m);
    for (size_t i = 0; i < m.positions.size(); ++i) {
        const Vec3 q = m.positions[i] - s.centre;
        EXPECT_NEAR(glm::dot(m.normals[i], q / s.radius), 1.0, 1e-12);
        // v = acos(-q_y/r)/pi everywhere; u = azimuth/2pi away from the seam and the poles.
        EXPECT_NEAR(m.uvs[i].y, std::acos(std::clamp(-q.y / s.radius, -1.0, 1.0)) / kPi, 1e-9);
        if (m.uvs[i].x > 1e-9 && m.uvs[i].x < 1 - 1e-9 && std::abs(q.y) < s.radius * 0.999) {
            EXPECT_NEAR(m.uvs[i].x, azimuth(q) / (2 * kPi), 1e-9);
        }
    }
}

TEST(Tessellate, BoxFacesMatchSurfaceAt) {
    const Box b{{0, 1, 0}, {1, 2, 3}};
    const PreviewMesh m = tessellate(b);
    EXPECT_EQ(m.triangle_count(), 12u);
    expect_on_surface(b, m);
    // Each face's uv at a vertex equals surface_at's for a ray hitting the face there.
    for (size_t i = 0; i < m.positions.size(); ++i) {
        const Vec3 n = m.normals[i];
        const Vec3 target =
            m.positions[i] - 1e-7 * (m.positions[i] - b.centre);  // just inside the corner
        const Ray r{target + 10.0 * n, -n};
        const ShapeHits h = intersect(b, r, {0, kInf});
        ASSERT_GT(h.count, 0);
        const SurfacePoint sp = surface_at(b, r, h.t[0], h.part[0]);
        EXPECT_NEAR(sp.uv.x, m.uvs[i].x, 1e-6);
        EXPECT_NEAR(sp.uv.y, m.uvs[i].y, 1e-6);
    }
}

TEST(Tessellate, CylinderAndConeOnTheirSurfaces) {
    const Cylinder c{{0, 0, 1}, 0.5, 2};
    expect_on_surface(c, tessellate(c, 24));
    const Cone k{{0, 0, 0}, 1, 2};
    const PreviewMesh m = tessellate(k, 24);
    const Vec3 apex(0, 1, 0);
    expect_on_surface(k, m, 1e-7, &apex);
    // Side normals follow normalize(h q/rho, r, h q/rho): y component r / sqrt(h^2 + r^2).
    for (const Vec3& n : m.normals)
        if (n.y > 0) {
            EXPECT_NEAR(n.y, 1 / std::sqrt(5.0), 1e-12);
        }
}

// Coverage of a 160x120 view: traced analytic shapes against the tessellated triangles.
double coverage_iou(const RenderScene& scene, int detail) {
    PreviewMesh world;
    for (const Instance& inst : scene.instances)
        world.append(tessellate_set(scene.sets[static_cast<size_t>(inst.set)], detail),
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

TEST(Tessellate, SilhouettesAgreeWithTheTraceUnderTransforms) {
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

TEST(Tessellate, SetCarriesMaterialsAndMirroredInstancesKeepOutwardNormals) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !a!\n"
        "#material 0 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 1 -1 !b!\n"
        "#group_begin -1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n"
        "#shape_sphere 1 2 0 0 1\n#group_end\n#shape_box 0 0 0 0 1 1 1\n");
    const PreviewMesh m = tessellate_set(scene.sets[0], 16);
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
TEST(Tessellate, MeshNormalsInterpolateAsTheTraceDoesUnderANonUniformScale) {
    const RenderScene scene = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#vertex 0 0 0  1 0 1  0 0\n#vertex 1 0 0  0 1 1  0 0\n#vertex 0 1 0  -1 -1 1  0 0\n"
        "#group_begin 8 0 0 0  0 1 0 0  0 0 0.5 0  0 0 0 1\n#shape_triangle 0 0 1 2\n"
        "#group_end\n");
    const PreviewMesh m = tessellate_set(scene.sets[0], 16);
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
    const PreviewMesh e = tessellate_set(ellipsoid.sets[0], 16);
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

}  // namespace
}  // namespace rt
