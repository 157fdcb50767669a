// The output files, all or nothing: each is probed before any work is done (a long render must
// not fail at the end), and the text files (report, plot) are staged under temporary names so
// they take their names only once the image is written.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "options.h"
#include "rt/image/exr.h"
#include "rt/image/image.h"
#include "rt/render/render.h"

namespace raytrace {

/// Creates and removes a scratch file beside each non-empty path (rt::create_scratch_file, so
/// no file of the user's is touched): its directory exists and is writable, and the path is no
/// directory, FIFO or device. Prints "raytrace: error: cannot write ..." and returns false
/// for the first that fails.
bool probe_outputs(const std::vector<std::string>& paths);

/// A text file to write beside the image: its path and its contents.
using TextFile = std::pair<std::string, std::string>;

/// What an EXR image holds beside the RGB (the other formats ignore it).
struct ExrOutput {
    bool full_float = false;               // 32-bit float channels, else half
    std::vector<rt::ExrChannel> channels;  // the AOVs
};

/// The EXR output of a finished render of `opt` (its samples in `state`): --exr-float and the
/// --aov channels, the first-hit AOVs traced now along the render's camera rays (rt/render/aov.h;
/// with --progressive, the passes' sample sequence).
ExrOutput exr_output(const Options& opt, const rt::RenderState& state, const rt::RenderScene& scene,
                     const rt::RenderPlan& plan);

/// Writes the texts to scratch files beside them (rt::write_scratch_file), the image
/// (atomically), then renames the texts; on failure
/// removes every temporary file and throws std::runtime_error. Non-finite pixels are written as
/// 0 (spec §9) with a warning naming `scene`. An .exr image takes `exr`'s precision and channels.
void write_outputs(const rt::Image& image, const std::string& image_path,
                   const std::vector<TextFile>& texts, const std::string& scene,
                   const ExrOutput& exr = {});

}  // namespace raytrace
