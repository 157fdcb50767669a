// The progressive trace of the open scene: the tracer, its latest image, what its plan left
// out, the time from an edit to its first passes, and the restart policy's state (an edit
// pending, when the last restart was). No GL.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "rt/image/image.h"
#include "rt/render/render.h"
#include "rt/render_scene.h"
#include "state/tracer.h"

namespace rt::view {

struct TraceSession {
    using Clock = std::chrono::steady_clock;

    TraceSession() = default;
    ~TraceSession() { tracer.stop(); }
    TraceSession(const TraceSession&) = delete;
    TraceSession& operator=(const TraceSession&) = delete;

    Tracer tracer;
    Image last_trace;
    int last_spp = 0;                    // its samples per pixel (0: the coarse pass)
    std::vector<std::string> explained;  // the running trace's plan.reasons
    double first_pass_ms =
        -1;  // edit -> first traced image (the coarse pass) on screen; -1: waiting
    double first_full_ms = -1;  // edit -> first full-resolution pass on screen; -1: waiting
    std::vector<double> first_pass_samples;  // every first_pass_ms, for the --frames summary
    std::vector<double> first_full_samples;  // every first_full_ms
    /// Print the features the renderer leaves out at the next restart (for --frames runs).
    bool print_left_out = false;

    /// Something the trace shows changed: the next due() is true once the policy allows.
    void mark_edited() {
        m_edited = true;
        m_edit_time = Clock::now();
    }
    bool edit_pending() const { return m_edited; }
    /// The trace's size in pixels; a change is an edit.
    void set_size(int w, int h);
    int width() const { return m_w; }
    int height() const { return m_h; }
    /// The restart policy: with an edit pending, due once the running trace's first pass is on
    /// screen or 100 ms after the last restart, and at once for a new scene (`scene_id`, the
    /// LoadedScene::id to trace).
    bool due(int scene_id);
    /// Restarts the tracer on a copy of `scene` (with the edits applied) and starts the edit's
    /// timings; `reference`: raytrace's image (Tracer::restart).
    void restart(const RenderScene& scene, const RenderSettings& render, int target_spp,
                 float target_error, int scene_id, bool reference = false);
    /// The scene the trace renders, when it was started on LoadedScene `scene_id` (else null).
    const RenderScene* traced(int scene_id) const {
        return scene_id == m_traced_id ? &tracer.scene() : nullptr;
    }
    /// Takes the trace's latest image into `last_trace` (and its samples per pixel into
    /// `last_spp`); false when there is none new.
    bool take_image();
    /// Less than a quarter second since the last restart or edit: the view is moving.
    bool moving() const;
    /// Seconds since the last edit (mark_edited(); a change of size is none): once the view is
    /// still, the trace pane refines at full resolution.
    double seconds_since_edit() const;

private:
    bool m_edited = true;
    int m_w = 0, m_h = 0;
    int m_traced_id = -1;                                  // LoadedScene::id the trace started on
    bool m_input_pending = false;                          // an edit waits for the restart policy
    Clock::time_point m_input_time = Clock::now();         // the first edit since the restart
    Clock::time_point m_served_input_time = m_input_time;  // the edit the running trace answers
    Clock::time_point m_change_time{};                     // the last restart
    Clock::time_point m_edit_time = Clock::now();          // the last mark_edited()
};

}  // namespace rt::view
