// The packed triangle test (one kernel family, compiled per instruction set: isa_target.h): four
// triangles against one ray in single precision, watertight (rt/accel/triangle4.h says how).
#pragma once

#include <immintrin.h>

#include "accel/isa_target.h"
#include "rt/accel/triangle4.h"

namespace rt {
// The rare cases, in double and out of line (triangle4.cpp): the distance of a hit inside the
// error band, and edge functions of exactly zero.
double tri4_plane_distance_double(const Tri4& tri, int l, const TriRay& ray);
void tri4_edges_in_double(const __m128 x[3], const __m128 y[3], int lanes, __m128* e0, __m128* e1,
                          __m128* e2) noexcept;
}  // namespace rt

RT_ISA_BEGIN

inline __m128 abs_ps(__m128 v) noexcept { return _mm_andnot_ps(_mm_set1_ps(-0.0f), v); }

// The value, rounded and in a register: an empty asm the optimiser cannot see through, so a
// product passed through it is never fused into a multiply-add (GCC contracts a * b - c * d into
// an FMA with -march=native even in ISO mode, which broke watertightness: see the edge functions).
inline __m128 rounded(__m128 v) noexcept {
#ifndef __wasm__  // WebAssembly has no fused multiply-add to contract into
    __asm__("" : "+x"(v));
#endif
    return v;
}
// a * b - c * d with both products rounded: exactly -(c * d - a * b).
inline __m128 cross_ps(__m128 a, __m128 b, __m128 c, __m128 d) noexcept {
    return _mm_sub_ps(rounded(_mm_mul_ps(a, b)), rounded(_mm_mul_ps(c, d)));
}

constexpr float gamma_f(int n) { return static_cast<float>(gamma_float(n)); }

// pbrt-v4's bound on the error of the distance, times |det| (delta_t * |det|), from the sheared
// vertices (z already scaled by sz) and the edge functions.
inline __m128 distance_error_scaled(const __m128 x[3], const __m128 y[3], const __m128 z[3],
                                    __m128 e0, __m128 e1, __m128 e2) noexcept {
    const __m128 max_z = _mm_max_ps(_mm_max_ps(abs_ps(z[0]), abs_ps(z[1])), abs_ps(z[2]));
    const __m128 max_x = _mm_max_ps(_mm_max_ps(abs_ps(x[0]), abs_ps(x[1])), abs_ps(x[2]));
    const __m128 max_y = _mm_max_ps(_mm_max_ps(abs_ps(y[0]), abs_ps(y[1])), abs_ps(y[2]));
    const __m128 g2 = _mm_set1_ps(gamma_f(2)), g3 = _mm_set1_ps(gamma_f(3)),
                 g5 = _mm_set1_ps(gamma_f(5));
    const __m128 delta_z = _mm_mul_ps(g3, max_z);
    const __m128 delta_x = _mm_mul_ps(g5, _mm_add_ps(max_x, max_z));
    const __m128 delta_y = _mm_mul_ps(g5, _mm_add_ps(max_y, max_z));
    const __m128 delta_e = _mm_mul_ps(
        _mm_set1_ps(2.0f),
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(g2, _mm_mul_ps(max_x, max_y)), _mm_mul_ps(delta_y, max_x)),
                   _mm_mul_ps(delta_x, max_y)));
    const __m128 max_e = _mm_max_ps(_mm_max_ps(abs_ps(e0), abs_ps(e1)), abs_ps(e2));
    return _mm_mul_ps(
        _mm_set1_ps(3.0f),
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(g3, _mm_mul_ps(max_e, max_z)), _mm_mul_ps(delta_e, max_z)),
                   _mm_mul_ps(delta_z, max_e)));
}

/// The lanes of `band` (hits within t's error bound) decided by their distance in double: those
/// inside (t_lo, t_hi) join `mask`, their distances written to t_out.
[[gnu::always_inline]] inline int band_hits(const Tri4& tri, const TriRay& ray, int band,
                                            float t_lo, float t_hi, float t_out[4], int mask) {
    for (int b = band; b;) {
        const int l = __builtin_ctz(static_cast<unsigned>(b));
        b &= b - 1;
        const double t = tri4_plane_distance_double(tri, l, ray);
        // A ray spawned at a hit starts outside its surface's error box (offset_origin), so its
        // own triangle is at t <= 0 in double; NaN (undecidable) stays rejected.
        if (t > static_cast<double>(t_lo) && t < static_cast<double>(t_hi)) {
            t_out[l] = static_cast<float>(t);
            mask |= 1 << l;
        }
    }
    return mask;
}

