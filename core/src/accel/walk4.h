// The 4-wide walk (one kernel family, compiled per instruction set: isa_target.h): a ray
// prepared for float box tests, the test of a node's four child boxes, and the traversal that
// calls back with leaves. It reads only the Bvh: nothing of shapes or the format.
#pragma once

#include <immintrin.h>

#include <cmath>
#include <cstdint>
#include <utility>

#include "accel/isa_target.h"
#include "rt/accel/bvh.h"

RT_ISA_BEGIN

/// A ray prepared for float box tests (Ize 2013, "Robust BVH Ray Traversal"): the origin and
/// reciprocal direction rounded to float and broadcast to SSE registers, with a per-axis slack
/// that covers the rounding of the origin, so the slab distances bound the exact ones.
struct BoxRay {
    __m128 o[3], inv[3], slack[3];
    // Axes the ray hardly moves along (|d| < 1e-30, zero included): the test there is o in
    // [lo, hi] (closed), widened by o's rounding and by |d| t_max, how far the ray drifts
    // along the axis before t_max; not a distance from a reciprocal.
    bool parallel[3] = {false, false, false};
    bool any_parallel = false;
    float drift[3] = {0.0f, 0.0f, 0.0f};  // |d| on parallel axes
    // The fast test (no parallel axis): the float offsets in a node of each axis's near and far
    // planes (lo or hi by the direction's sign), and the largest slack of the three axes.
    int near_off[3] = {0, 4, 8}, far_off[3] = {12, 16, 20};
    __m128 slack_max;
    explicit BoxRay(const Ray& r);
};

/// Tests the ray against the four child boxes of a node; returns a 4-bit hit mask and the entry
/// distances. The far distance is widened by 2*gamma(3) in float (Ize 2013) plus the origin
/// slack; the near one is lowered by the slack. Serves any ray, parallel axes included.
inline int intersect_node(const Bvh4Node& node, const BoxRay& ray, float t_max, float t_entry[4]) {
    constexpr float kWiden = static_cast<float>(1.0 + 2.0 * gamma_float(3));
    const __m128 widen = _mm_set1_ps(kWiden);
    __m128 t0 = _mm_setzero_ps();
    __m128 t1 = _mm_set1_ps(t_max);
    __m128 inside = _mm_castsi128_ps(_mm_set1_epi32(-1));
    for (int a = 0; a < 3; ++a) {
        if (ray.parallel[a]) {
            __m128 s = ray.slack[a];
            if (ray.drift[a] > 0.0f) s = _mm_add_ps(s, _mm_set1_ps(ray.drift[a] * t_max * kWiden));
            inside = _mm_and_ps(
                inside, _mm_and_ps(_mm_cmple_ps(_mm_load_ps(node.lo[a]), _mm_add_ps(ray.o[a], s)),
                                   _mm_cmpge_ps(_mm_load_ps(node.hi[a]), _mm_sub_ps(ray.o[a], s))));
            continue;
        }
        const __m128 ta = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.lo[a]), ray.o[a]), ray.inv[a]);
        const __m128 tb = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.hi[a]), ray.o[a]), ray.inv[a]);
        const __m128 tn = _mm_sub_ps(_mm_min_ps(ta, tb), ray.slack[a]);
        const __m128 tf = _mm_add_ps(_mm_mul_ps(_mm_max_ps(ta, tb), widen), ray.slack[a]);
        t0 = _mm_max_ps(t0, tn);
        t1 = _mm_min_ps(t1, tf);
    }
    _mm_storeu_ps(t_entry, t0);
    return _mm_movemask_ps(_mm_and_ps(_mm_cmple_ps(t0, t1), inside)) &
           ((1 << node.num_children) - 1);
}

