// SceneDesc -> .ray text: the top-level file of a description (camera, background, ambient,
// lights, textures, materials, vertices, includes and the scene graph) in its dialect, with
// every number at full precision, so parsing the text again gives the same description. The
// viewer saves edited cameras and lights with it.
#pragma once

#include <string>

#include "rt/scene/scene_desc.h"

namespace rt {

/// The top-level file of `desc` as .ray text. Paths of textures and included files are written
/// as resolved (absolute when `absolute_paths`), so the text can be saved anywhere. Joints are
/// written as groups with their frame-0 matrices.
std::string write_scene(const SceneDesc& desc, bool absolute_paths = true);

}  // namespace rt
