// What compile_scene() and animate() share: the bounds rules and the last step of a compile,
// which turns the rig's placements at some joint values into instances, world bounds and the
// top-level BVH.
#pragma once

#include <cstdint>

#include "rt/render_scene.h"
#include "rt/scene/scene_time.h"

namespace rt::compile_detail {

/// Geometry must stay within +-1e300 in every frame (docs/format.md, "our choices").
bool within_limits(const Bounds3& b);

/// The box of a CSG node from its children's boxes (spec §13.8, informative).
Bounds3 combine_csg_bounds(CsgNodeKind kind, const Bounds3* child, uint32_t count);

/// Tight world bounds of a set placed by world_from_set (the default camera frames them).
Bounds3 tight_world_bounds(const GeometrySet& set, const Mat4& world_from_set);

/// scene.instances, scene.world_bounds and scene.top from scene.rig with the joints at `values`
/// (a placement under a singular joint is left out). Returns the seconds the BVH build took.
/// Throws SceneError at a placement that reaches beyond +-1e300.
double place_instances(RenderScene& scene, const JointValues& values);

}  // namespace rt::compile_detail
