#include "rt/accel/bvh.h"

#include <immintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <thread>

#include "rt/util/threads.h"

namespace rt {

namespace {

// A box in float with SSE: lo in v[0] (lanes x, y, z), hi in v[1]; what the builder keeps per
// node and per bin.
struct Box4 {
    __m128 lo = _mm_set1_ps(INFINITY), hi = _mm_set1_ps(-INFINITY);
    void extend(__m128 l, __m128 h) noexcept {
        lo = _mm_min_ps(lo, l);
        hi = _mm_max_ps(hi, h);
    }
    void extend(const Box4& b) { extend(b.lo, b.hi); }
    float area() const {
        alignas(16) float d[4];
        _mm_store_ps(d, _mm_max_ps(_mm_sub_ps(hi, lo), _mm_setzero_ps()));
        return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
    }
    float lo_at(int a) const {
        alignas(16) float v[4];
        _mm_store_ps(v, lo);
        return v[a];
    }
    float hi_at(int a) const {
        alignas(16) float v[4];
        _mm_store_ps(v, hi);
        return v[a];
    }
    int largest_axis() const {
        const float dx = hi_at(0) - lo_at(0), dy = hi_at(1) - lo_at(1), dz = hi_at(2) - lo_at(2);
        return dx >= dy && dx >= dz ? 0 : dy >= dz ? 1 : 2;
    }
};

// The fourth lane of lo holds the id: as a float most ids are denormal, and every multiply or
// add on one took a microcode assist (the build ran four times slower). It is cleared.
inline __m128 ref_lo(const PrimRef& r) {
    return _mm_and_ps(_mm_load_ps(r.lo), _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)));
}
inline __m128 ref_hi(const PrimRef& r) { return _mm_load_ps(r.hi); }
// The centroid, from the bounds clamped to the finite floats: a box beyond float range (the
// compile allows shapes out to 1e300) has infinite bounds, and -inf + inf would be NaN.
inline __m128 ref_centre(const PrimRef& r) noexcept {
    const __m128 big = _mm_set1_ps(std::numeric_limits<float>::max()), half = _mm_set1_ps(0.5f);
    auto clamp = [&](__m128 v) noexcept {
        return _mm_min_ps(_mm_max_ps(v, _mm_sub_ps(_mm_setzero_ps(), big)), big);
    };
    return _mm_add_ps(_mm_mul_ps(clamp(ref_lo(r)), half), _mm_mul_ps(clamp(ref_hi(r)), half));
}

// The binary tree the SAH builder makes; collapsed into Bvh4Node afterwards.
struct Node2 {
    Box4 bounds;
    uint32_t left = 0, right = 0;   // interior: children
    uint32_t first = 0, count = 0;  // leaf: count > 0
};

constexpr int kMaxBins = 32;
constexpr int kSahDepth = 40;

// Binned SAH over a contiguous array of primitive references that the splits partition in
// place (each pass reads memory in order: no index indirection).
struct Builder {
    PrimRef* refs = nullptr;
    HugePageVector<Node2> nodes;
    BvhBuildSettings settings;
    int spawn_depth = 0;  // subtrees above this depth are built on their own thread

    // Bounds and centroid bounds of refs[begin, end).
    void measure(uint32_t begin, uint32_t end, Box4* box, Box4* cbox) const {
        for (uint32_t i = begin; i < end; ++i) {
            box->extend(ref_lo(refs[i]), ref_hi(refs[i]));
            const __m128 c = ref_centre(refs[i]);
            cbox->extend(c, c);
        }
    }

    uint32_t leaf(const Box4& box, uint32_t begin, uint32_t n, int depth) {
        // Leaves hold at most kMaxLeafCount primitives; larger sets (coincident centroids) are
        // halved in their current order.
        if (n > Bvh4Node::kMaxLeafCount) return split(box, begin, begin + n / 2, begin + n, depth);
        Node2 node;
        node.bounds = box;
        node.first = begin;
        node.count = n;
        nodes.push_back(node);
        return static_cast<uint32_t>(nodes.size() - 1);
    }

