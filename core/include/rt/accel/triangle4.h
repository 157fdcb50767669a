// Four triangles tested against one ray at once, in single precision with SSE: the watertight
// ray/triangle algorithm of Woop, Benthin and Wald (JCGT 2013), with pbrt-v4's conservative
// bound on the computed distance so that a ray leaving a triangle never finds that triangle
// again at t ~ 0. Every triangle test of the renderer goes through this kernel (the BVH path and
// the brute-force path alike), so both see exactly the same hits.
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "rt/util/math.h"

namespace rt {

/// Four triangles, structure of arrays: p[vertex][axis][lane], in the set's frame.
struct alignas(16) Tri4 {
    float p[3][3][4];
};

/// Writes the triangle (p0, p1, p2), relative to `origin` and rounded to float, into lane `lane`
/// of a block: the one float copy of a triangle that rays test.
inline void put_triangle(Tri4& block, int lane, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                         const Vec3& origin) {
    const Vec3* v[3] = {&p0, &p1, &p2};
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a)
            block.p[k][a][lane] = static_cast<float>((*v[k])[a] - origin[a]);
}

/// Per-ray constants of the watertight test: the axis permutation that makes z the dominant
/// direction and the shear that maps the ray onto +z.
struct TriRay {
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
    float o[3] = {0, 0, 0};
    double od[3] = {0, 0, 0}, dd[3] = {0, 0, 1};  // the ray in double, unpermuted (see below)
    TriRay() = default;                           // not set up: for sets without triangles
    explicit TriRay(const Ray& r);
};

/// Tests the lanes of `lanes_mask`. Returns a mask of the lanes hit with t in (t_lo, t_hi) and
/// writes their distances to t_out; the upper test is conservative (a lane may come back with a
/// distance a few float steps beyond t_hi, never one below it that is dropped), so callers
/// compare the distances returned with their own bound, and the lanes found do not depend on
/// how tight t_hi was. A lane that the float edge test hits but whose float distance
/// lies inside pbrt-v4's error band around zero (a grazing hit: the band is loose when the
/// triangle is seen nearly edge-on) gets its distance recomputed in double before it is rejected,
/// so the band never opens a hole between triangles.
int intersect_tri4(const Tri4& tri, const TriRay& ray, int lanes_mask, float t_lo, float t_hi,
                   float t_out[4]);

}  // namespace rt
