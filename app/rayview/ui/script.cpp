#define GL_GLEXT_PROTOTYPES
#include "ui/script.h"

#include <GL/gl.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "state/commands.h"

namespace rt::view {

void save_window(int width, int height, const std::string& path) {
    std::vector<unsigned char> px(static_cast<size_t>(width) * height * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, px.data());
    Image shot(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = (static_cast<size_t>(height - 1 - y) * width + x) * 3;
            shot.set(x, y, Vec3(px[i], px[i + 1], px[i + 2]) / 255.0);
        }
    save_image(shot, path);
}

double FrameStats::tick() {
    const auto now = std::chrono::steady_clock::now();
    const double frame_s = std::chrono::duration<double>(now - m_last).count();
    m_last = now;
    if (m_count++ > 0) {
        m_total_s += frame_s;
        m_max_s = std::max(m_max_s, frame_s);
        if (m_count > 3) m_ms.push_back(1000 * frame_s);  // after start-up
    }
    return frame_s;
}

void FrameStats::print(const ViewerState& v) const {
    std::printf(
        "rayview: %d frames, mean %.1f ms, max %.1f ms; first traced pass %.0f ms "
        "after the last change\n",
        m_count, 1000 * m_total_s / (m_count - 1), 1000 * m_max_s, v.trace.first_pass_ms);
    auto quantile = [](std::vector<double> x, double q) {
        std::sort(x.begin(), x.end());
        return x.empty() ? 0.0 : x[static_cast<size_t>(q * static_cast<double>(x.size() - 1))];
    };
    std::printf(
        "rayview: frames after start-up: median %.1f ms, p95 %.1f ms; first "
        "traced pass after a change: median %.0f ms, p95 %.0f ms (%zu changes)\n",
        quantile(m_ms, 0.5), quantile(m_ms, 0.95), quantile(v.trace.first_pass_samples, 0.5),
        quantile(v.trace.first_pass_samples, 0.95), v.trace.first_pass_samples.size());
    std::printf(
        "rayview: first full-resolution pass after a change: median %.0f ms, p95 %.0f ms "
        "(%zu changes)\n",
        quantile(v.trace.first_full_samples, 0.5), quantile(v.trace.first_full_samples, 0.95),
        v.trace.first_full_samples.size());
    const Tracer::Status st = v.trace.tracer.status();
    std::printf("rayview: trace at %d spp, %.2f Mray/s on %d threads\n", st.spp,
                st.rays_per_second / 1e6, resolve_thread_count(v.settings.render.threads));
}

ScriptRun::ScriptRun(const RunOptions& options)
    : m_lines(options.script), m_frames_left(options.frames), m_screenshot(options.screenshot) {}

void ScriptRun::restarted() {
    for (const std::string& cause : m_causes)
        std::printf("rayview: frame %d: %s: trace restarted\n", m_frame, cause.c_str());
    m_causes.clear();
}

void ScriptRun::run(const ScriptLine& l, ViewerState& v, int fb_w, int fb_h) {
    if (const std::optional<std::string> said = run_command(v, l)) {
        std::fputs(said->c_str(), stdout);
        return;
    }
    const std::string& c = l.command;
    const std::string path = l.args.empty() ? "" : l.args[0];
    if (c == "wait-compare") {
        if (!v.ui.compare.active()) throw std::runtime_error("wait-compare: nothing compared");
        m_wait = Wait::Compare;
        m_wait_limit_s = l.args.empty() ? 120 : command_number(l, 0, 0.1, 3600);
        m_wait_start = std::chrono::steady_clock::now();
    } else if (c == "wait-spp" || c == "wait-jobs") {
        const bool spp = c == "wait-spp";
        m_wait = spp ? Wait::Spp : Wait::Jobs;
        m_wait_spp = spp ? command_whole(l, 0, 1, 1 << 20) : 0;
        const size_t limit = spp ? 1 : 0;
        m_wait_limit_s = l.args.size() > limit ? command_number(l, limit, 0.1, 3600) : 120;
        m_wait_start = std::chrono::steady_clock::now();
    } else if (c == "screenshot" && !path.empty()) {
        save_window(fb_w, fb_h, path);
        std::printf("rayview: frame %d: %s (trace at %d spp)\n", m_frame, path.c_str(),
                    v.trace.tracer.status().spp);
    } else {
        throw std::runtime_error("unknown command or missing argument: '" + c + "'");
    }
}

bool ScriptRun::end_frame(ViewerState& v, int fb_w, int fb_h, bool preview_drawn, int* exit_code) {
    if (m_wait != Wait::None) {  // this frame again until what the script waits for is there
        const double waited =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - m_wait_start).count();
        const CompareView& cv = v.ui.compare;
        const bool done = m_wait == Wait::Spp
                              ? !v.edit_pending() && v.trace.tracer.status().spp >= m_wait_spp
                          : m_wait == Wait::Compare
                              ? !cv.active() || (!v.edit_pending() && cv.current && cv.result)
                              : !v.jobs.loader.busy() && !v.jobs.image.running() && preview_drawn;
        if (done && m_wait == Wait::Compare && cv.active())
            std::printf("rayview: frame %d: %s\n", m_frame, compare_status(cv).c_str());
        if (done) {
            m_wait = Wait::None;  // shown from the next frame on, which runs the next commands
        } else if (waited > m_wait_limit_s) {
            std::fprintf(stderr, "rayview: frame %d: error: %s not done in %g s\n", m_frame,
                         m_wait == Wait::Spp       ? "wait-spp"
                         : m_wait == Wait::Compare ? "wait-compare"
                                                   : "wait-jobs",
                         m_wait_limit_s);
            m_failed = true;
            m_wait = Wait::None;
        }
        return false;
    }
    for (const ScriptLine& l : m_lines) {
        if (l.frame != m_frame) continue;
        try {
            run(l, v, fb_w, fb_h);
        } catch (const std::exception& e) {  // a bad number, a screenshot that cannot be written
            std::fprintf(stderr, "rayview: frame %d: error: %s\n", m_frame, e.what());
            m_failed = true;  // reported, and the run goes on; it exits 1 at the end
        }
        if (v.edit_pending()) m_causes.push_back(l.command);  // reported at the restart
    }
    // Scripted runs check GL once a frame: any error fails the run.
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
        std::fprintf(stderr, "rayview: frame %d: GL error 0x%x\n", m_frame, e);
        m_failed = true;
    }
    ++m_frame;
    if (m_frames_left <= 0 || --m_frames_left > 0) return false;
    // A failed command, or any error of the viewer's: an open, a background load or render,
    // the scene at start-up (each printed when it happened).
    if (m_failed || v.messages.failures > 0) *exit_code = 1;
    if (!m_screenshot.empty()) {
        try {
            save_window(fb_w, fb_h, m_screenshot);
            std::printf("rayview: saved %s\n", m_screenshot.c_str());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "rayview: %s\n", e.what());
            *exit_code = 1;
        }
    }
    return true;
}

void ScriptRun::print_summary(const FrameStats& stats, const ViewerState& v) const {
    if (stats.count() > 1 && !m_screenshot.empty()) stats.print(v);
}

}  // namespace rt::view
