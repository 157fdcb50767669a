// raytrace -o NAME.part: one share of a split render (--tile, --samples, --frame), merged by
// raymerge into the image the whole render gives, bit for bit.
#pragma once

#include <string>

#include "options.h"
#include "report.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"

namespace raytrace {

/// Every setting the image depends on, one line (threads and --no-specialize do not change it):
/// parts merge only when theirs are equal.
std::string settings_line(const Options& opt);

/// Renders the share and writes the part file atomically; prints a summary. Returns the exit
/// status.
int render_part_output(const Options& opt, const rt::SceneDesc& desc, const rt::RenderScene& scene,
                       Timings t);

}  // namespace raytrace