/// The same test for a ray with no parallel axis, in fewer operations: the near and far planes
/// are picked by the direction's signs (no min/max per axis), and the widening and the slack of
/// the far distance are applied once over all axes, with the largest slack (a looser bound,
/// never a tighter one).
inline int intersect_node_fast(const Bvh4Node& node, const BoxRay& ray, __m128 t_max,
                               __m128* t_entry) noexcept {
    constexpr float kWiden = static_cast<float>(1.0 + 2.0 * gamma_float(3));
    const float* base = &node.lo[0][0];
    // Distance to the plane at float offset `off` of the node, along axis a.
    auto plane = [&](int off, int a) {
        return _mm_mul_ps(_mm_sub_ps(_mm_load_ps(base + off), ray.o[a]), ray.inv[a]);
    };
    const __m128 n0 = plane(ray.near_off[0], 0), n1 = plane(ray.near_off[1], 1),
                 n2 = plane(ray.near_off[2], 2);
    const __m128 f0 = plane(ray.far_off[0], 0), f1 = plane(ray.far_off[1], 1),
                 f2 = plane(ray.far_off[2], 2);
    // The entry distances are intersect_node()'s to the bit: the order children are visited
    // in, and so which of two hits at the same distance is kept, does not change.
    const __m128 t0 =
        _mm_max_ps(_mm_max_ps(_mm_sub_ps(n0, ray.slack[0]), _mm_sub_ps(n1, ray.slack[1])),
                   _mm_max_ps(_mm_sub_ps(n2, ray.slack[2]), _mm_setzero_ps()));
    const __m128 t1 =
        _mm_min_ps(_mm_add_ps(_mm_mul_ps(_mm_min_ps(_mm_min_ps(f0, f1), f2), _mm_set1_ps(kWiden)),
                              ray.slack_max),
                   t_max);
    *t_entry = t0;
    // Empty slots (lo = +inf, hi = -inf) miss on their own unless a reciprocal underflowed to
    // zero (|d| > 1e38), where inf * 0 is NaN: the mask of filled slots decides.
    return _mm_movemask_ps(_mm_cmple_ps(t0, t1)) & ((1 << node.num_children) - 1);
}

/// A subtree waiting on walk_nodes()' stack, and where the ray enters its box.
struct WalkEntry {
    uint32_t child;
    float t;
};

/// A child pushed for later is fetched meanwhile (all of its cache lines).
template <class Node>
[[gnu::always_inline]] inline void prefetch_node(const Node* nodes, uint32_t child) {
    if (child & Bvh4Node::kLeaf) return;
    const char* p = reinterpret_cast<const char*>(nodes + child);
    for (size_t line = 0; line < sizeof(Node) / 64; ++line)
        _mm_prefetch(p + 64 * line, _MM_HINT_T0);
}

/// Traversal over 4-wide or 8-wide nodes (Bvh4Node, Bvh8Node): `test(node, tmax, t)` returns
/// the mask of the children whose boxes the ray enters before tmax and writes their entry
/// distances to t. `visit_leaf(first, count, t_max)` tests the leaf's primitives (positions
/// first .. first + count - 1 of `indices`) and may shrink t_max (closest hit); it returns true
/// to stop the whole walk (any hit). With kOrdered, children are visited nearest entry first
/// (one hit: no stack; two: one compare; more: sorted on the stack) and a subtree whose box
/// starts beyond t_max is skipped (closest-hit queries); any-hit queries skip the sorting. The
/// walk keeps the node it descends into in a register and pushes only the other children hit.
/// Its stack: each level pushes at most kWidth - 1 entries and consumes at least one level of
/// the binary tree, which the build keeps below 40 + log2(n) deep (bvh.cpp): 512 entries hold
/// any tree of up to 2^32 primitives.
template <bool kOrdered, class Node, class TestNode, class VisitLeaf, class Count>
void walk_nodes(const Node* nodes, TestNode&& test, double& t_max, VisitLeaf&& visit_leaf,
                Count count) {
    constexpr int kWidth = sizeof(Node::child) / sizeof(uint32_t);
    using Entry = WalkEntry;
    Entry stack[512];  // the depth: above
    int sp = 0;
    // Box tests in float compare against t_max rounded up; updated when a leaf shrinks it.
    auto t_max_f = [&] { return static_cast<float>(t_max) * (1.0f + 1e-6f) + 1e-30f; };
    float tmax = t_max_f();
    auto prefetch = [&](uint32_t child) { prefetch_node(nodes, child); };
    uint32_t cur = 0;
    for (;;) {
        if (!(cur & Bvh4Node::kLeaf)) {
            const Node& node = nodes[cur];
            count.node();
            alignas(32) float t[kWidth];
            int mask = test(node, tmax, t);
            if (mask) {
                const int i0 = __builtin_ctz(static_cast<unsigned>(mask));
                mask &= mask - 1;
                if (!mask) {  // one child hit: descend without the stack
                    cur = node.child[i0];
                    continue;
                }
                if constexpr (!kOrdered) {
                    while (mask) {
                        const int i = __builtin_ctz(static_cast<unsigned>(mask));
                        mask &= mask - 1;
                        stack[sp++] = {node.child[i], 0.0f};
                        prefetch(node.child[i]);
                    }
                    cur = node.child[i0];
                    continue;
                } else {
                    const int i1 = __builtin_ctz(static_cast<unsigned>(mask));
                    mask &= mask - 1;
                    Entry a{node.child[i0], t[i0]}, b{node.child[i1], t[i1]};
                    if (a.t >= b.t) std::swap(a, b);  // a tie: the later slot first, as below
                    if (!mask) {                      // two: the far one waits
                        stack[sp++] = b;
                        prefetch(b.child);
                        cur = a.child;
                        continue;
                    }
                    // More: sorted into the stack, farthest deepest; the nearest taken at once.
                    Entry* hits = stack + sp;
                    hits[0] = b;
                    hits[1] = a;
                    int n = 2;
                    while (mask) {
                        const int i = __builtin_ctz(static_cast<unsigned>(mask));
                        mask &= mask - 1;
                        const Entry h{node.child[i], t[i]};
                        int k = n++;
                        while (k > 0 && hits[k - 1].t < h.t) hits[k] = hits[k - 1], --k;
                        hits[k] = h;
                    }
                    sp += n - 1;
                    prefetch(hits[n - 2].child);
                    cur = hits[n - 1].child;
                    continue;
                }
            }
        } else {
            count.leaf();
            if (visit_leaf(Bvh4Node::leaf_first(cur), Bvh4Node::leaf_count(cur), t_max)) return;
            if constexpr (kOrdered) tmax = t_max_f();
        }
        // Pop the next subtree; with kOrdered, those that start beyond the best hit are gone.
        for (;;) {
            if (sp == 0) return;
            const Entry e = stack[--sp];
            if (!kOrdered || e.t <= tmax) {
                cur = e.child;
                break;
            }
        }
    }
}

