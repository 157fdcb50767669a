// What the viewer writes: the scene as edited (its file and, when asked, the materials of its
// included files), the trace as shown, and images and animations rendered in the background.
// Functions over the viewer's state; no GL.
#pragma once

#include <string>
#include <vector>

#include "rt/image/image.h"
#include "state/viewer.h"

namespace rt::view {

/// The description with the viewer's camera, lights and materials, as a .ray file. The
/// materials of included files are written into those files only with `included_too`:
/// each edited #material directive replaced in place, every other byte kept; every text is
/// made before any file is written, so an error (a file changed since it was read) writes
/// nothing. Throws.
void save_scene(const ViewerState& v, const std::string& path, bool included_too = false);
/// The included files (as resolved) whose materials differ from the file's.
std::vector<std::string> edited_included_files(const ViewerState& v);
/// The latest traced image: 8-bit formats with the exposure and tonemap shown, PFM linear.
/// Throws.
void save_trace(const ViewerState& v, const std::string& path);
/// The latest trace as shown: exposure and tonemap applied.
Image displayed_trace(const ViewerState& v);
/// Renders the scene as edited at `width` x `height` and `spp` in the background
/// (jobs.image) and writes it to `path` with the display's exposure and tonemap (PFM
/// linear); the panel says when it is done. The interactive trace goes on.
void render_image(ViewerState& v, const std::string& path, int width, int height, int spp);
/// The animation rendered as render_image() renders an image: `frames` frames from time 0
/// at the timeline's fps, interpolation and rotation, to `pattern` (a %d pattern, as
/// raytrace --frames), encoded to `video` too when it is not empty (needs ffmpeg).
void render_animation(ViewerState& v, const std::string& pattern, int frames, int width, int height,
                      int spp, const std::string& video = "");

}  // namespace rt::view
