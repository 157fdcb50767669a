// Description -> render representation: compile_scene() resolves indices, flattens groups,
// instances sets and builds the BVHs; what it did and how long the builds took come back beside
// the scene, not inside it.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"

namespace rt {

/// What compile_scene() made of a description.
struct CompileReport {
    size_t files = 0;
    size_t prims_by_kind[kShapeKinds] = {};  // after instancing
    size_t unique_prims = 0;                 // before instancing
    size_t instances = 0;
    size_t lights = 0, materials = 0, textures = 0;
    size_t skipped_shapes = 0;  // degenerate shapes the parser skipped
    double build_seconds = 0;   // BVH builds (included in compile_scene's time)
    /// Asked for before compile_scene (kept by it): where each primitive was read, for tools
    /// that point at a directive (the viewer's picking). prim_locs[set][prim] is the shape's
    /// directive, a CSG node's #shape_union/_intersection/_difference.
    bool record_locations = false;
    std::vector<std::vector<SourceLoc>> prim_locs;
    std::vector<std::string> material_names;  // [material]: its !name!, "" for none
};

/// A compile's progress, for a thread that shows it: units of work done of the total (three per
/// shape of the description: its bounds, its place in its set's BVH, its packing), and a flag
/// that stops the compile at its next check between those steps with a SceneError ("loading
/// cancelled").
struct CompileProgress {
    std::atomic<uint64_t> total{0};
    std::atomic<uint64_t> done{0};
    const std::atomic<bool>* cancel = nullptr;
};

/// SceneDesc -> RenderScene; `report`, when given, receives the counts and the BVH build time
/// (and with record_locations the primitives' locations). The joints hold their values at
/// `time` (spec §14.7; none: key 0 as read); a joint singular there is left out with a warning
/// into `diag`. The loops over primitives and the BVH builds use up to `threads` threads (0:
/// hardware_threads()); the scene does not depend on it. `progress`, when given, is updated as
/// the compile goes (and may cancel it).
RenderScene compile_scene(const SceneDesc& desc, CompileReport* report = nullptr,
                          const std::optional<SceneTime>& time = std::nullopt,
                          Diagnostics* diag = nullptr, unsigned threads = 0,
                          CompileProgress* progress = nullptr);

/// compile_scene() for a caller that needs only the description's files, settings, lights and
/// tracks afterwards (raytrace's still images): the shapes of each group that holds only
/// triangles, and each file's vertices, are freed from `desc` as soon as their set has what it
/// needs of them, so a large mesh is not held twice. Nothing is freed that a later set reads (a
/// file instanced inside a CSG tree and what it instances), nor anything when `desc` has
/// animation tracks (animate() may compile again) or `report` records locations. The scene is
/// the one compile_scene() makes.
RenderScene compile_scene_releasing(SceneDesc& desc, CompileReport* report = nullptr,
                                    const std::optional<SceneTime>& time = std::nullopt,
                                    Diagnostics* diag = nullptr, unsigned threads = 0);

/// Moves the joints of `scene`, compiled from `desc`, to `time`: the instances under joints get
/// their new transforms, the world bounds and the top-level BVH are made again, and nothing else
/// is touched (unless a joint lies under a CSG node: then the scene is compiled again, and its
/// camera, lights, materials, background and ambient are kept). With those as `desc` has them,
/// the result renders exactly as compile_scene(desc, nullptr, time). Make a new render plan
/// after.
void animate(RenderScene& scene, const SceneDesc& desc, const std::optional<SceneTime>& time,
             Diagnostics* diag = nullptr);

/// How compile_scene() builds the BVH of a set of this layout: one analytic shape per leaf (each
/// culled by its own box); triangles by the SAH in blocks of four, with 8-wide nodes too when
/// the active instruction set has their walk (AVX2 and wider).
BvhBuildSettings set_bvh_settings(SetLayout layout);

/// A light and the camera of the description as the renderer uses them (directions made unit
/// for lights).
Light compile_light(const LightDesc& desc);
CameraPose compile_camera(const CameraDesc& desc);
/// Where material k of the compiled scene comes from: its file in SceneDesc::files and its index
/// there (file -1: the built-in V0 default, last), and that file's textures in
/// RenderScene::textures (a material may use only its own file's).
struct MaterialOrigin {
    int file = -1, index = -1;
    int first_texture = 0, textures = 0;
};
/// The scene's materials in RenderScene::materials' order, the one compile_scene() makes: each
/// file's in file order, then the V0 default. The descriptions, and where each comes from.
std::vector<MaterialDesc> material_descs(const SceneDesc& desc);
std::vector<MaterialOrigin> material_origins(const SceneDesc& desc);
/// A material as the renderer uses it: its terms, and its texture (the file's index) made the
/// scene's by `origin` (-1, none, when its file has no such texture).
Material compile_material(const MaterialDesc& desc, const MaterialOrigin& origin);

}  // namespace rt