    // Splits at mid, measuring both halves.
    uint32_t split(const Box4& box, uint32_t begin, uint32_t mid, uint32_t end, int depth) {
        Box4 lb, lc, rb, rc;
        measure(begin, mid, &lb, &lc);
        measure(mid, end, &rb, &rc);
        return split(box, begin, mid, end, depth, lb, lc, rb, rc);
    }

    uint32_t split(const Box4& box, uint32_t begin, uint32_t mid, uint32_t end, int depth,
                   const Box4& lb, const Box4& lc, const Box4& rb, const Box4& rc) {
        const uint32_t index = static_cast<uint32_t>(nodes.size());
        Node2 inner;
        inner.bounds = box;
        nodes.push_back(inner);
        uint32_t l = 0, r = 0;
        if (depth < spawn_depth && end - begin > 50000) {
            // The left subtree on another thread, into its own node array, merged afterwards.
            Builder sub;
            sub.refs = refs;
            sub.settings = settings;
            sub.spawn_depth = spawn_depth;
            // Room for its half as build_bvh() makes it for the whole, so it does not double.
            sub.nodes.reserve(nodes.capacity() * (mid - begin) / (end - begin) + 16);
            std::thread t([&] { sub.build(begin, mid, depth + 1, lb, lc); });
            r = build(mid, end, depth + 1, rb, rc);
            t.join();
            l = static_cast<uint32_t>(nodes.size());
            for (Node2 n : sub.nodes) {
                if (n.count == 0) n.left += l, n.right += l;
                nodes.push_back(n);
            }
        } else {
            l = build(begin, mid, depth + 1, lb, lc);
            r = build(mid, end, depth + 1, rb, rc);
        }
        nodes[index].left = l;
        nodes[index].right = r;
        return index;
    }

    uint32_t build(uint32_t begin, uint32_t end, int depth, const Box4& box, const Box4& cbox) {
        const uint32_t n = end - begin;
        const int axis = cbox.largest_axis();
        const float c_lo = cbox.lo_at(axis);
        const float extent = cbox.hi_at(axis) - c_lo;
        if (n <= static_cast<uint32_t>(settings.max_leaf_size) || !(extent > 0.0f))
            return leaf(box, begin, n, depth);
        // Deep in the tree (SAH can peel one primitive at a time off wildly spread sizes), only
        // median splits: each halves the set, so the depth stays below kSahDepth + log2(n) and
        // the traversal stack (bvh.h) cannot overflow.
        if (depth >= kSahDepth) return median(box, begin, end, axis, depth);

        // Binned SAH along the largest centroid axis; each bin keeps its primitives' bounds and
        // centroid bounds, so the children's boxes come from the bins, not another pass.
        const int nb = std::clamp(settings.bins, 2, kMaxBins);
        std::array<Box4, kMaxBins> bin_box{}, bin_cbox{};
        std::array<uint32_t, kMaxBins> bin_count{};
        const float scale = static_cast<float>(nb) / extent;
        // A spread so small (subnormal) that the bin scale overflows: binning cannot separate
        // the centroids, and (c - lo) * inf would be NaN cast to int. Median split instead.
        if (!std::isfinite(scale)) return median(box, begin, end, axis, depth);
        auto bin_of = [&](const PrimRef& r) {
            alignas(16) float c[4];
            _mm_store_ps(c, ref_centre(r));
            const int b = static_cast<int>((c[axis] - c_lo) * scale);
            return std::clamp(b, 0, nb - 1);
        };
        for (uint32_t i = begin; i < end; ++i) {
            const size_t b = static_cast<size_t>(bin_of(refs[i]));
            bin_box[b].extend(ref_lo(refs[i]), ref_hi(refs[i]));
            const __m128 c = ref_centre(refs[i]);
            bin_cbox[b].extend(c, c);
            ++bin_count[b];
        }
        // A leaf of n primitives costs ceil(n / leaf_block) tests.
        const uint32_t block = static_cast<uint32_t>(std::max(settings.leaf_block, 1));
        auto blocks = [&](uint32_t count) {
            return static_cast<float>((count + block - 1) / block);
        };
        std::array<float, kMaxBins> right_cost{};
        Box4 acc;
        uint32_t cnt = 0;
        for (int b = nb - 1; b > 0; --b) {
            acc.extend(bin_box[static_cast<size_t>(b)]);
            cnt += bin_count[static_cast<size_t>(b)];
            right_cost[static_cast<size_t>(b)] = acc.area() * blocks(cnt);
        }
        float best_cost = INFINITY;
        int best = -1;
        acc = Box4{};
        cnt = 0;
        for (int b = 1; b < nb; ++b) {
            acc.extend(bin_box[static_cast<size_t>(b - 1)]);
            cnt += bin_count[static_cast<size_t>(b - 1)];
            if (cnt == 0 || cnt == n) continue;
            const float cost = acc.area() * blocks(cnt) + right_cost[static_cast<size_t>(b)];
            if (cost < best_cost) best_cost = cost, best = b;
        }
        // Leaf cost (its tests) * area against traversal (~1 test) plus the children.
        const float leaf_cost = box.area() * blocks(n);
        if (best < 0) return median(box, begin, end, axis, depth);
        if (best_cost + box.area() >= leaf_cost && n <= Bvh4Node::kMaxLeafCount)
            return leaf(box, begin, n, depth);
        const uint32_t mid = static_cast<uint32_t>(
            std::partition(refs + begin, refs + end,
                           [&](const PrimRef& r) { return bin_of(r) < best; }) -
            refs);
        Box4 lb, lc, rb, rc;
        for (int b = 0; b < nb; ++b) {
            const size_t i = static_cast<size_t>(b);
            (b < best ? lb : rb).extend(bin_box[i]);
            (b < best ? lc : rc).extend(bin_cbox[i]);
        }
        return split(box, begin, mid, end, depth, lb, lc, rb, rc);
    }

