// The output files, all or nothing: each is probed before any work is done (a long render must
// not fail at the end), and the text files (report, plot) are staged under temporary names so
// they take their names only once the image is written.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "rt/image/image.h"

namespace raytrace {

/// Creates and removes path.part for each non-empty path: its directory exists and is writable,
/// and the path is no directory. Prints "raytrace: error: cannot write ..." and returns false
/// for the first that fails.
bool probe_outputs(const std::vector<std::string>& paths);

/// A text file to write beside the image: its path and its contents.
using TextFile = std::pair<std::string, std::string>;

/// Writes the texts to path.part, the image (atomically), then renames the texts; on failure
/// removes every temporary file and throws std::runtime_error. Non-finite pixels are written as
/// 0 (spec §9) with a warning naming `scene`.
void write_outputs(const rt::Image& image, const std::string& image_path,
                   const std::vector<TextFile>& texts, const std::string& scene);

}  // namespace raytrace
