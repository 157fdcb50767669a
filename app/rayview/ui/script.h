// Scripted runs of the viewer, for tests and measurements (the command line that starts them:
// run_options.h): the script runner (its commands on the state: state/commands.h; here the
// window's own: the waits and screenshots), saving the window as an image, and the frame
// statistics a --frames run prints at the end.
//
// A script has one command a line, "FRAME COMMAND ARGS...", run at that frame after it is drawn
// (the list: rayview --help). A command that fails is reported and the run goes on. Frames count
// the frames the script runs in: `wait-spp` holds the count until the trace has converged that
// far, so a test waits for the trace, not for a number of frames that a loaded machine may need.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "state/run_options.h"
#include "state/viewer.h"

namespace rt::view {

/// The whole window as drawn (the current framebuffer), rows flipped to top-first. Throws.
void save_window(int width, int height, const std::string& path);

/// Frame times: the last frame's, and the statistics of a --frames run.
class FrameStats {
public:
    /// Once a frame: returns the time since the previous call (seconds).
    double tick();
    int count() const { return m_count; }
    /// The summary line of a --frames run.
    void print(const ViewerState& v) const;

private:
    std::chrono::steady_clock::time_point m_last = std::chrono::steady_clock::now();
    double m_total_s = 0, m_max_s = 0;
    int m_count = 0;
    std::vector<double> m_ms;  // after start-up
};

/// Runs the script and counts down --frames.
class ScriptRun {
public:
    explicit ScriptRun(const RunOptions& options);
    /// The trace restarted this frame: reports the script commands whose edits it answers.
    void restarted();
    /// After the frame is drawn: runs this frame's commands (run_command; one that fails is
    /// reported and the run goes on); at the last frame saves the --screenshot and sets
    /// `*exit_code` to 1 when anything failed. `preview_drawn`: the preview shows the latest
    /// change (wait-jobs waits for it). Returns true when the run is over.
    bool end_frame(ViewerState& v, int fb_w, int fb_h, bool preview_drawn, int* exit_code);
    /// After the last frame: the frame statistics, for --screenshot runs.
    void print_summary(const FrameStats& stats, const ViewerState& v) const;

private:
    void run(const ScriptLine& l, ViewerState& v, int fb_w, int fb_h);

    std::vector<ScriptLine> m_lines;
    int m_frames_left;
    std::string m_screenshot;
    int m_frame = 0;
    std::vector<std::string> m_causes;  // commands whose edits await a restart
    bool m_failed = false;              // a command failed (reported): the run exits 1
    /// What a wait-spp, wait-jobs or wait-compare holds the script for.
    enum class Wait { None, Spp, Jobs, Compare };
    Wait m_wait = Wait::None;
    int m_wait_spp = 0;
    double m_wait_limit_s = 0;
    std::chrono::steady_clock::time_point m_wait_start;
};

}  // namespace rt::view
