// Where the programs find their data (the preview's shaders, the sample scenes): beside the
// executable, never through the source tree, so an installed or moved copy works from any
// directory with the source gone.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rtapp {

/// The directory of the running executable (from /proc/self/exe); empty when it cannot be read.
std::filesystem::path executable_dir();

/// The places find_data_dir() looks in, in order: $RAYTRACER_DATA_DIR when set, then the
/// executable's directory joined with RT_DATA_RELATIVE (`../share/raytracer` once installed,
/// which the build tree mirrors with links to the sources).
std::vector<std::filesystem::path> data_dir_candidates();

/// The first candidate that holds `entry` (e.g. "shaders/preview.vert"). Throws
/// std::runtime_error naming every place it looked in.
std::filesystem::path find_data_dir(const std::string& entry);

}  // namespace rtapp
