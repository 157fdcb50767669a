// The reference image of progressive rendering: a .pfm file, or `--reference auto`, rendered
// once at --reference-spp samples and cached under $XDG_CACHE_HOME/raytrace (or
// ~/.cache/raytrace), keyed by a hash of every input file, the settings and the renderer's
// version.
#pragma once

#include <optional>

#include "options.h"
#include "rt/image/image.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"

namespace raytrace {

/// The reference of opt.progressive.reference (nullopt when none is asked for). Throws
/// std::runtime_error when it cannot be read or its size is not the image's.
std::optional<rt::Image> load_reference(const Options& opt, const rt::SceneDesc& desc,
                                        const rt::RenderScene& scene);

/// `--reference auto`: the cached image, or a new one rendered and cached (a failure to cache
/// is a warning).
rt::Image auto_reference(const Options& opt, const rt::SceneDesc& desc,
                         const rt::RenderScene& scene);

}  // namespace raytrace
