#include "state/trace_session.h"

#include <cstdio>

#include "rt/render/plan.h"
#include "rt/util/stopwatch.h"

namespace rt::view {

void TraceSession::set_size(int w, int h) {
    if (w == m_w && h == m_h) return;
    m_w = w;
    m_h = h;
    m_edited = true;  // a restart, but not an edit of the view
}

bool TraceSession::due(int scene_id) {
    // A new scene restarts at once: the preview draws with the plan of the scene it shows.
    const bool trace_caught_up =
        first_pass_ms >= 0 || seconds_since(m_change_time) > 0.1 || scene_id != m_traced_id;
    if (m_edited && !m_input_pending) {
        m_input_pending = true;
        m_input_time = Clock::now();
    }
    return m_edited && trace_caught_up;
}

void TraceSession::restart(const RenderScene& scene, const RenderSettings& render, int target_spp,
                           float target_error, int scene_id, bool reference) {
    tracer.restart(scene, render, target_spp, target_error, reference);
    m_traced_id = scene_id;
    explained.clear();
    for (const PlanReason& r : tracer.plan().reasons) explained.push_back(reason_line(r));
    if (print_left_out)
        for (const std::string& l : explained)
            if (l.rfind("left out", 0) == 0) std::printf("rayview: %s\n", l.c_str());
    print_left_out = false;
    m_edited = false;
    m_input_pending = false;
    m_served_input_time = m_input_time;
    m_change_time = Clock::now();
    first_pass_ms = -1;
    first_full_ms = -1;
}

bool TraceSession::take_image() {
    if (!tracer.take_image(&last_trace, &last_spp)) return false;
    // From the edit, not the (possibly deferred) restart.
    const double ms =
        std::chrono::duration<double, std::milli>(Clock::now() - m_served_input_time).count();
    if (first_pass_ms < 0) {
        first_pass_ms = ms;
        first_pass_samples.push_back(first_pass_ms);
    }
    if (first_full_ms < 0 && last_spp >= 1) {
        first_full_ms = ms;
        first_full_samples.push_back(first_full_ms);
    }
    return true;
}

// Also without a restart: with the trace pane hidden (the preview alone) nothing restarts.
bool TraceSession::moving() const {
    return seconds_since(m_change_time) < 0.25 || seconds_since(m_edit_time) < 0.25;
}

double TraceSession::seconds_since_edit() const { return seconds_since(m_edit_time); }

}  // namespace rt::view
