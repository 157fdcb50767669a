// What rayview keeps between runs: the window's size, the UI scale and the recent files, in
// $XDG_CONFIG_HOME/rayview/rayview.conf (~/.config/rayview/rayview.conf without it), one
// "key = value" a line. Unknown keys and bad values are ignored, so an old or hand-edited
// file never stops the viewer.
#pragma once

#include <string>
#include <vector>

namespace rt::view {

struct UserConfig {
    int window_w = 1280, window_h = 720;
    float ui_scale = 1;
    std::vector<std::string> recent;  // most recent first, at most kMaxRecent
    static constexpr size_t kMaxRecent = 8;
};

/// The config file's path ("" when neither XDG_CONFIG_HOME nor HOME is set).
std::string config_path();
/// Reads `path`; the defaults for what is missing (all of it when the file is absent). A file
/// that is there but cannot be read (a FIFO, a directory, no permission) gives the defaults
/// too, with the reason in *problem.
UserConfig read_config(const std::string& path, std::string* problem = nullptr);
/// Writes `path` (its folder made if needed) atomically; false, and nothing written, on failure.
bool write_config(const std::string& path, const UserConfig& config);

}  // namespace rt::view
