// Bounding volume hierarchy over boxes and indices. It knows nothing of shapes or of the scene
// format: build_bvh() sees only primitive bounds and returns a 4-wide tree (and on request an
// 8-wide one over the same leaves) plus a primitive order. The walks over it are kernels compiled
// per instruction set (core/src/accel/walk4.h).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "rt/util/huge_pages.h"
#include "rt/util/math.h"

namespace rt {

/// A 4-wide node in single precision, structure-of-arrays so one SSE instruction tests an axis
/// of all four child boxes (116 bytes padded to 128: two cache lines). Boxes are rounded outward
/// from the double-precision bounds, so the float traversal never misses what a double test would
/// hit.
struct alignas(64) Bvh4Node {
    float lo[3][4];  // [axis][child]
    float hi[3][4];
    /// kEmpty, an interior node index, or kLeaf | count << kCountShift | first primitive.
    uint32_t child[4];
    uint32_t num_children;  // children fill slots 0 .. num_children - 1

    static constexpr uint32_t kLeaf = 0x80000000u;
    static constexpr uint32_t kCountShift = 27;
    static constexpr uint32_t kMaxLeafCount = 15;
    static constexpr uint32_t kFirstMask = (1u << kCountShift) - 1;
    static constexpr uint32_t kEmpty = 0xFFFFFFFFu;

    /// A leaf child's code, and its parts back.
    static constexpr uint32_t leaf(uint32_t first, uint32_t count) {
        return kLeaf | count << kCountShift | first;
    }
    static constexpr uint32_t leaf_first(uint32_t child) { return child & kFirstMask; }
    static constexpr uint32_t leaf_count(uint32_t child) { return (child & ~kLeaf) >> kCountShift; }
};

/// An 8-wide node, for the AVX2 and AVX-512 walks: one 256-bit instruction tests an axis of all
/// eight child boxes (228 bytes padded to 256: four cache lines). Child codes as in Bvh4Node.
struct alignas(64) Bvh8Node {
    float lo[3][8];  // [axis][child]
    float hi[3][8];
    uint32_t child[8];
    uint32_t num_children;
};

struct Bvh {
    HugePageVector<Bvh4Node> nodes;  // nodes[0] is the root (when there is any primitive)
    /// With BvhBuildSettings::wide: the same leaves under 8-wide nodes (nodes8[0] the root),
    /// collapsed from the same binary tree.
    HugePageVector<Bvh8Node> nodes8;
    /// Leaves cover ranges of this primitive order. A user may renumber the leaves' ranges
    /// afterwards (the triangle sets point them at their packed blocks) and drop it.
    HugePageVector<uint32_t> indices;
    Bounds3 root_bounds;

    bool empty() const { return nodes.empty(); }
};

/// What a walk did, for the benchmark's counts per ray (bench/walk_counts.cpp). The walks take
/// a counter as their last template argument: the renderer's is NoWalkCount, which does
/// nothing and compiles to nothing; CountWalk adds to a WalkCount.
struct WalkCount {
    uint64_t rays = 0, nodes = 0, leaves = 0, blocks = 0;
};
struct NoWalkCount {
    void node() const {}
    void leaf() const {}
};
struct CountWalk {
    WalkCount* count;
    void node() const { ++count->nodes; }
    void leaf() const { ++count->leaves; }
};

struct BvhBuildSettings {
    int max_leaf_size = 4;
    int bins = 16;
    /// The surface area heuristic counts a leaf's primitives in blocks of this many (a leaf of
    /// 1 to 4 triangles costs one 4-wide test), so it favours full blocks.
    int leaf_block = 1;
    /// Also collapse the tree into 8-wide nodes (Bvh::nodes8).
    bool wide = false;
    /// The threads the build may use (0: hardware_threads()).
    unsigned threads = 0;
};

/// What the builder sorts: a primitive's bounds rounded outward to float, and its index (32
/// bytes, so the splits move the records themselves and read memory in order).
struct alignas(16) PrimRef {
    float lo[3];
    uint32_t id;
    float hi[3];
    uint32_t pad = 0;
};
PrimRef make_prim_ref(const Bounds3& b, uint32_t id);

/// Binned surface-area-heuristic build (Wald 2007) of a binary tree over the given primitive
/// bounds, collapsed into a 4-wide tree.
Bvh build_bvh(std::span<const Bounds3> prim_bounds, const BvhBuildSettings& settings = {});
/// The same from references made by make_prim_ref (ids 0 .. n - 1, any order); exact_bounds,
/// the union of the primitives' bounds in double, becomes root_bounds.
Bvh build_bvh(HugePageVector<PrimRef> refs, const Bounds3& exact_bounds,
              const BvhBuildSettings& settings = {});

}  // namespace rt