inline int tri4_hits(const Tri4& tri, const TriRay& ray, int lanes_mask, float t_lo, float t_hi,
                     float t_out[4]) {
    const __m128 ox = _mm_set1_ps(ray.o[ray.kx]), oy = _mm_set1_ps(ray.o[ray.ky]),
                 oz = _mm_set1_ps(ray.o[ray.kz]);
    const __m128 sx = _mm_set1_ps(ray.sx), sy = _mm_set1_ps(ray.sy), sz = _mm_set1_ps(ray.sz);

    // Vertices relative to the ray origin, permuted, then sheared so the ray is the +z axis.
    __m128 x[3], y[3], z[3];
    for (int v = 0; v < 3; ++v) {
        z[v] = _mm_sub_ps(_mm_load_ps(tri.p[v][ray.kz]), oz);
        x[v] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(tri.p[v][ray.kx]), ox), _mm_mul_ps(sx, z[v]));
        y[v] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(tri.p[v][ray.ky]), oy), _mm_mul_ps(sy, z[v]));
    }
    // Edge functions: the signed areas seen from the ray. Watertightness (Woop, Benthin, Wald,
    // JCGT 2(1) 2013, §3) rests on a shared edge giving exactly opposite values in its two
    // triangles, which holds for round(round(a*b) - round(c*d)) but not for a fused multiply-add
    // (fma(a, b, -c*d) != -fma(c, d, -a*b)): with -O3 -march=native GCC fused these and 50168 of
    // 2.9 million rays leaked out of closed meshes (tests/test_intersect.cpp). cross_ps forbids it.
    __m128 e0 = cross_ps(x[1], y[2], y[1], x[2]);
    __m128 e1 = cross_ps(x[2], y[0], y[2], x[0]);
    __m128 e2 = cross_ps(x[0], y[1], y[0], x[1]);

    const __m128 zero = _mm_setzero_ps();
    // An edge function of exactly zero is recomputed in double (the watertight fallback).
    const int zero_mask = _mm_movemask_ps(_mm_or_ps(
        _mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)), _mm_cmpeq_ps(e2, zero)));
    if (zero_mask & lanes_mask) tri4_edges_in_double(x, y, zero_mask & lanes_mask, &e0, &e1, &e2);

    // Inside when all edge functions share a sign (zero counts for both).
    const __m128 any_neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)),
                                     _mm_cmplt_ps(e2, zero));
    const __m128 any_pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)),
                                     _mm_cmpgt_ps(e2, zero));
    const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
    int mask = lanes_mask & ~_mm_movemask_ps(_mm_and_ps(any_neg, any_pos)) &
               ~_mm_movemask_ps(_mm_cmpeq_ps(det, zero));
    if (!mask) return 0;

    // Scaled distance, compared against the interval without dividing.
    for (int v = 0; v < 3; ++v) z[v] = _mm_mul_ps(z[v], sz);
    const __m128 t_scaled =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, z[0]), _mm_mul_ps(e1, z[1])), _mm_mul_ps(e2, z[2]));

    // pbrt-v4's conservative bound on t's error: a hit closer than it may be the surface the
    // ray starts on, seen through rounding, and is rejected. Everything is compared scaled by
    // |det| (t = t_scaled / det), so only the hits pay for a division.
    const __m128 delta_t_scaled = distance_error_scaled(x, y, z, e0, e1, e2);
    // t * |det|, positive when t is.
    const __m128 sign = _mm_and_ps(det, _mm_set1_ps(-0.0f));
    const __m128 ts = _mm_xor_ps(t_scaled, sign);
    const __m128 abs_det = abs_ps(det);
    const __m128 lo = _mm_max_ps(_mm_mul_ps(_mm_set1_ps(t_lo), abs_det), delta_t_scaled);
    // The upper bound is rounded up (relative 2^-21, plus a few subnormal steps): a lane whose
    // returned distance t_scaled / det lies below t_hi always passes, and the caller decides on
    // that distance. Rounded down, t_hi * |det| could reject such a lane, and whether a hit was
    // found would depend on how tight t_hi was when its lane was tested: the packed walk (four
    // lanes against the bound at the start of a block) and the walk of one triangle at a time
    // (the generic renderer) found different triangles of near-coincident pairs.
    const __m128 hi =
        _mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(t_hi), abs_det), _mm_set1_ps(1.0f + 0x1p-21f)),
                   _mm_set1_ps(0x1p-146f));
    const int firm = _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(ts, lo), _mm_cmplt_ps(ts, hi)));
    // Hits inside the error band (t * |det| <= delta_t * |det|, but not below t_lo): the band is
    // a conservative bound that grows without limit relative to t as the triangle turns edge-on,
    // so a ray that grazes a mesh far from its origin could be rejected by every triangle around
    // the point it crosses (a leak). Such lanes are decided by their distance in double instead.
    // Lanes surely behind the origin (t * |det| < -delta_t * |det|) are not in the band. The
    // upper bound is left to the double distance, so that a band lane's fate does not depend
    // on the float bound either.
    const int band =
        mask & ~firm &
        _mm_movemask_ps(_mm_and_ps(_mm_cmple_ps(ts, delta_t_scaled),
                                   _mm_cmpge_ps(ts, _mm_sub_ps(_mm_setzero_ps(), delta_t_scaled))));
    mask &= firm;
    if (mask) _mm_storeu_ps(t_out, _mm_div_ps(t_scaled, det));
    return band_hits(tri, ray, band, t_lo, t_hi, t_out, mask);
}

/// The blocks of a packed leaf (blocks `first` and on, `count` triangles: full blocks but the
/// last) against the ray in (t_lo, best), best read again for each block:
/// `on_lane(block, lane, t)` for each lane hit (its t to be checked against the caller's own
/// bounds); it returns true to stop, and so does this.
template <class OnLane>
bool leaf_block_hits(const Tri4* blocks, uint32_t first, uint32_t count, const TriRay& ray,
                     float t_lo, const double& best, OnLane&& on_lane) {
    for (uint32_t k = 0; k < count; k += 4) {
        const uint32_t b = first + k / 4;
        const int lanes = count - k >= 4 ? 15 : (1 << (count - k)) - 1;
        float tt[4];
        for (int m = tri4_hits(blocks[b], ray, lanes, t_lo, float_upper(best), tt); m; m &= m - 1) {
            const int l = __builtin_ctz(static_cast<unsigned>(m));
            if (on_lane(b, l, static_cast<double>(tt[l]))) return true;
        }
    }
    return false;
}

RT_ISA_END
