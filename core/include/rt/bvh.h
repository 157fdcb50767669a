// Bounding volume hierarchy over boxes and indices. It knows nothing of shapes or of the scene
// format: build_bvh() sees only primitive bounds; traversal calls back with primitive indices.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rt/math.h"

namespace rt {

/// Interior nodes keep their left child right after them (depth-first order) and store the
/// right child's index; leaves store a range of `Bvh::indices`.
struct BvhNode {
    Bounds3 bounds;
    uint32_t offset = 0;  // leaf: first index; interior: right child
    uint16_t count = 0;   // leaf: number of primitives; interior: 0
    uint8_t axis = 0;     // interior: split axis
};

struct Bvh {
    std::vector<BvhNode> nodes;
    std::vector<uint32_t> indices;  // primitive order referenced by leaves
    bool empty() const { return nodes.empty(); }
    Bounds3 bounds() const { return nodes.empty() ? Bounds3{} : nodes[0].bounds; }
};

struct BvhBuildSettings {
    int max_leaf_size = 4;
    int bins = 16;
};

/// Binned surface-area-heuristic build over the given primitive bounds.
Bvh build_bvh(std::span<const Bounds3> prim_bounds, const BvhBuildSettings& settings = {});

/// Ordered traversal: children are visited nearest entry first, and a subtree whose box starts
/// beyond `t_max` is skipped. `visit(prim_index, t_max)` tests one primitive and may shrink
/// t_max (closest hit); it returns true to stop the whole walk (any-hit).
template <class Visit>
void traverse(const Bvh& bvh, const Ray& ray, double& t_max, Visit&& visit) {
    if (bvh.nodes.empty()) return;
    const Vec3 inv_d(1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z);
    struct Entry {
        uint32_t node;
        double t;
    };
    Entry stack[128];
    int sp = 0;
    double t_root = 0.0;
    if (!intersect_bounds(bvh.nodes[0].bounds, ray.o, inv_d, t_max, &t_root)) return;
    stack[sp++] = {0, t_root};
    while (sp > 0) {
        const Entry e = stack[--sp];
        if (e.t > t_max) continue;  // farther than the best hit so far
        const BvhNode& node = bvh.nodes[e.node];
        if (node.count > 0) {
            for (uint32_t i = node.offset; i < node.offset + node.count; ++i)
                if (visit(bvh.indices[i], t_max)) return;
            continue;
        }
        const uint32_t l = e.node + 1, r = node.offset;
        double tl = 0.0, tr = 0.0;
        const bool hl = intersect_bounds(bvh.nodes[l].bounds, ray.o, inv_d, t_max, &tl);
        const bool hr = intersect_bounds(bvh.nodes[r].bounds, ray.o, inv_d, t_max, &tr);
        if (hl && hr) {
            // Push the farther child first so the nearer one is visited next.
            if (tl <= tr) {
                stack[sp++] = {r, tr};
                stack[sp++] = {l, tl};
            } else {
                stack[sp++] = {l, tl};
                stack[sp++] = {r, tr};
            }
        } else if (hl) {
            stack[sp++] = {l, tl};
        } else if (hr) {
            stack[sp++] = {r, tr};
        }
    }
}

}  // namespace rt
