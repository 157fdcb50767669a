// The work of one walk per ray, counted (raybench's table of nodes, leaves and triangle blocks
// visited per ray): the library's own 4-wide and 8-wide walks and triangle kernel, compiled for
// AVX2 in walk_counts.cpp, with a counter in place of the renderer's NoWalkCount.
#pragma once

#include "rt/accel/bvh.h"
#include "rt/render_scene.h"

namespace rt::avx2 {

/// Walks the 4-wide (width 4) or 8-wide (width 8) nodes of a triangle set for a ray in the
/// set's frame: the closest hit in (0, t_max), or with any_hit the first hit; adds to `count`.
void count_walk(const GeometrySet& set, const Ray& ray, double t_max, bool any_hit, int width,
                WalkCount& count);

}  // namespace rt::avx2
