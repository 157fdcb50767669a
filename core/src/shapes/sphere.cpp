// Sphere (spec §5): |q| = r, q = p - c; outward normal q/r; u = azimuth/2pi about +y from -z,
// v = acos(-q_y/r)/pi (0 at the bottom pole). Inside: |q| < r.
#include "common.h"

namespace rt {

Bounds3 bounds(const Sphere& s) { return {s.centre - Vec3(s.radius), s.centre + Vec3(s.radius)}; }

Bounds3 bounds(const Sphere& s, const Mat4& m) {
    // An ellipsoid's half extent along world axis i is r times the length of row i of A.
    const Vec3 c = Vec3(m * glm::dvec4(s.centre, 1.0));
    Vec3 e;
    for (int i = 0; i < 3; ++i) e[i] = s.radius * glm::length(Vec3(m[0][i], m[1][i], m[2][i]));
    return {c - e, c + e};
}

ShapeHits intersect(const Sphere& s, const Ray& ray, Interval t) {
    // Numerically stable quadratic (Haines et al., Ray Tracing Gems ch. 7): the discriminant is
    // a * (r^2 - |l|^2) with l the closest-approach vector, which avoids b^2 - 4ac cancellation,
    // and the two roots come from q without subtracting nearly equal numbers.
    const Vec3 f = ray.o - s.centre;
    const double a = glm::dot(ray.d, ray.d);
    const double b = glm::dot(f, ray.d);  // half of the usual b
    const Vec3 l = f - (b / a) * ray.d;
    const double disc = a * (s.radius - glm::length(l)) * (s.radius + glm::length(l));
    ShapeHits h;
    if (!(disc >= 0.0)) return h;
    const double c = glm::dot(f, f) - s.radius * s.radius;
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double t0 = q != 0.0 ? c / q : 0.0;
    double t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    if (t.contains(t0)) h.add(t0, 0);
    if (t.contains(t1) && t1 != t0) h.add(t1, 0);
    return h;
}

SurfacePoint surface_at(const Sphere& s, const Ray& ray, double t, int /*part*/, bool uv) {
    SurfacePoint sp;
    Vec3 q = ray.at(t) - s.centre;
    // Re-project onto the sphere: the point's error no longer depends on t's error.
    q *= s.radius / glm::length(q);
    sp.p = s.centre + q;
    sp.p_error = kAnalyticRetestMargin * gamma(5) * (glm::abs(s.centre) + glm::abs(q));
    sp.n_geometric = q / s.radius;
    sp.n_shading = sp.n_geometric;
    if (uv) {
        sp.uv.x = azimuth(q) / (2 * kPi);
        sp.uv.y = std::acos(std::clamp(-q.y / s.radius, -1.0, 1.0)) / kPi;
    }
    return sp;
}

bool inside(const Sphere& s, const Vec3& p_object) {
    const Vec3 q = p_object - s.centre;
    return glm::dot(q, q) < s.radius * s.radius;
}

PreviewMesh tessellate(const Sphere& s, int detail) {
    const int segments = std::max(3, detail), rings = std::max(2, detail / 2);
    MeshBuilder b;
    // v = acos(-q_y / r) / pi: v = 0 at the bottom pole.
    b.grid(rings, segments, [&](int i, int j, Vec3* p, Vec3* n, Vec2* uv) {
        const double v = static_cast<double>(i) / rings, u = static_cast<double>(j) / segments;
        const double theta = kPi * v;
        Vec3 q = around(2 * kPi * u, s.radius * std::sin(theta));
        q.y = -s.radius * std::cos(theta);
        *p = s.centre + q;
        *n = q / s.radius;
        *uv = {u, v};
    });
    return std::move(b.mesh);
}

double csg_sign(const Sphere& s, const Vec3& p_object) {
    return glm::length(p_object - s.centre) - s.radius;
}

double csg_epsilon(const Sphere& s) { return kCsgTolerance * (glm::length(s.centre) + s.radius); }

}  // namespace rt
