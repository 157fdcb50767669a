#include "rt/accel/bvh.h"

#include <immintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <thread>

namespace rt {

namespace {

// The binary tree the SAH builder makes; collapsed into Bvh4Node afterwards.
struct Node2 {
    Bounds3 bounds;
    uint32_t left = 0, right = 0;   // interior: children
    uint32_t first = 0, count = 0;  // leaf: count > 0
};

constexpr int kMaxBins = 32;
constexpr int kSahDepth = 40;

struct Builder {
    std::span<const Bounds3> prims;
    const std::vector<Vec3>* centroids = nullptr;
    std::vector<uint32_t>* order = nullptr;
    std::vector<Node2> nodes;
    BvhBuildSettings settings;
    int spawn_depth = 0;  // subtrees above this depth are built on their own thread

    const Vec3& centroid(uint32_t prim) const { return (*centroids)[prim]; }

    // Bounds and centroid bounds of order[begin, end).
    void measure(uint32_t begin, uint32_t end, Bounds3* box, Bounds3* cbox) const {
        for (uint32_t i = begin; i < end; ++i) {
            box->extend(prims[(*order)[i]]);
            cbox->extend(centroid((*order)[i]));
        }
    }

    uint32_t leaf(const Bounds3& box, uint32_t begin, uint32_t n, int depth) {
        // Leaves hold at most kMaxLeafCount primitives; larger sets (coincident centroids) are
        // halved in their current order.
        if (n > Bvh4Node::kMaxLeafCount) return split(box, begin, begin + n / 2, begin + n, depth);
        nodes.push_back({box, 0, 0, begin, n});
        return static_cast<uint32_t>(nodes.size() - 1);
    }

    // Splits at mid, measuring both halves.
    uint32_t split(const Bounds3& box, uint32_t begin, uint32_t mid, uint32_t end, int depth) {
        Bounds3 lb, lc, rb, rc;
        measure(begin, mid, &lb, &lc);
        measure(mid, end, &rb, &rc);
        return split(box, begin, mid, end, depth, lb, lc, rb, rc);
    }

