// Small geometric vocabulary shared by every core module: vectors, rays, intervals, boxes and
// affine transforms, on GLM in double precision. Nothing here knows the scene format.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <limits>

namespace rt {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using Mat3 = glm::dmat3;
using Mat4 = glm::dmat4;  // GLM is column-major: m[col][row]

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kPi = 3.14159265358979323846;
/// Unit roundoff of double (half an ulp of 1).
inline constexpr double kMachineEps = std::numeric_limits<double>::epsilon() * 0.5;

/// gamma(n) of Higham / pbrt: bounds the relative error of n chained floating-point operations.
constexpr double gamma(int n) { return (n * kMachineEps) / (1 - n * kMachineEps); }

/// Unit roundoff of float, and gamma(n) for float arithmetic (BVH nodes and triangles are
/// tested in single precision).
inline constexpr double kFloatEps = 5.9604644775390625e-8;
constexpr double gamma_float(int n) { return (n * kFloatEps) / (1 - n * kFloatEps); }

/// std::nextafter(f, INFINITY) for a float that is not NaN, inline: the ray kernels compiled
/// for AVX2 call it with the upper halves of the vector registers in use, where a call into
/// libm's SSE code pays for the switch.
inline float float_next_up(float f) {
    if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
    if (f == INFINITY) return f;
    uint32_t bits;  // std::bit_cast, which the web build's libc++ lacks
    std::memcpy(&bits, &f, sizeof bits);
    bits = f > 0.0f ? bits + 1 : bits - 1;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}
/// Rounds a double distance limit to float, never below it.
inline float float_upper(double t) {
    if (!(t < 3.4e38)) return INFINITY;
    float f = static_cast<float>(t);
    if (static_cast<double>(f) < t) f = float_next_up(f);
    return f;
}
/// Rounds a double distance limit to float, never above it.
inline float float_lower(double t) {
    float f = static_cast<float>(t);
    if (static_cast<double>(f) > t) f = -float_next_up(-f);
    return f;
}

inline double max_component(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline bool is_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// A ray o + t*d. d need not be unit length (rays keep t across frames, spec §4.1).
struct Ray {
    Vec3 o{0.0};
    Vec3 d{0.0, 0.0, -1.0};
    Vec3 at(double t) const { return o + t * d; }
};

/// Open-ended parameter range [lo, hi] for ray hits.
struct Interval {
    double lo = 0.0;
    double hi = kInf;
    bool contains(double t) const { return t > lo && t < hi; }
};

/// Axis-aligned box; empty when lo > hi.
struct Bounds3 {
    Vec3 lo{kInf};
    Vec3 hi{-kInf};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void extend(const Vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Bounds3& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    Vec3 centre() const { return 0.5 * (lo + hi); }
    Vec3 diagonal() const { return hi - lo; }
    double surface_area() const {
        if (empty()) return 0.0;
        const Vec3 d = diagonal();
        return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    /// Grown by the rounding error of the arithmetic that produced it (a few operations per
    /// coordinate), so a box computed through a transform stays conservative.
    Bounds3 widened() const {
        if (empty()) return *this;
        const Vec3 err = gamma(3) * (glm::abs(lo) + glm::abs(hi));
        return {lo - err, hi + err};
    }
    int largest_axis() const {
        const Vec3 d = diagonal();
        return d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    }
};

/// The singular test of spec §4.1: |det A| <= 1e-12 |a1| |a2| |a3| (a_i the columns), which
/// also holds when a column is zero; a product that overflows counts as singular too.
inline bool singular_3x3(const Mat3& a) {
    // hypot: a column of length 1e200 must not overflow in its squared length.
    auto len = [](const Vec3& c) { return std::hypot(c.x, c.y, c.z); };
    const double scale = len(a[0]) * len(a[1]) * len(a[2]);
    const double det = glm::determinant(a);
    if (!std::isfinite(scale) || !std::isfinite(det)) return true;
    return scale == 0.0 || std::abs(det) <= 1e-12 * scale;
}

/// An affine transform p_parent = M p_local with its cached inverse and normal matrix
/// (spec §4.1: points by M, directions by A, normals by (A^-1)^T).
struct Transform {
    Mat4 m{1.0};
    Mat4 inv{1.0};
    Mat3 normal{1.0};  // (A^-1)^T

    static Transform from_matrix(const Mat4& m);

    Vec3 point(const Vec3& p) const { return Vec3(m * glm::dvec4(p, 1.0)); }
    Vec3 normal_dir(const Vec3& n) const { return normal * n; }
    /// A normal that is interpolated before it is normalised (a mesh vertex's): normal_dir(n)
    /// scaled by one positive factor of the transform (its normal matrix's largest entry), so
    /// magnitudes stay near n's whatever the scale. Spec §5 normalises only the interpolated
    /// sum; the map is linear, so no sum of such normals changes direction.
    Vec3 interpolable_normal(const Vec3& n) const;
    Vec3 inv_point(const Vec3& p) const { return Vec3(inv * glm::dvec4(p, 1.0)); }
    Vec3 inv_vector(const Vec3& v) const { return Mat3(inv) * v; }
    /// The ray in the local frame, direction not renormalised so t is unchanged.
    Ray inv_ray(const Ray& r) const { return {inv_point(r.o), inv_vector(r.d)}; }
    Bounds3 apply(const Bounds3& b) const;
    bool is_identity() const { return m == Mat4(1.0); }
};

inline Transform Transform::from_matrix(const Mat4& mat) {
    Transform t;
    t.m = mat;
    t.inv = glm::inverse(mat);
    t.normal = glm::transpose(Mat3(t.inv));
    return t;
}

inline Vec3 Transform::interpolable_normal(const Vec3& n) const {
    double largest = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) largest = std::max(largest, std::abs(normal[c][r]));
    const Vec3 mapped = normal_dir(n);
    return largest > 0.0 && std::isfinite(largest) ? mapped * (1.0 / largest) : mapped;
}

inline Bounds3 Transform::apply(const Bounds3& b) const {
    Bounds3 out;
    if (b.empty()) return out;
    for (int i = 0; i < 8; ++i) {
        const Vec3 c{(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y,
                     (i & 4) ? b.hi.z : b.lo.z};
        out.extend(point(c));
    }
    return out.widened();
}

}  // namespace rt
