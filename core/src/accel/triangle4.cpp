#include "rt/accel/triangle4.h"

#include "accel/triangle_kernel.h"
#include "rt/shapes/shapes.h"

namespace rt {

TriRay::TriRay(const Ray& r) {
    // The dominant axis of the direction becomes z; x and y follow cyclically (winding kept).
    const Vec3 a = glm::abs(r.d);
    kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    const double dz = r.d[kz];
    sx = static_cast<float>(-r.d[kx] / dz);
    sy = static_cast<float>(-r.d[ky] / dz);
    sz = static_cast<float>(1.0 / dz);
    for (int i = 0; i < 3; ++i) {
        o[i] = static_cast<float>(r.o[i]);
        od[i] = r.o[i];
        dd[i] = r.d[i];
    }
}

// The distance to the plane of lane l's float triangle in double, or NaN when even double cannot
// tell it from zero. Used only for hits the float bound could not separate from t = 0.
double tri4_plane_distance_double(const Tri4& tri, int l, const TriRay& ray) {
    Vec3 v[3];
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) v[k][a] = static_cast<double>(tri.p[k][a][l]);
    const Vec3 o(ray.od[0], ray.od[1], ray.od[2]), d(ray.dd[0], ray.dd[1], ray.dd[2]);
    const Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0], w = v[0] - o;
    const Vec3 n = glm::cross(e1, e2);
    const double num = glm::dot(n, w), den = glm::dot(n, d);
    if (!(den != 0.0)) return std::nan("");
    const double t = num / den;
    // Rounding of n (a few operations on e1, e2), of w and of the two dot products.
    const Vec3 ae1 = glm::abs(e1), ae2 = glm::abs(e2), aw = glm::abs(w);
    const Vec3 an(ae1.y * ae2.z + ae1.z * ae2.y, ae1.z * ae2.x + ae1.x * ae2.z,
                  ae1.x * ae2.y + ae1.y * ae2.x);  // bounds |n| componentwise
    const double err_num = gamma(8) * glm::dot(an, aw + glm::abs(o) + glm::abs(v[0]));
    const double err_den = gamma(8) * glm::dot(an, glm::abs(d));
    if (std::abs(den) <= err_den) return std::nan("");
    const double err_t = (err_num + std::abs(t) * err_den) / (std::abs(den) - err_den);
    return std::abs(t) > err_t ? t : std::nan("");
}

// The watertight fallback: the edge functions of the lanes in `lanes` (those with an edge
// function of exactly zero) recomputed in double and rounded back.
void tri4_edges_in_double(const __m128 x[3], const __m128 y[3], int lanes, __m128* e0, __m128* e1,
                          __m128* e2) noexcept {
    alignas(16) float fx[3][4], fy[3][4], f0[4], f1[4], f2[4];
    for (int v = 0; v < 3; ++v) {
        _mm_store_ps(fx[v], x[v]);
        _mm_store_ps(fy[v], y[v]);
    }
    _mm_store_ps(f0, *e0);
    _mm_store_ps(f1, *e1);
    _mm_store_ps(f2, *e2);
    for (int l = 0; l < 4; ++l) {
        if (!(lanes >> l & 1)) continue;
        auto dp = [&](int a, int b) {
            return static_cast<float>(
                static_cast<double>(fx[a][l]) * static_cast<double>(fy[b][l]) -
                static_cast<double>(fy[a][l]) * static_cast<double>(fx[b][l]));
        };
        f0[l] = dp(1, 2);
        f1[l] = dp(2, 0);
        f2[l] = dp(0, 1);
    }
    *e0 = _mm_load_ps(f0);
    *e1 = _mm_load_ps(f1);
    *e2 = _mm_load_ps(f2);
}

int intersect_tri4(const Tri4& tri, const TriRay& ray, int lanes_mask, float t_lo, float t_hi,
                   float t_out[4]) {
    return sse2::tri4_hits(tri, ray, lanes_mask, t_lo, t_hi, t_out);
}

ShapeHits intersect(const Triangle& tri, const Ray& ray, Interval t) {
    // The shape's test is the kernel's: lane 0 of a block, the arithmetic every triangle of a
    // scene goes through (a set's float copies are relative to GeometrySet::tri_origin; here the
    // origin is 0).
    Tri4 block{};
    put_triangle(block, 0, tri.p0, tri.p1, tri.p2, Vec3(0.0));
    ShapeHits h;
    float tt[4];
    if (intersect_tri4(block, TriRay(ray), 1, float_lower(t.lo), float_upper(t.hi), tt) &&
        t.contains(static_cast<double>(tt[0])))
        h.add(static_cast<double>(tt[0]), 0);
    return h;
}

}  // namespace rt