    uint32_t split(const Bounds3& box, uint32_t begin, uint32_t mid, uint32_t end, int depth,
                   const Bounds3& lb, const Bounds3& lc, const Bounds3& rb, const Bounds3& rc) {
        const uint32_t index = static_cast<uint32_t>(nodes.size());
        nodes.push_back({box, 0, 0, 0, 0});
        uint32_t l = 0, r = 0;
        if (depth < spawn_depth && end - begin > 50000) {
            // The left subtree on another thread, into its own node array, merged afterwards.
            Builder sub;
            sub.prims = prims;
            sub.centroids = centroids;
            sub.order = order;
            sub.settings = settings;
            sub.spawn_depth = spawn_depth;
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

    uint32_t build(uint32_t begin, uint32_t end, int depth, const Bounds3& box,
                   const Bounds3& cbox) {
        const uint32_t n = end - begin;
        const int axis = cbox.largest_axis();
        const double extent = cbox.hi[axis] - cbox.lo[axis];
        if (n <= static_cast<uint32_t>(settings.max_leaf_size) || !(extent > 0.0))
            return leaf(box, begin, n, depth);
        // Deep in the tree (SAH can peel one primitive at a time off wildly spread sizes), only
        // median splits: each halves the set, so the depth stays below kSahDepth + log2(n) and
        // the traversal stack (bvh.h) cannot overflow.
        if (depth >= kSahDepth) return median(box, begin, end, axis, depth);

        // Binned SAH along the largest centroid axis; each bin keeps its primitives' bounds and
        // centroid bounds, so the children's boxes come from the bins, not another pass.
        const int nb = std::clamp(settings.bins, 2, kMaxBins);
        std::array<Bounds3, kMaxBins> bin_box{}, bin_cbox{};
        std::array<uint32_t, kMaxBins> bin_count{};
        const double scale = nb / extent;
        // A spread so small (subnormal) that the bin scale overflows: binning cannot separate
        // the centroids, and (c - lo) * inf would be NaN cast to int. Median split instead.
        if (!std::isfinite(scale)) return median(box, begin, end, axis, depth);
        auto bin_of = [&](uint32_t prim) {
            const int b = static_cast<int>((centroid(prim)[axis] - cbox.lo[axis]) * scale);
            return std::clamp(b, 0, nb - 1);
        };
        for (uint32_t i = begin; i < end; ++i) {
            const uint32_t prim = (*order)[i];
            const size_t b = static_cast<size_t>(bin_of(prim));
            bin_box[b].extend(prims[prim]);
            bin_cbox[b].extend(centroid(prim));
            ++bin_count[b];
        }
        // A leaf of n primitives costs ceil(n / leaf_block) tests.
        const uint32_t block = static_cast<uint32_t>(std::max(settings.leaf_block, 1));
        auto blocks = [&](uint32_t count) {
            return static_cast<double>((count + block - 1) / block);
        };
        std::array<double, kMaxBins> right_cost{};
        Bounds3 acc;
        uint32_t cnt = 0;
        for (int b = nb - 1; b > 0; --b) {
            acc.extend(bin_box[static_cast<size_t>(b)]);
            cnt += bin_count[static_cast<size_t>(b)];
            right_cost[static_cast<size_t>(b)] = acc.surface_area() * blocks(cnt);
        }
        double best_cost = kInf;
        int best = -1;
        acc = Bounds3{};
        cnt = 0;
        for (int b = 1; b < nb; ++b) {
            acc.extend(bin_box[static_cast<size_t>(b - 1)]);
            cnt += bin_count[static_cast<size_t>(b - 1)];
            if (cnt == 0 || cnt == n) continue;
            const double cost =
                acc.surface_area() * blocks(cnt) + right_cost[static_cast<size_t>(b)];
            if (cost < best_cost) best_cost = cost, best = b;
        }
        // Leaf cost (its tests) * area against traversal (~1 test) plus the children.
        const double leaf_cost = box.surface_area() * blocks(n);
        if (best < 0) return median(box, begin, end, axis, depth);
        if (best_cost + box.surface_area() >= leaf_cost && n <= Bvh4Node::kMaxLeafCount)
            return leaf(box, begin, n, depth);
        const uint32_t mid =
            static_cast<uint32_t>(std::partition(order->begin() + begin, order->begin() + end,
                                                 [&](uint32_t p) { return bin_of(p) < best; }) -
                                  order->begin());
        Bounds3 lb, lc, rb, rc;
        for (int b = 0; b < nb; ++b) {
            const size_t i = static_cast<size_t>(b);
            (b < best ? lb : rb).extend(bin_box[i]);
            (b < best ? lc : rc).extend(bin_cbox[i]);
        }
        return split(box, begin, mid, end, depth, lb, lc, rb, rc);
    }

    uint32_t median(const Bounds3& box, uint32_t begin, uint32_t end, int axis, int depth) {
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(
            order->begin() + begin, order->begin() + mid, order->begin() + end,
            [&](uint32_t a, uint32_t b) { return centroid(a)[axis] < centroid(b)[axis]; });
        return split(box, begin, mid, end, depth);
    }
};

// Collapses the binary tree into 4-wide nodes: each node adopts the grandchildren of its
// largest interior children until it has four.
struct Collapser {
    const std::vector<Node2>& in;
    HugePageVector<Bvh4Node>& out;

    uint32_t encode(uint32_t n2) {
        const Node2& n = in[n2];
        if (n.count > 0) return Bvh4Node::kLeaf | (n.count << Bvh4Node::kCountShift) | n.first;
        return emit(n2);
    }

    uint32_t emit(uint32_t n2) {
        const uint32_t index = static_cast<uint32_t>(out.size());
        out.emplace_back();
        std::array<uint32_t, 4> kids{};
        int k = 0;
        const Node2& root = in[n2];
        if (root.count > 0) {
            kids[k++] = n2;  // a leaf root: one child
        } else {
            kids[k++] = root.left;
            kids[k++] = root.right;
            while (k < 4) {
                // Open the interior child with the largest surface area.
                int best = -1;
                double area = -1;
                for (int i = 0; i < k; ++i) {
                    const Node2& c = in[kids[static_cast<size_t>(i)]];
                    if (c.count == 0 && c.bounds.surface_area() > area)
                        area = c.bounds.surface_area(), best = i;
                }
                if (best < 0) break;
                const Node2& c = in[kids[static_cast<size_t>(best)]];
                kids[static_cast<size_t>(best)] = c.left;
                kids[static_cast<size_t>(k++)] = c.right;
            }
        }
        Bvh4Node node;
        for (int i = 0; i < 4; ++i) {
            for (int a = 0; a < 3; ++a) {
                node.lo[a][i] = INFINITY;  // empty slot: never hit
                node.hi[a][i] = -INFINITY;
            }
            node.child[i] = Bvh4Node::kEmpty;
        }
        for (int i = 0; i < k; ++i) {
            const Node2& c = in[kids[static_cast<size_t>(i)]];
            for (int a = 0; a < 3; ++a) {
                node.lo[a][i] = float_lower(c.bounds.lo[a]);
                node.hi[a][i] = float_upper(c.bounds.hi[a]);
            }
        }
        node.num_children = static_cast<uint32_t>(k);
        out[index] = node;
        for (int i = 0; i < k; ++i) out[index].child[i] = encode(kids[static_cast<size_t>(i)]);
        return index;
    }
};

}  // namespace

Bvh build_bvh(std::span<const Bounds3> prim_bounds, const BvhBuildSettings& settings) {
    Bvh bvh;
    if (prim_bounds.empty()) return bvh;
    std::vector<Vec3> centroids;
    centroids.reserve(prim_bounds.size());
    for (const Bounds3& pb : prim_bounds) centroids.push_back(pb.centre());
    std::vector<uint32_t> order(prim_bounds.size());
    std::iota(order.begin(), order.end(), 0u);
    Builder b;
    b.prims = prim_bounds;
    b.centroids = &centroids;
    b.order = &order;
    b.settings = settings;
    // Subtrees near the root go to other threads: log2 of the cores, at most 3 levels.
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    b.spawn_depth = cores >= 8 ? 3 : cores >= 4 ? 2 : cores >= 2 ? 1 : 0;
    b.nodes.reserve(prim_bounds.size() / 2 + 1);
    Bounds3 box, cbox;
    b.measure(0, static_cast<uint32_t>(prim_bounds.size()), &box, &cbox);
    const uint32_t root = b.build(0, static_cast<uint32_t>(prim_bounds.size()), 0, box, cbox);
    bvh.root_bounds = b.nodes[root].bounds;
    bvh.nodes.reserve(b.nodes.size() / 2 + 1);
    Collapser c{b.nodes, bvh.nodes};
    c.emit(root);
    bvh.indices = std::move(order);
    return bvh;
}

BoxRay::BoxRay(const Ray& r) {
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

}  // namespace rt
