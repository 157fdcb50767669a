// raytrace --inspect: the ray tree of one pixel sample, printed as text and, with
// --inspect-json, written as JSON (rt/render/inspect.h; docs/inspect.md).
#pragma once

#include "options.h"
#include "rt/compile/compile.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"

namespace raytrace {

/// Prints the tree of --inspect's pixel and sample (the pixel's value last) and writes the
/// JSON file atomically. Returns the exit status.
int run_inspect(const Options& opt, const rt::SceneDesc& desc, const rt::RenderScene& scene,
                const rt::CompileReport& report);

}  // namespace raytrace
