#define RT_ISA_AVX2 1
#include "walk_counts.h"

#include "accel/triangle_kernel.h"
#include "accel/walk4.h"
#include "accel/walk8.h"

RT_ISA_BEGIN

void count_walk(const GeometrySet& set, const Ray& ray, double t_max, bool any_hit, int width,
                WalkCount& count) {
    ++count.rays;
    const TriRay tri({ray.o - set.tri_origin, ray.d});
    // walks.h's leaf test of a triangle set, without its tie rule (the counts do not need it).
    auto leaf = [&](uint32_t first, uint32_t n, double& best) {
        const uint32_t end = first + (n + 3) / 4;  // the leaf's blocks: [first, end)
        count.blocks += end - first;
        return leaf_block_hits(set.tri4.data(), first, n, tri, 0.0f, best,
                               [&](uint32_t b, int, double t) {
                                   if (!(t > 0.0 && t < best)) return false;
                                   best = t;
                                   if (any_hit) count.blocks -= end - 1 - b;  // not tested
                                   return any_hit;
                               });
    };
    const BoxRay box(ray);
    double best = t_max;
    const CountWalk counter{&count};
    if (width == 8 && !box.any_parallel && !set.bvh.nodes8.empty()) {
        if (any_hit)
            traverse_leaves8_impl<false>(set.bvh, BoxRay8(box), best, leaf, counter);
        else
            traverse_leaves8_impl<true>(set.bvh, BoxRay8(box), best, leaf, counter);
    } else if (box.any_parallel) {
        if (any_hit)
            traverse_leaves_impl<false, false>(set.bvh, box, best, leaf, counter);
        else
            traverse_leaves_impl<true, false>(set.bvh, box, best, leaf, counter);
    } else {
        if (any_hit)
            traverse_leaves_impl<false, true>(set.bvh, box, best, leaf, counter);
        else
            traverse_leaves_impl<true, true>(set.bvh, box, best, leaf, counter);
    }
}

RT_ISA_END
