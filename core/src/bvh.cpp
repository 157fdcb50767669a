#include "rt/bvh.h"

#include <algorithm>
#include <numeric>

namespace rt {

namespace {

struct Builder {
    std::span<const Bounds3> prims;
    std::vector<Vec3> centroids;
    Bvh bvh;
    BvhBuildSettings settings;

    // Builds the subtree over indices[begin, end); returns its node index.
    uint32_t build(uint32_t begin, uint32_t end, int depth) {
        const uint32_t index = static_cast<uint32_t>(bvh.nodes.size());
        bvh.nodes.emplace_back();
        Bounds3 box, cbox;
        for (uint32_t i = begin; i < end; ++i) {
            box.extend(prims[bvh.indices[i]]);
            cbox.extend(centroids[bvh.indices[i]]);
        }
        bvh.nodes[index].bounds = box;
        const uint32_t n = end - begin;
        const int axis = cbox.largest_axis();
        const double extent = cbox.hi[axis] - cbox.lo[axis];
        // The traversal stack holds 128 entries; depth stays far below with SAH or median splits.
        if (n <= static_cast<uint32_t>(settings.max_leaf_size) || extent <= 0.0 || depth > 60) {
            make_leaf(index, begin, n);
            return index;
        }

        // Binned SAH (Wald 2007): bins along the centroid extent of the largest axis.
        const int nb = settings.bins;
        std::vector<Bounds3> bin_box(static_cast<size_t>(nb));
        std::vector<uint32_t> bin_count(static_cast<size_t>(nb), 0);
        auto bin_of = [&](uint32_t prim) {
            const int b = static_cast<int>(nb * ((centroids[prim][axis] - cbox.lo[axis]) / extent));
            return std::clamp(b, 0, nb - 1);
        };
        for (uint32_t i = begin; i < end; ++i) {
            const int b = bin_of(bvh.indices[i]);
            bin_box[static_cast<size_t>(b)].extend(prims[bvh.indices[i]]);
            ++bin_count[static_cast<size_t>(b)];
        }
        std::vector<double> right_area(static_cast<size_t>(nb), 0.0);
        std::vector<uint32_t> right_count(static_cast<size_t>(nb), 0);
        Bounds3 acc;
        uint32_t cnt = 0;
        for (int b = nb - 1; b > 0; --b) {
            acc.extend(bin_box[static_cast<size_t>(b)]);
            cnt += bin_count[static_cast<size_t>(b)];
            right_area[static_cast<size_t>(b)] = acc.surface_area();
            right_count[static_cast<size_t>(b)] = cnt;
        }
        double best_cost = kInf;
        int best_split = -1;
        acc = Bounds3{};
        cnt = 0;
        for (int b = 1; b < nb; ++b) {
            acc.extend(bin_box[static_cast<size_t>(b - 1)]);
            cnt += bin_count[static_cast<size_t>(b - 1)];
            if (cnt == 0 || right_count[static_cast<size_t>(b)] == 0) continue;
            const double cost = acc.surface_area() * cnt + right_area[static_cast<size_t>(b)] *
                                                               right_count[static_cast<size_t>(b)];
            if (cost < best_cost) best_cost = cost, best_split = b;
        }
        const double leaf_cost = box.surface_area() * n;
        const double traversal_cost = box.surface_area();  // relative to one intersection
        uint32_t mid = begin;
        if (best_split > 0 && (best_cost + traversal_cost < leaf_cost ||
                               n > static_cast<uint32_t>(settings.max_leaf_size) * 4)) {
            mid = static_cast<uint32_t>(
                std::partition(bvh.indices.begin() + begin, bvh.indices.begin() + end,
                               [&](uint32_t p) { return bin_of(p) < best_split; }) -
                bvh.indices.begin());
        }
        if (mid == begin || mid == end) {
            if (n <= 255 && best_split > 0 && !(best_cost + traversal_cost < leaf_cost)) {
                make_leaf(index, begin, n);
                return index;
            }
            // Fall back to a median split so leaves stay small.
            mid = begin + n / 2;
            std::nth_element(
                bvh.indices.begin() + begin, bvh.indices.begin() + mid, bvh.indices.begin() + end,
                [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
        }
        build(begin, mid, depth + 1);
        const uint32_t right = build(mid, end, depth + 1);
        bvh.nodes[index].offset = right;
        bvh.nodes[index].count = 0;
        bvh.nodes[index].axis = static_cast<uint8_t>(axis);
        return index;
    }

    void make_leaf(uint32_t index, uint32_t begin, uint32_t n) {
        // Leaf counts fit 16 bits; a larger set of coincident primitives is split in halves.
        if (n > 0xFFFF) {
            const uint32_t mid = begin + n / 2;
            build_children_of(index, begin, mid, begin + n);
            return;
        }
        bvh.nodes[index].offset = begin;
        bvh.nodes[index].count = static_cast<uint16_t>(n);
    }

    void build_children_of(uint32_t index, uint32_t begin, uint32_t mid, uint32_t end) {
        build(begin, mid, 0);
        const uint32_t right = build(mid, end, 0);
        bvh.nodes[index].offset = right;
        bvh.nodes[index].count = 0;
    }
};

}  // namespace

Bvh build_bvh(std::span<const Bounds3> prim_bounds, const BvhBuildSettings& settings) {
    Builder b;
    b.prims = prim_bounds;
    b.settings = settings;
    if (prim_bounds.empty()) return {};
    b.centroids.reserve(prim_bounds.size());
    for (const Bounds3& pb : prim_bounds) b.centroids.push_back(pb.centre());
    b.bvh.indices.resize(prim_bounds.size());
    std::iota(b.bvh.indices.begin(), b.bvh.indices.end(), 0u);
    b.bvh.nodes.reserve(prim_bounds.size() * 2);
    b.build(0, static_cast<uint32_t>(prim_bounds.size()), 0);
    return std::move(b.bvh);
}

}  // namespace rt