/// walk_nodes() over the 4-wide nodes; kFast: the ray has no parallel axis.
template <bool kOrdered, bool kFast, class VisitLeaf, class Count = NoWalkCount>
void traverse_leaves_impl(const Bvh& bvh, const BoxRay& box_ray, double& t_max,
                          VisitLeaf&& visit_leaf, Count count = {}) {
    auto test = [&](const Bvh4Node& node, float tmax, float* t) {
        if constexpr (kFast) {
            __m128 te;
            const int mask = intersect_node_fast(node, box_ray, _mm_set1_ps(tmax), &te);
            _mm_store_ps(t, te);
            return mask;
        } else {
            return intersect_node(node, box_ray, tmax, t);
        }
    };
    walk_nodes<kOrdered>(bvh.nodes.data(), test, t_max, visit_leaf, count);
}

template <bool kOrdered = true, class VisitLeaf>
void traverse_leaves(const Bvh& bvh, const Ray& ray, double& t_max, VisitLeaf&& visit_leaf) {
    if (bvh.empty()) return;
    const BoxRay box_ray(ray);
    if (box_ray.any_parallel)
        traverse_leaves_impl<kOrdered, false>(bvh, box_ray, t_max, visit_leaf);
    else
        traverse_leaves_impl<kOrdered, true>(bvh, box_ray, t_max, visit_leaf);
}

/// The same walk with one call per primitive: `visit(prim_index, t_max)`.
template <bool kOrdered = true, class Visit>
void traverse(const Bvh& bvh, const Ray& ray, double& t_max, Visit&& visit) {
    traverse_leaves<kOrdered>(bvh, ray, t_max, [&](uint32_t first, uint32_t count, double& t) {
        for (uint32_t i = first; i < first + count; ++i)
            if (visit(bvh.indices[i], t)) return true;
        return false;
    });
}

inline BoxRay::BoxRay(const Ray& r) {
    float slack_hi = 0.0f;
    for (int a = 0; a < 3; ++a) {
        const float of = static_cast<float>(r.o[a]);
        o[a] = _mm_set1_ps(of);
        const double rounding = std::abs(r.o[a] - static_cast<double>(of));
        if (std::abs(r.d[a]) < 1e-30) {
            // A containment test (intersect_node): a huge reciprocal instead would turn an
            // origin exactly on a box's upper face into a far distance of about 1 and cull
            // every box behind it. The ray's drift |d| t_max is added there per query.
            parallel[a] = true;
            inv[a] = _mm_setzero_ps();
            slack[a] = _mm_set1_ps(float_upper(rounding));
            drift[a] = float_upper(std::abs(r.d[a]));
            continue;
        }
        const double inv_d = 1.0 / r.d[a];
        const float inv_f = static_cast<float>(inv_d);
        // The origin's rounding to float moves the slab distances by up to |o - o_f| / |d|.
        const double slack_d = (rounding + 1e-30) * std::abs(inv_d) * 2.0;
        inv[a] = _mm_set1_ps(inv_f);
        slack[a] = _mm_set1_ps(static_cast<float>(slack_d));
        slack_hi = std::max(slack_hi, static_cast<float>(slack_d));
        if (inv_f < 0.0f) near_off[a] = 12 + 4 * a, far_off[a] = 4 * a;
    }
    any_parallel = parallel[0] || parallel[1] || parallel[2];
    slack_max = _mm_set1_ps(slack_hi);
}

RT_ISA_END
