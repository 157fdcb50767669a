// The 8-wide walk (AVX2 and AVX-512 only: isa_target.h): the test of a node's eight child boxes
// in one 256-bit register per plane, and the traversal over Bvh::nodes8 that calls back with
// leaves, as walk4.h's does over the 4-wide nodes. The leaves are the same in both trees; only
// the order they come in differs, so a caller whose answer does not depend on that order (the
// closest hit with its tie rule, any hit) may take either.
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <utility>

#include "accel/isa_target.h"
#include "accel/walk4.h"
#include "rt/accel/bvh.h"

#if !defined(RT_ISA_SSE2)

RT_ISA_BEGIN

/// BoxRay's values broadcast to eight lanes, for a ray with no parallel axis (the 4-wide walk
/// takes the others).
struct BoxRay8 {
    __m256 o[3], inv[3], slack[3], slack_max;
    explicit BoxRay8(const BoxRay& r) {
        for (int a = 0; a < 3; ++a) {
            o[a] = _mm256_set1_ps(_mm_cvtss_f32(r.o[a]));
            inv[a] = _mm256_set1_ps(_mm_cvtss_f32(r.inv[a]));
            slack[a] = _mm256_set1_ps(_mm_cvtss_f32(r.slack[a]));
        }
        slack_max = _mm256_set1_ps(_mm_cvtss_f32(r.slack_max));
    }
};

/// intersect_node_fast() for eight children: the same distances per lane (so the same boxes
/// are hit at the same entry distances as in the 4-wide tree's nodes of the same bounds), but
/// each axis's near and far planes are the min and max of its two, not picked by the
/// direction's sign: the loads then need no offsets read from the ray first, which sat on the
/// path from one node to the next (primary rays 10% faster on the meshes). Always inlined: GCC
/// kept it out of line in the larger walks, and the call with its 256-bit arguments made the
/// walk 30% slower than the 4-wide one (mesh10k, primary rays).
[[gnu::always_inline]] inline int intersect_node8(const Bvh8Node& node, const BoxRay8& ray,
                                                  __m256 t_max, __m256* t_entry) noexcept {
    constexpr float kWiden = static_cast<float>(1.0 + 2.0 * gamma_float(3));
    auto plane = [&](const float* p, int a) {
        return _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(p), ray.o[a]), ray.inv[a]);
    };
    const __m256 a0 = plane(node.lo[0], 0), b0 = plane(node.hi[0], 0);
    const __m256 a1 = plane(node.lo[1], 1), b1 = plane(node.hi[1], 1);
    const __m256 a2 = plane(node.lo[2], 2), b2 = plane(node.hi[2], 2);
    const __m256 n0 = _mm256_min_ps(a0, b0), n1 = _mm256_min_ps(a1, b1), n2 = _mm256_min_ps(a2, b2);
    const __m256 f0 = _mm256_max_ps(a0, b0), f1 = _mm256_max_ps(a1, b1), f2 = _mm256_max_ps(a2, b2);
    const __m256 t0 = _mm256_max_ps(
        _mm256_max_ps(_mm256_sub_ps(n0, ray.slack[0]), _mm256_sub_ps(n1, ray.slack[1])),
        _mm256_max_ps(_mm256_sub_ps(n2, ray.slack[2]), _mm256_setzero_ps()));
    const __m256 t1 = _mm256_min_ps(
        _mm256_add_ps(
            _mm256_mul_ps(_mm256_min_ps(_mm256_min_ps(f0, f1), f2), _mm256_set1_ps(kWiden)),
            ray.slack_max),
        t_max);
    *t_entry = t0;
    return _mm256_movemask_ps(_mm256_cmp_ps(t0, t1, _CMP_LE_OQ)) & ((1 << node.num_children) - 1);
}

/// walk_nodes() (walk4.h) over the 8-wide nodes, for a ray with no parallel axis.
template <bool kOrdered, class VisitLeaf, class Count = NoWalkCount>
void traverse_leaves8_impl(const Bvh& bvh, const BoxRay8& ray, double& t_max,
                           VisitLeaf&& visit_leaf, Count count = {}) {
    auto test = [&](const Bvh8Node& node, float tmax, float* t) {
        __m256 te;
        const int mask = intersect_node8(node, ray, _mm256_set1_ps(tmax), &te);
        _mm256_store_ps(t, te);
        return mask;
    };
    walk_nodes<kOrdered>(bvh.nodes8.data(), test, t_max, visit_leaf, count);
}

/// The walk over the 8-wide nodes when the tree has them and the ray has no parallel axis, else
/// walk4.h's over the 4-wide ones: the same leaves either way.
template <bool kOrdered, class VisitLeaf>
void traverse_leaves_wide(const Bvh& bvh, const Ray& ray, double& t_max, VisitLeaf&& visit_leaf) {
    if (bvh.empty()) return;
    const BoxRay box_ray(ray);
    if (box_ray.any_parallel)
        traverse_leaves_impl<kOrdered, false>(bvh, box_ray, t_max, visit_leaf);
    else if (!bvh.nodes8.empty())
        traverse_leaves8_impl<kOrdered>(bvh, BoxRay8(box_ray), t_max, visit_leaf);
    else
        traverse_leaves_impl<kOrdered, true>(bvh, box_ray, t_max, visit_leaf);
}

RT_ISA_END

#endif