    uint32_t median(const Box4& box, uint32_t begin, uint32_t end, int axis, int depth) {
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(refs + begin, refs + mid, refs + end,
                         [&](const PrimRef& a, const PrimRef& b) {
                             alignas(16) float ca[4], cb[4];
                             _mm_store_ps(ca, ref_centre(a));
                             _mm_store_ps(cb, ref_centre(b));
                             return ca[axis] < cb[axis];
                         });
        return split(box, begin, mid, end, depth);
    }
};

// Collapses the binary tree into W-wide nodes: each node adopts the grandchildren of its
// largest interior children until it has W.
template <class WideNode, int W>
struct Collapser {
    const HugePageVector<Node2>& in;
    HugePageVector<WideNode>& out;

    uint32_t encode(uint32_t n2) {
        const Node2& n = in[n2];
        if (n.count > 0) return Bvh4Node::leaf(n.first, n.count);
        return emit(n2);
    }

    uint32_t emit(uint32_t n2) {
        const uint32_t index = static_cast<uint32_t>(out.size());
        out.emplace_back();
        std::array<uint32_t, W> kids{};
        int k = 0;
        const Node2& root = in[n2];
        if (root.count > 0) {
            kids[k++] = n2;  // a leaf root: one child
        } else {
            kids[k++] = root.left;
            kids[k++] = root.right;
            while (k < W) {
                // Open the interior child with the largest surface area.
                int best = -1;
                float area = -1;
                for (int i = 0; i < k; ++i) {
                    const Node2& c = in[kids[static_cast<size_t>(i)]];
                    if (c.count == 0 && c.bounds.area() > area) area = c.bounds.area(), best = i;
                }
                if (best < 0) break;
                const Node2& c = in[kids[static_cast<size_t>(best)]];
                kids[static_cast<size_t>(best)] = c.left;
                kids[static_cast<size_t>(k++)] = c.right;
            }
        }
        WideNode node{};
        for (int i = 0; i < W; ++i) {
            for (int a = 0; a < 3; ++a) {
                node.lo[a][i] = INFINITY;  // empty slot: never hit
                node.hi[a][i] = -INFINITY;
            }
            node.child[i] = Bvh4Node::kEmpty;
        }
        for (int i = 0; i < k; ++i) {
            const Node2& c = in[kids[static_cast<size_t>(i)]];
            for (int a = 0; a < 3; ++a) {
                node.lo[a][i] = c.bounds.lo_at(a);  // already rounded outward (PrimRef)
                node.hi[a][i] = c.bounds.hi_at(a);
            }
        }
        node.num_children = static_cast<uint32_t>(k);
        out[index] = node;
        for (int i = 0; i < k; ++i) out[index].child[i] = encode(kids[static_cast<size_t>(i)]);
        return index;
    }
};

}  // namespace

