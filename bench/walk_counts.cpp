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
    // The leaf test of walks.h's triangle sets, without the tie rule (the counts do not need it).
    auto leaf = [&](uint32_t first, uint32_t n, double& best) {
        for (uint32_t k = 0; k < n; k += 4) {
            ++count.blocks;
            float tt[4];
            int m = tri4_hits(set.tri4[first + k / 4], tri, n - k >= 4 ? 15 : (1 << (n - k)) - 1,
                              0.0f, float_upper(best), tt);
            for (; m; m &= m - 1) {
                const double th = static_cast<double>(tt[__builtin_ctz(static_cast<unsigned>(m))]);
                if (th > 0.0 && th < best) {
                    if (any_hit) return true;
                    best = th;
                }
            }
        }
        return false;
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
