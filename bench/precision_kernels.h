// The renderer's intersection and ray-spawning kernels templated on the scalar type, for the
// precision benchmark (bench/precision.cpp): float, double and long double run the very same
// algorithms as core/, so their images differ only by rounding.
//   - sphere: the numerically stable quadratic of Haines, Guenther and Akenine-Moeller, "Precision
//     Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7), as core/src/shapes/
//     sphere.cpp, with its re-projected hit point and widened error bound;
//   - triangle: the watertight test of Woop, Benthin and Wald (JCGT 2(1), 2013) with pbrt-v4's
//     conservative bound on the computed distance (Pharr, Jakob, Humphreys, "Physically Based
//     Rendering" 4th ed., sec. 6.5.3 and 6.8.7), as core/src/triangle4.cpp;
//   - box: the slab test made conservative by Ize's factor 1 + 2 gamma(3) ("Robust BVH Ray
//     Traversal", JCGT 2(2), 2013; pbrt-v4 Bounds3::IntersectP), as the core's BVH nodes;
//   - spawn: pbrt-v4's OffsetRayOrigin (sec. 6.8.6), as core/src/intersect.cpp offset_origin().
// Header-only and independent of core/ (which is the version that ships).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace prec {

template <class T>
struct V3 {
    T v[3] = {T(0), T(0), T(0)};
    V3() = default;
    V3(T x, T y, T z) : v{x, y, z} {}
    T& operator[](int i) { return v[i]; }
    T operator[](int i) const { return v[i]; }
    template <class U>
    static V3 from(const V3<U>& a) {
        return {static_cast<T>(a[0]), static_cast<T>(a[1]), static_cast<T>(a[2])};
    }
};
template <class T>
V3<T> operator+(const V3<T>& a, const V3<T>& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
template <class T>
V3<T> operator-(const V3<T>& a, const V3<T>& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <class T>
V3<T> operator-(const V3<T>& a) {
    return {-a[0], -a[1], -a[2]};
}
template <class T>
V3<T> operator*(T s, const V3<T>& a) {
    return {s * a[0], s * a[1], s * a[2]};
}
template <class T>
T dot(const V3<T>& a, const V3<T>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class T>
V3<T> cross(const V3<T>& a, const V3<T>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <class T>
V3<T> vabs(const V3<T>& a) {
    return {std::abs(a[0]), std::abs(a[1]), std::abs(a[2])};
}
template <class T>
T length(const V3<T>& a) {
    return std::sqrt(dot(a, a));
}
template <class T>
V3<T> normalize(const V3<T>& a) {
    return (T(1) / length(a)) * a;
}

/// Unit roundoff and Higham's gamma(n) = n u / (1 - n u) of the scalar type (pbrt's gamma).
template <class T>
constexpr T unit_roundoff() {
    return std::numeric_limits<T>::epsilon() / T(2);
}
template <class T>
constexpr T gamma(int n) {
    return (static_cast<T>(n) * unit_roundoff<T>()) /
           (T(1) - static_cast<T>(n) * unit_roundoff<T>());
}

/// The wider type the watertight test falls back to when an edge function is exactly zero.
template <class T>
struct Wider {
    using type = long double;
};
template <>
struct Wider<float> {
    using type = double;
};

template <class T>
struct Ray {
    V3<T> o, d;
};

/// Per-ray constants of the watertight test: the axis permutation that makes z the dominant
/// direction (x, y follow cyclically so the winding is kept) and the shear onto +z.
template <class T>
struct WtRay {
    int kx = 0, ky = 1, kz = 2;
    T sx = T(0), sy = T(0), sz = T(1);
    explicit WtRay(const Ray<T>& r) {
        const V3<T> a = vabs(r.d);
        kz = a[0] > a[1] ? (a[0] > a[2] ? 0 : 2) : (a[1] > a[2] ? 1 : 2);
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        sx = -r.d[kx] / r.d[kz];
        sy = -r.d[ky] / r.d[kz];
        sz = T(1) / r.d[kz];
    }
};

template <class T>
struct Sphere {
    V3<T> c;
    T r = T(1);
};
template <class T>
struct Triangle {
    V3<T> p[3];
};

/// Nearest root of the sphere in (lo, hi); false when none (core: intersect(Sphere, ...)).
template <class T>
bool intersect_sphere(const Sphere<T>& s, const Ray<T>& ray, T lo, T hi, T* t_out) {
    const V3<T> f = ray.o - s.c;
    const T a = dot(ray.d, ray.d);
    const T b = dot(f, ray.d);  // half of the usual b
    const V3<T> l = f - (b / a) * ray.d;
    const T len_l = length(l);
    // a (r^2 - |l|^2): the discriminant without the b^2 - 4ac cancellation (RTG ch. 7).
    const T disc = a * (s.r - len_l) * (s.r + len_l);
    if (!(disc >= T(0))) return false;
    const T c = dot(f, f) - s.r * s.r;
    const T q = -(b + std::copysign(std::sqrt(disc), b));
    T t0 = q != T(0) ? c / q : T(0);
    T t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > lo && t0 < hi) {
        *t_out = t0;
        return true;
    }
    if (t1 > lo && t1 < hi) {
        *t_out = t1;
        return true;
    }
    return false;
}

template <class T>
struct TriHit {
    T t = T(0), b0 = T(0), b1 = T(0), b2 = T(0);
};

/// Watertight ray/triangle test (Woop et al. 2013) with pbrt-v4's bound on t's error: a hit
/// closer than the bound may be the surface the ray starts on and is rejected.
template <class T>
bool intersect_triangle(const Triangle<T>& tri, const Ray<T>& ray, const WtRay<T>& wr, T t_lo,
                        T t_hi, TriHit<T>* out) {
    T x[3], y[3], z[3];
    for (int v = 0; v < 3; ++v) {
        z[v] = tri.p[v][wr.kz] - ray.o[wr.kz];
        x[v] = (tri.p[v][wr.kx] - ray.o[wr.kx]) + wr.sx * z[v];
        y[v] = (tri.p[v][wr.ky] - ray.o[wr.ky]) + wr.sy * z[v];
    }
    T e0 = x[1] * y[2] - y[1] * x[2];
    T e1 = x[2] * y[0] - y[2] * x[0];
    T e2 = x[0] * y[1] - y[0] * x[1];
    if (e0 == T(0) || e1 == T(0) || e2 == T(0)) {
        // Watertight fallback: the edge function recomputed in wider precision.
        using W = typename Wider<T>::type;
        auto ef = [&](int i, int j) {
            return static_cast<T>(static_cast<W>(x[i]) * static_cast<W>(y[j]) -
                                  static_cast<W>(y[i]) * static_cast<W>(x[j]));
        };
        e0 = ef(1, 2);
        e1 = ef(2, 0);
        e2 = ef(0, 1);
    }
    if ((e0 < T(0) || e1 < T(0) || e2 < T(0)) && (e0 > T(0) || e1 > T(0) || e2 > T(0)))
        return false;
    const T det = e0 + e1 + e2;
    if (det == T(0)) return false;
    for (int v = 0; v < 3; ++v) z[v] *= wr.sz;
    const T t_scaled = e0 * z[0] + e1 * z[1] + e2 * z[2];

    // pbrt-v4 sec. 6.8.7, compared scaled by |det| as in the core.
    auto max3 = [](const T* a) {
        return std::max(std::abs(a[0]), std::max(std::abs(a[1]), std::abs(a[2])));
    };
    const T max_z = max3(z), max_x = max3(x), max_y = max3(y);
    const T delta_z = gamma<T>(3) * max_z;
    const T delta_x = gamma<T>(5) * (max_x + max_z);
    const T delta_y = gamma<T>(5) * (max_y + max_z);
    const T delta_e = T(2) * (gamma<T>(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    const T max_e = std::max(std::abs(e0), std::max(std::abs(e1), std::abs(e2)));
    const T delta_t_scaled =
        T(3) * (gamma<T>(3) * max_e * max_z + delta_e * max_z + delta_z * max_e);
    const T ts = det < T(0) ? -t_scaled : t_scaled;
    const T abs_det = std::abs(det);
    if (!(ts > std::max(t_lo * abs_det, delta_t_scaled) && ts < t_hi * abs_det)) return false;
    const T inv = T(1) / det;
    out->t = t_scaled * inv;
    out->b0 = e0 * inv;
    out->b1 = e1 * inv;
    out->b2 = e2 * inv;
    return true;
}

template <class T>
struct Box {
    V3<T> lo, hi;
};

/// Slab test, conservative: t_far grown by 1 + 2 gamma(3) (Ize 2013), so no hit is missed.
template <class T>
bool intersect_box(const Box<T>& b, const Ray<T>& ray, const V3<T>& inv_d, T t_lo, T t_hi) {
    T t0 = t_lo, t1 = t_hi;
    for (int a = 0; a < 3; ++a) {
        T tn = (b.lo[a] - ray.o[a]) * inv_d[a];
        T tf = (b.hi[a] - ray.o[a]) * inv_d[a];
        if (tn > tf) std::swap(tn, tf);
        tf *= T(1) + T(2) * gamma<T>(3);
        t0 = tn > t0 ? tn : t0;  // NaN (0 * inf) leaves the bound as it was
        t1 = tf < t1 ? tf : t1;
        if (t0 > t1) return false;
    }
    return true;
}

/// Error-bound spawn point (pbrt-v4 OffsetRayOrigin): p pushed along the geometric normal n by
/// the projection of its error box, to the side of w, each component rounded away from p.
template <class T>
V3<T> offset_origin(const V3<T>& p, const V3<T>& p_error, const V3<T>& n, const V3<T>& w) {
    const T d = dot(vabs(n), p_error);
    V3<T> offset = d * n;
    if (dot(w, n) < T(0)) offset = -offset;
    V3<T> po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > T(0))
            po[i] = std::nextafter(po[i], std::numeric_limits<T>::infinity());
        else if (offset[i] < T(0))
            po[i] = std::nextafter(po[i], -std::numeric_limits<T>::infinity());
    }
    return po;
}

/// The core's factor on the analytic shapes' point error bound (shapes.h kAnalyticRetestMargin):
/// the re-test of a spawned ray errs as much as the hit point itself.
inline constexpr int kAnalyticRetestMargin = 64;

template <class T>
struct SurfacePoint {
    V3<T> p, p_error, n;  // n: geometric, unit, outward (triangles: by winding)
};

/// Sphere hit point as core/src/shapes/sphere.cpp surface_at(): re-projected onto the sphere.
template <class T>
SurfacePoint<T> sphere_surface(const Sphere<T>& s, const Ray<T>& ray, T t) {
    SurfacePoint<T> sp;
    V3<T> q = (ray.o + t * ray.d) - s.c;
    q = (s.r / length(q)) * q;
    sp.p = s.c + q;
    sp.p_error = (static_cast<T>(kAnalyticRetestMargin) * gamma<T>(5)) * (vabs(s.c) + vabs(q));
    sp.n = (T(1) / s.r) * q;
    return sp;
}

/// Triangle hit point from the test's barycentrics, with pbrt-v4's bound (sec. 6.8.7).
template <class T>
SurfacePoint<T> triangle_surface(const Triangle<T>& tri, const TriHit<T>& h) {
    SurfacePoint<T> sp;
    const V3<T> a0 = h.b0 * tri.p[0], a1 = h.b1 * tri.p[1], a2 = h.b2 * tri.p[2];
    sp.p = a0 + a1 + a2;
    sp.p_error = gamma<T>(7) * (vabs(a0) + vabs(a1) + vabs(a2));
    sp.n = normalize(cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]));
    return sp;
}

}  // namespace prec
