// Text -> SceneDesc. Reads a .ray file and everything it includes (spec §2-§4, §10), reporting
// the first error as a SceneError with file:line:col and warnings through Diagnostics.
#pragma once

#include <optional>
#include <string>

#include "rt/scene/scene_desc.h"
#include "rt/util/error.h"

namespace rt {

struct ParseOptions {
    std::optional<Dialect> dialect;  ///< --dialect: overrides detection (spec §10 step 4)
};

/// Parses a scene file and its includes. Throws SceneError.
SceneDesc parse_scene_file(const std::string& path, Diagnostics& diag,
                           const ParseOptions& options = {});

/// Parses scene text given inline; `name` is used in locations and `base_dir` resolves relative
/// paths (includes, textures). Throws SceneError.
SceneDesc parse_scene_string(const std::string& text, const std::string& name, Diagnostics& diag,
                             const ParseOptions& options = {}, const std::string& base_dir = ".");

}  // namespace rt
