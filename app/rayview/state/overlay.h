// What the viewer draws over the preview, as world-space line segments: light markers, BVH node
// boxes and the scene graph's group boxes. Geometry only, no GL: the preview draws the lines.
#pragma once

#include <vector>

#include "rt/render/inspect.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"

namespace rt::view {

/// One end of an overlay line segment.
struct LineVertex {
    float position[3];
    float color[3];
};

/// The scene's bounds grown by what the overlay draws around it (light markers and arrows).
Bounds3 view_bounds(const RenderScene& scene);

/// Which light markers the overlay draws: none, or a small cross at each light with a position
/// (three great circles at the radius for sphere lights), and the direction (a spot's cut-off
/// cone, a directional light's arrows towards the scene's centre) of light `selected` only, or of
/// every light with `directions`. Drawn for all, the cones and arrows cross most scenes.
struct LightMarkers {
    bool show = true;
    int selected = -1;
    bool directions = false;
};

/// Overlay geometry: the light markers and, up to `bvh_depth` levels, the boxes of the
/// instances and of their BVH nodes (the flattened groups' boxes) and of their CSG nodes, in
/// world space.
std::vector<LineVertex> overlay_lines(const RenderScene& scene, const LightMarkers& lights,
                                      int bvh_depth);

/// The 12 edges of a world-space box (the selection's), in one colour.
std::vector<LineVertex> box_lines(const Bounds3& box, const Vec3& colour);

/// The boxes of the scene graph's groups (#group_begin blocks, V3 #static_affine and
/// #dynamic_affine transforms and lists, included files, each instance of an include on its own)
/// and of its CSG nodes (blue; union: the union of the operands' boxes, intersection: their
/// intersection, difference: A's, spec §13.8) and their operands, world-aligned, down to nesting
/// level `depth` (1: the top-level groups), in colours that fade with depth. Not the BVH: the
/// structure the file describes.
std::vector<LineVertex> group_box_lines(const SceneDesc& desc, int depth);

/// The colours of a ray tree's lines (also the panel's legend).
struct InspectColours {
    static constexpr float camera[3] = {1.0f, 1.0f, 1.0f};
    static constexpr float reflected[3] = {0.3f, 0.8f, 1.0f};
    static constexpr float refracted[3] = {0.3f, 1.0f, 0.5f};
    static constexpr float shadow_lit[3] = {1.0f, 0.9f, 0.2f};      // reaches the light
    static constexpr float shadow_blocked[3] = {1.0f, 0.2f, 0.2f};  // up to the blocker
    static constexpr float normal[3] = {0.7f, 0.4f, 1.0f};
    static constexpr float hovered[3] = {1.0f, 0.5f, 0.0f};
};

/// A pixel's ray tree (rt/render/inspect.h) as world-space segments: each ray from its origin to
/// its hit (a miss: `miss_length` along it), each shadow ray to its light (when blocked, to its
/// blocker, with a cross there), and at each hit the normal N as a tick `tick` long. The
/// `hovered` ray (index into tree.rays) and its shadow rays in the hovered colour.
std::vector<LineVertex> inspect_lines(const PixelTree& tree, double tick, double miss_length,
                                      int hovered = -1);

}  // namespace rt::view
