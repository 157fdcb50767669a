// raytrace --frames: an animation rendered frame by frame from one compiled scene.
#pragma once

#include "options.h"
#include "report.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"

namespace raytrace {

/// Renders frame k = 0 .. N-1 at --start + k / --fps (animate() moves the joints, a new plan is
/// made), writes each to its name from -o's pattern atomically, shows a progress bar over the
/// frames and prints a summary; with --video, ffmpeg encodes them (a warning without ffmpeg).
/// Each frame's image is the one `raytrace --at t` gives. Returns the exit status.
int render_sequence(const Options& opt, const rt::SceneDesc& desc, rt::RenderScene& scene,
                    Timings t);

}  // namespace raytrace
