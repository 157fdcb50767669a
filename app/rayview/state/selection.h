// What a click picked: the primitive under a pixel of the view and what the panel says about
// it (its shape, material, where it is in the file and the groups above it). No GL.
#pragma once

#include <cstdint>
#include <string>

#include "state/camera_controller.h"
#include "state/loader.h"

namespace rt::view {

/// What a click picked: the primitive under the pixel and what the panel says about it.
struct Selection {
    int instance = -1;  // -1: nothing
    uint32_t prim = 0;
    Bounds3 bounds;                      // world bounds of the primitive (a CSG node's whole tree)
    Vec3 point{0.0};                     // where the ray met it
    std::string shape, material, where;  // "sphere"; "glass (material 3)"; "file:line:col"
    int material_index = -1;             // into RenderScene::materials
    std::string groups;                  // its file and groups: "pawn.ray > group at line 3 > ..."
};

/// The selection of primitive `prim` of instance `instance` of the open scene, met at `point`
/// (nothing, instance -1, when there is no such primitive).
Selection selection_of(const LoadedScene& scene, int instance, uint32_t prim, const Vec3& point);

/// What `camera` sees of `scene` at (x, y) of a `w` x `h` image, each in [0, 1) from the top
/// left corner; nothing (instance -1) where the ray leaves the scene.
Selection pick_at(const LoadedScene& scene, const OrbitCamera& camera, int w, int h, double x,
                  double y);

}  // namespace rt::view
