// rayview's command line: its own options (--frames, --screenshot, --script, --layout, --size,
// --panel, --compare) and raytrace's render flags, which become the viewer's initial settings. No
// GL here (the tests parse command lines without a display).
#pragma once

#include <string>
#include <vector>

#include "render_options.h"
#include "state/viewer.h"

namespace rt::view {

/// The most frames a --frames run or a script runs (a script's frame numbers are at most this
/// too): about half an hour at 60 frames a second, so a typo never runs for days.
constexpr int kMaxFrames = 100000;

struct ScriptLine {
    int frame = 0;
    std::string command;
    std::vector<std::string> args;
};

/// Reads a script; throws std::runtime_error when the file is not a regular file that can be
/// read (a directory, a FIFO) or a frame number is not in 0..kMaxFrames.
std::vector<ScriptLine> read_script(const std::string& path);

/// The viewer's initial render options: raytrace's, but 256 samples per pixel (the trace's
/// target).
rtapp::RenderOptions default_render_options();

struct RunOptions {
    std::string scene;
    int frames = 0;  // > 0: run this many frames, save the window, exit
    std::string screenshot;
    std::vector<ScriptLine> script;
    /// raytrace's render flags (--width, --spp, --depth, --threads, the progressive features,
    /// --missing-textures): the initial settings. --spp is where the trace stops (the panel's
    /// target spp), --width and --height the render's size (the panes keep its aspect).
    rtapp::RenderOptions render = default_render_options();
    bool spp_given = false;
    float target_error = 1e-4f;      // --target-error: the trace stops at this estimated relMSE
    int layout = 0;                  // --layout: ViewSettings::layout
    int window_w = 0, window_h = 0;  // --size, 0: the last run's
    bool panel = true;               // --panel on|off
    /// --compare: an image compared with the reference, rendered at its size from the file's
    /// camera with --spp samples (1 when not given, as raytrace).
    std::string compare;
};

/// The settings the command line asks for (render flags, --layout, --panel), over `settings`
/// (what the viewer starts with).
void apply_run_options(const RunOptions& options, ViewSettings* settings);

/// The script commands (--script), as --help and the F1 overlay list them.
const char* script_commands_help();

/// "WxH" (each 64 to 16384) into *w and *h; false, and both unchanged, otherwise.
bool parse_size(const std::string& text, int* w, int* h);

/// Reads the command line into `out` (the scene defaults to `default_scene`). Returns -1 to run,
/// else the exit code (0 after --help, 2 for a bad option or an unreadable script).
int parse_run_options(int argc, char** argv, const std::string& default_scene, RunOptions* out);

}  // namespace rt::view
