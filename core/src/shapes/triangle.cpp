// Triangle (spec §5): p = w1 v1 + w2 v2 + w3 v3; geometric normal normalize((v2-v1) x (v3-v1));
// shading normal interpolated when all three vertices have normals; uv interpolated. A triangle
// bounds no solid: inside() is always false (a closed mesh's interior is not a triangle's).
#include "rt/shapes/shapes.h"

namespace rt {

Bounds3 bounds(const Triangle& t) {
    Bounds3 b;
    b.extend(t.p0);
    b.extend(t.p1);
    b.extend(t.p2);
    return b;
}

Bounds3 bounds(const Triangle& t, const Mat4& m) {
    Bounds3 b;
    for (const Vec3& v : {t.p0, t.p1, t.p2}) b.extend(Vec3(m * glm::dvec4(v, 1.0)));
    return b;
}

// Barycentrics of the ray's hit in double precision (Moller-Trumbore), for the shading point,
// normal and texture coordinates; false when the double test calls it a miss (a hit the float
// test found on an edge), and surface_at() then projects onto the triangle.
static bool barycentric(const Triangle& tri, const Ray& ray, double* t, double* b1, double* b2) {
    const Vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
    const Vec3 pv = glm::cross(ray.d, e2);
    const double det = glm::dot(e1, pv);
    if (!(det != 0.0) || !std::isfinite(det)) return false;
    const Vec3 tv = ray.o - tri.p0;
    const double u = glm::dot(tv, pv);
    const Vec3 qv = glm::cross(tv, e1);
    const double v = glm::dot(ray.d, qv);
    *b1 = u / det;
    *b2 = v / det;
    *t = glm::dot(e2, qv) / det;
    return !(det > 0.0 ? (u < 0.0 || v < 0.0 || u + v > det) : (u > 0.0 || v > 0.0 || u + v < det));
}

SurfacePoint surface_at(const Triangle& tri, const TriangleAttribs& attr, const Ray& ray, double t,
                        bool uv, const Vec3& origin) {
    SurfacePoint sp;
    double tt = t, b1 = 0, b2 = 0;
    if (!barycentric(tri, ray, &tt, &b1, &b2)) {
        // Numerically on an edge: fall back to the ray point's barycentrics, clamped.
        const Vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0, pp = ray.at(t) - tri.p0;
        const double d00 = glm::dot(e1, e1), d01 = glm::dot(e1, e2), d11 = glm::dot(e2, e2);
        const double d20 = glm::dot(pp, e1), d21 = glm::dot(pp, e2);
        const double den = d00 * d11 - d01 * d01;
        b1 = std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
        b2 = std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - b1);
    }
    const double b0 = 1.0 - b1 - b2;
    // The point from barycentrics. Its error bound is pbrt's, in single precision: rays are
    // tested against the float copy of the triangle from a float origin, so a spawned ray must
    // clear the float rounding of the vertices and of its own origin.
    const Vec3 a0 = b0 * tri.p0, a1 = b1 * tri.p1, a2 = b2 * tri.p2;
    sp.p = a0 + a1 + a2;
    // The float copy is relative to `origin`, and so is a ray's float origin: the float
    // rounding is of the vertices and the point about it; the double subtraction of the origin
    // and the sum above add a few double roundings of the absolute values.
    const Vec3 l0 = b0 * (tri.p0 - origin), l1 = b1 * (tri.p1 - origin),
               l2 = b2 * (tri.p2 - origin);
    sp.p_error = gamma_float(7) * (glm::abs(l0) + glm::abs(l1) + glm::abs(l2)) +
                 gamma(8) * (glm::abs(a0) + glm::abs(a1) + glm::abs(a2) + glm::abs(origin));
    sp.n_geometric = glm::normalize(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
    sp.n_shading = sp.n_geometric;
    if (attr.has_normals) {
        const Vec3 n = b0 * attr.n[0] + b1 * attr.n[1] + b2 * attr.n[2];
        const double len = glm::length(n);
        if (len > 0) sp.n_shading = n / len;
    }
    if (uv) sp.uv = b0 * attr.uv[0] + b1 * attr.uv[1] + b2 * attr.uv[2];
    return sp;
}

bool inside(const Triangle& /*t*/, const Vec3& /*p_object*/) { return false; }

void tessellate(const Triangle& t, const TriangleAttribs& a, PreviewMesh& out) {
    const Vec3 ng = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
    const Vec3 ps[3] = {t.p0, t.p1, t.p2};
    const uint32_t first = static_cast<uint32_t>(out.positions.size());
    for (int k = 0; k < 3; ++k) {
        out.positions.push_back(ps[k]);
        out.normals.push_back(a.has_normals ? a.n[k] : ng);
        out.uvs.push_back(a.uv[k]);
    }
    // The file's winding: (v2 - v1) x (v3 - v1) is the geometric normal (spec §5).
    out.indices.insert(out.indices.end(), {first, first + 1, first + 2});
}

double csg_sign(const Triangle& /*t*/, const Vec3& /*p_object*/) { return kInf; }

double csg_epsilon(const Triangle& /*t*/) { return 0.0; }

}  // namespace rt
