#include "state/image_job.h"

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <cstdio>

#include "frames.h"
#include "rt/compile/compile.h"
#include "rt/render/plan.h"
#include "rt/util/stopwatch.h"

namespace rt::view {

void ImageJob::start(RenderScene scene, const ImageJobSpec& spec) {
    cancel();
    m_scene = std::make_unique<RenderScene>(std::move(scene));
    m_stop = false;
    m_done = false;
    m_progress = 0;
    if (have_threads())
        m_thread = std::thread([this, spec] { run(spec); });
    else  // the single-thread web page: the image is rendered before this returns
        run(spec);
}

void ImageJob::cancel() {
    m_stop = true;
    if (m_thread.joinable()) m_thread.join();
    m_stop = false;
    std::lock_guard lock(m_mutex);
    m_message.clear();  // a cancelled job says nothing
}

bool ImageJob::take_result(std::string* message, bool* ok) {
    if (!m_done) return false;  // (a result taken once has its message cleared below)
    if (m_thread.joinable()) m_thread.join();
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
#ifdef __linux__
    setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
#endif
    const Clock::time_point t0 = Clock::now();
    std::string message;
    bool ok = false;
    try {
        if (spec.sequence.frames > 0) {
            ok = render_sequence(spec, &message);
        } else if (render_one(spec, spec.path, 0, 1)) {
            char buf[64];
            std::snprintf(buf, sizeof buf, " (%dx%d, %d spp, %.1f s)", spec.width, spec.height,
                          spec.spp, seconds_since(t0));
            message = "saved " + spec.path + buf;
            ok = true;
        }
    } catch (const std::bad_alloc&) {
        message = "out of memory while rendering " + spec.path + " (" + std::to_string(spec.width) +
                  "x" + std::to_string(spec.height) + ")";
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

bool ImageJob::render_one(const ImageJobSpec& spec, const std::string& path, double done,
                          double share) {
    RenderSettings s = spec.settings;
    s.width = spec.width;
    s.height = spec.height;
    const RenderPlan plan = make_render_plan(*m_scene, s);
    RenderState state;
    // Stratified samples in one call when the image needs no progressive feature, as
    // raytrace --spp N renders; else passes of one sample, each a step of the progress bar.
    const int steps = s.stochastic() ? spec.spp : 1;
    const int per_step = spec.spp / steps;
    for (int i = 0; i < steps; ++i) {
        const bool finished = render_samples(
            state, *m_scene, plan, s, per_step,
            [&](int rows, int total) {
                m_progress =
                    done + share * (i + static_cast<double>(rows) / std::max(1, total)) / steps;
            },
            &m_stop);
        if (!finished) return false;
    }
    const Image linear = state.image();
    const bool linear_file = holds_linear(image_format_from_path(path));  // PFM, EXR
    save_image(linear_file ? linear : display_transform(linear, spec.exposure, spec.tonemap), path);
    return true;
}

bool ImageJob::render_sequence(const ImageJobSpec& spec, std::string* message) {
    const SequenceSpec& q = spec.sequence;
    const Clock::time_point t0 = Clock::now();
    int written = 0;
    for (int k = 0; k < q.frames; ++k) {
        if (q.desc)
            animate(*m_scene, *q.desc, SceneTime{q.start + k / q.fps, q.interpolation, q.rotation});
        if (!render_one(spec, rtapp::frame_path(spec.path, k), static_cast<double>(k) / q.frames,
                        1.0 / q.frames)) {
            *message = "render animation stopped: " + std::to_string(written) + " of " +
                       std::to_string(q.frames) + " frames written";
            return false;
        }
        ++written;
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, " (%d frames, %dx%d, %d spp, %.1f s)", q.frames, spec.width,
                  spec.height, spec.spp, seconds_since(t0));
    *message = "saved " + spec.path + buf;
    if (q.video.empty()) return true;
    std::string error;
    if (!rtapp::encode_video(spec.path, q.frames, q.fps, q.video, &error)) {
        *message += "; " + error;
        return false;
    }
    *message += " and " + q.video;
    return true;
}

}  // namespace rt::view
