#include "image_job.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdio>

#include "rt/render/plan.h"
#include "rt/util/stopwatch.h"

namespace rt::view {

void ImageJob::start(RenderScene scene, const ImageJobSpec& spec) {
    cancel();
    m_scene = std::make_unique<RenderScene>(std::move(scene));
    m_stop = false;
    m_done = false;
    m_progress = 0;
    m_thread = std::thread([this, spec] { run(spec); });
}

void ImageJob::cancel() {
    m_stop = true;
    if (m_thread.joinable()) m_thread.join();
    m_stop = false;
    std::lock_guard lock(m_mutex);
    m_message.clear();  // a cancelled job says nothing
}

bool ImageJob::take_result(std::string* message, bool* ok) {
    if (!m_done || !m_thread.joinable()) return false;
    m_thread.join();
    m_scene.reset();
    std::lock_guard lock(m_mutex);
    if (m_message.empty()) return false;
    *message = std::move(m_message);
    *ok = m_ok;
    m_message.clear();
    return true;
}

void ImageJob::run(ImageJobSpec spec) {
    // Below the interface (nice 10, passed on to the render's worker threads) and above the
    // interactive trace (SCHED_IDLE): the window stays smooth and the image the user asked for
    // goes first.
    setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
    const Clock::time_point t0 = Clock::now();
    std::string message;
    bool ok = false;
    try {
        RenderSettings s = spec.settings;
        s.width = spec.width;
        s.height = spec.height;
        const RenderPlan plan = make_render_plan(*m_scene, s);
        RenderState state;
        // Stratified samples in one call when the image needs no progressive feature, as
        // raytrace --spp N renders; else passes of one sample, each a step of the progress bar.
        const int steps = s.stochastic() ? spec.spp : 1;
        const int per_step = spec.spp / steps;
        bool finished = true;
        for (int i = 0; i < steps && finished; ++i) {
            finished = render_samples(
                state, *m_scene, plan, s, per_step,
                [&](int rows, int total) {
                    m_progress = (i + static_cast<double>(rows) / std::max(1, total)) / steps;
                },
                &m_stop);
        }
        if (finished) {
            const Image linear = state.image();
            const bool pfm = image_format_from_path(spec.path) == ImageFormat::Pfm;
            save_image(pfm ? linear : display_transform(linear, spec.exposure, spec.tonemap),
                       spec.path);
            char buf[64];
            std::snprintf(buf, sizeof buf, " (%dx%d, %d spp, %.1f s)", spec.width, spec.height,
                          spec.spp, seconds_since(t0));
            message = "saved " + spec.path + buf;
            ok = true;
        }
    } catch (const std::exception& e) {
        message = e.what();
    }
    {
        std::lock_guard lock(m_mutex);
        m_message = message;
        m_ok = ok;
    }
    m_progress = 1;
    m_done = true;
}

}  // namespace rt::view
