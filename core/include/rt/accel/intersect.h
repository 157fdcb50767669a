// Ray queries on a RenderScene: nearest hit, shadow transmittance (every surface on the segment
// multiplies by its transparency, spec §7.2), and the surface description at a hit. The BVH path
// and the brute-force path give the same answers; the latter stays for tests.
#pragma once

#include "rt/render_scene.h"

namespace rt {

struct Hit {
    double t = kInf;
    int instance = -1;
    uint32_t prim = 0;
    int part = 0;   // the shape's surface piece (ShapeHits::part)
    int leaf = -1;  // a CSG primitive's hit: the leaf hit (GeometrySet::csg.leaves), whose
                    // shape, part, material and transform interaction() uses
};

/// What shading needs at a hit, in world space: the surface point (rt/shapes/shapes.h) and its
/// material.
struct SurfaceInteraction : SurfacePoint {
    int material = 0;
};

/// Nearest hit with t in (t.lo, t.hi). Returns false when the ray escapes. This and occluded(),
/// transmittance() and interaction() take the generic walk, which serves any scene; the
/// overloads that take a RenderPlan (rt/render/plan.h) take the walk that fits the scene.
bool intersect(const RenderScene& scene, const Ray& ray, Interval t, Hit* hit);

/// The nearest hit by testing every primitive of every instance.
bool intersect_brute_force(const RenderScene& scene, const Ray& ray, Interval t, Hit* hit);

/// Any hit with t in (0, t_max): the shadow query of opaque scenes and of the benchmark.
bool occluded(const RenderScene& scene, const Ray& ray, double t_max);

/// Every hit of one primitive of a set, for a ray in the set's frame (the benchmark uses it to
/// give Embree the same analytic shapes); a CSG primitive: its nearest valid hit.
ShapeHits intersect_primitive(const GeometrySet& set, uint32_t prim, const Ray& ray_set,
                              Interval t);

/// Product of the transparencies T of every surface crossing on (0, t_max); zero as soon as an
/// opaque surface is met (spec §7.2). A closed transparent object counts twice. A CSG node's
/// crossings count where the node keeps the surface (spec §13.8), with the leaf's T.
Vec3 transmittance(const RenderScene& scene, const Ray& ray, double t_max);

SurfaceInteraction interaction(const RenderScene& scene, const Ray& ray, const Hit& hit,
                               bool uv = true);

/// A ray leaving the surface point toward `dir`: the origin is pushed off along n_geometric by
/// the point's error bound so the new ray cannot hit the same surface (pbrt's OffsetRayOrigin).
Ray spawn_ray(const SurfaceInteraction& si, const Vec3& dir);
/// A point moved off the surface to the side of `dir` (used for shadow rays toward a point).
Vec3 offset_origin(const SurfaceInteraction& si, const Vec3& dir);

}  // namespace rt