PrimRef make_prim_ref(const Bounds3& b, uint32_t id) {
    PrimRef r;
    for (int a = 0; a < 3; ++a) {
        r.lo[a] = float_lower(b.lo[a]);
        r.hi[a] = float_upper(b.hi[a]);
    }
    r.id = id;
    return r;
}

Bvh build_bvh(std::span<const Bounds3> prim_bounds, const BvhBuildSettings& settings) {
    HugePageVector<PrimRef> refs;
    refs.reserve(prim_bounds.size());
    Bounds3 exact;
    for (size_t i = 0; i < prim_bounds.size(); ++i) {
        refs.push_back(make_prim_ref(prim_bounds[i], static_cast<uint32_t>(i)));
        exact.extend(prim_bounds[i]);
    }
    return build_bvh(std::move(refs), exact, settings);
}

Bvh build_bvh(HugePageVector<PrimRef> refs, const Bounds3& exact_bounds,
              const BvhBuildSettings& settings) {
    Bvh bvh;
    if (refs.empty()) return bvh;
    Builder b;
    b.refs = refs.data();
    b.settings = settings;
    // Subtrees near the root go to other threads: log2 of the cores, at most 3 levels.
    const unsigned cores = !have_threads()    ? 1u
                           : settings.threads ? settings.threads
                                              : hardware_threads();
    b.spawn_depth = cores >= 8 ? 3 : cores >= 4 ? 2 : cores >= 2 ? 1 : 0;
    // A binary tree over n primitives in leaves of about max_leaf_size / 1.2 (what the SAH
    // makes of meshes) has twice as many nodes as leaves: reserved once, so the array does not
    // double at the end.
    const size_t leaf_size = static_cast<size_t>(std::max(settings.max_leaf_size, 1));
    b.nodes.reserve(2 * refs.size() * 6 / (5 * leaf_size) + 16);
    Box4 box, cbox;
    const uint32_t n = static_cast<uint32_t>(refs.size());
    b.measure(0, n, &box, &cbox);
    const uint32_t root = b.build(0, n, 0, box, cbox);
    bvh.root_bounds = exact_bounds;
    // The order the leaves read is all the collapse needs of the references: freed first.
    bvh.indices.resize(n);
    for (uint32_t i = 0; i < n; ++i) bvh.indices[i] = refs[i].id;
    HugePageVector<PrimRef>().swap(refs);
    // Each 4-wide node takes up to three binary nodes (with their children); the exact count
    // is known only after the collapse, so the estimate is trimmed if it was well over.
    bvh.nodes.reserve(b.nodes.size() / 5 + 16);
    Collapser<Bvh4Node, 4>{b.nodes, bvh.nodes}.emit(root);
    if (settings.wide) {
        bvh.nodes8.reserve(bvh.nodes.size() / 2 + 16);
        Collapser<Bvh8Node, 8>{b.nodes, bvh.nodes8}.emit(root);
        if (bvh.nodes8.capacity() > bvh.nodes8.size() + bvh.nodes8.size() / 8)
            bvh.nodes8.shrink_to_fit();
    }
    HugePageVector<Node2>().swap(b.nodes);
    if (bvh.nodes.capacity() > bvh.nodes.size() + bvh.nodes.size() / 8) bvh.nodes.shrink_to_fit();
    return bvh;
}

}  // namespace rt
