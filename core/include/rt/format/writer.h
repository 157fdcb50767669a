// SceneDesc -> .ray text: the top-level file of a description (camera, background, ambient,
// lights, textures, materials, vertices, includes and the scene graph) in its dialect, with
// every number at full precision, so parsing the text again gives the same description. The
// viewer saves edited cameras and lights with it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "rt/scene/scene_desc.h"

namespace rt {

/// The top-level file of `desc` as .ray text in its dialect. Paths of textures and included files
/// are written as resolved (absolute when `absolute_paths`), so the text can be saved anywhere.
/// V0/V1: joints are written as groups with their frame-0 matrices; a V3-only feature (a V3-only
/// shape kind, CSG node, sphere light, a light with an ambient colour or diffuse != specular,
/// #shader) is a SceneError naming it. V3 (spec §13): the global, local and shapes parts, key files
/// and #dynamic_affine NAME for joints; every list the parser folds (scene_desc.h) is written so
/// that it folds back the same way, an empty CSG operand as an empty #shape_list_begin/_end.
std::string write_scene(const SceneDesc& desc, bool absolute_paths = true);
/// The same text for saving at `saved_path`: texture and included file paths relative to its
/// directory (where the parser looks first), so the saved scene and its files can move together.
std::string write_scene_for(const SceneDesc& desc, const std::string& saved_path);

/// One #material directive as the writer writes it in `dialect` (no newline).
std::string write_material(const MaterialDesc& m, Dialect dialect);
/// `text`, the contents of the .ray file `file`, with the #material directives at the given
/// locations (MaterialDesc::loc: line and column from 1, in bytes) replaced by the given text;
/// every other byte, comments included, stays. A location where the file no longer has a
/// #material, or one whose numbers and !name! string have anything else between them, is a
/// SceneError at that location (the file changed since it was read): nothing is replaced.
std::string replace_materials(const std::string& text, const std::string& file,
                              std::vector<std::pair<SourceLoc, std::string>> edits);

}  // namespace rt
