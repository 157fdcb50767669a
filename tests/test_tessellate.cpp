// Preview meshes: every vertex on the analytic surface with its outward normal and spec §5 uv,
// and each appended primitive's kind and numbers in its set's frame. (The whole set's mesh is
// the viewer's: tests/app/test_preview_geometry.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>

#include "rt/shapes/tessellate.h"

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

// What a primitive is in its set's frame: a similarity keeps a sphere one, with its centre and
// radius mapped; an uneven scale makes it an ellipsoid, which is no sphere.
TEST(Tessellate, AppendedSphereCarriesItsCentreAndRadiusInTheSetsFrame) {
    const Sphere s{{1, 0, 0}, 2};
    PreviewMesh out;
    append_preview(Box{}, nullptr, 0, 16, out);
    const Transform turned =
        Transform::from_matrix(glm::translate(Mat4(1.0), Vec3(0, 3, 0)) *
                               glm::rotate(Mat4(1.0), 0.7, glm::normalize(Vec3(1, 2, 3))) *
                               glm::scale(Mat4(1.0), Vec3(1.5)));
    const PreviewShape p = append_preview(s, &turned, 7, 16, out);
    EXPECT_EQ(p.kind, ShapeKind::Sphere);
    EXPECT_EQ(p.first, 12u);  // after the box's twelve
    EXPECT_EQ(p.first + p.count, out.triangle_count());
    EXPECT_TRUE(p.solid);
    EXPECT_NEAR(glm::length(p.centre - turned.point(s.centre)), 0.0, 1e-12);
    EXPECT_NEAR(p.radius, 3.0, 1e-12);
    for (size_t t = p.first; t < p.first + p.count; ++t) {
        EXPECT_EQ(out.materials[t], 7);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(glm::length(out.positions[out.indices[3 * t + k]] - p.centre), p.radius,
                        1e-9);
    }
    const Transform uneven = Transform::from_matrix(glm::scale(Mat4(1.0), Vec3(1, 1, 1.1)));
    EXPECT_FALSE(append_preview(s, &uneven, 0, 16, out).solid);
}

// A box stays one under scales, axis flips and quarter turns (its box the mapped corners'), not
// under any other turn; a torus about y under turns about y and even scales, not tilted.
TEST(Tessellate, AppendedBoxAndTorusAreSolidsWhereTheirTransformKeepsThem) {
    PreviewMesh out;
    const Box b{{1, 2, 3}, {0.5, 1, 2}};
    const Transform quarter = Transform::from_matrix(
        glm::rotate(Mat4(1.0), kPi / 2, Vec3(0, 1, 0)) * glm::scale(Mat4(1.0), Vec3(2, -1, 1)));
    const PreviewShape box = append_preview(b, &quarter, 0, 0, out);
    EXPECT_EQ(box.kind, ShapeKind::Box);
    EXPECT_EQ(box.count, 12u);
    EXPECT_TRUE(box.solid);
    Bounds3 vertices;
    for (size_t v = 0; v < out.positions.size(); ++v) vertices.extend(out.positions[v]);
    EXPECT_NEAR(glm::length(box.box.lo - vertices.lo), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(box.box.hi - vertices.hi), 0.0, 1e-12);
    const Transform tilted = Transform::from_matrix(glm::rotate(Mat4(1.0), 0.3, Vec3(1, 0, 0)));
    EXPECT_FALSE(append_preview(b, &tilted, 0, 0, out).solid);

    const Torus t{{0, 1, 0}, 0.25, 1.0};
    const Transform about_y = Transform::from_matrix(glm::rotate(Mat4(1.0), 0.4, Vec3(0, 1, 0)) *
                                                     glm::scale(Mat4(1.0), Vec3(2)));
    const PreviewShape ring = append_preview(t, &about_y, 0, 24, out);
    EXPECT_EQ(ring.kind, ShapeKind::Torus);
    EXPECT_TRUE(ring.solid);
    EXPECT_NEAR(glm::length(ring.centre - Vec3(0, 2, 0)), 0.0, 1e-12);
    EXPECT_NEAR(ring.radii.x, 2.0, 1e-12);
    EXPECT_NEAR(ring.radii.y, 0.5, 1e-12);
    EXPECT_FALSE(append_preview(t, &tilted, 0, 24, out).solid);
    EXPECT_FALSE(append_preview(Cylinder{}, nullptr, 0, 24, out).solid);

    const PreviewShape tri =
        append_preview(Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, TriangleAttribs{}, 3, out);
    EXPECT_EQ(tri.kind, ShapeKind::Triangle);
    EXPECT_EQ(tri.count, 1u);
    EXPECT_FALSE(tri.solid);
    EXPECT_EQ(tri.first + 1, out.triangle_count());
    EXPECT_EQ(out.materials.back(), 3);
}

}  // namespace
}  // namespace rt
