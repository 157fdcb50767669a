#include "state/tracer.h"

#include <algorithm>

#ifdef __linux__
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace rt::view {

void Tracer::stop() {
    m_coop.done = true;
    m_stop = true;
    if (m_thread.joinable()) m_thread.join();
    m_stop = false;
    std::lock_guard lock(m_mutex);
    m_updated = false;  // the stopped run's image is no longer news (the scene may change)
}

void Tracer::restart(RenderScene scene, const RenderSettings& settings, int target_spp,
                     double target_error, bool reference) {
    stop();
    {
        std::lock_guard lock(m_mutex);
        m_status = {};
        m_status.target_error = target_error;
        m_history.clear();
        m_forecast.clear();
    }
    m_scene = std::move(scene);
    m_plan = make_render_plan(m_scene, settings);
    if (!m_threaded) {  // pump() renders it
        m_coop = Cooperative();
        m_coop.settings = settings;
        m_coop.target_spp = target_spp;
        m_coop.target_error = target_error;
        m_coop.t0 = std::chrono::steady_clock::now();
        m_coop.done = false;
        m_coop.reference = reference;
        m_coop.settings.centre_first_sample = reference;  // as run()'s passes
        return;
    }
    m_thread = std::thread([this, settings, target_spp, target_error, reference] {
        run(settings, target_spp, target_error, reference);
    });
}

bool Tracer::more_passes(const RenderState& state, int target_spp) const {
    return target_spp <= 0 || state.samples.empty() ||
           static_cast<int>(state.samples[0]) < target_spp;
}

void Tracer::pump(double seconds) {
    Cooperative& c = m_coop;
    if (m_threaded || c.done) return;
    using Clock = std::chrono::steady_clock;
    const auto until = Clock::now() + std::chrono::duration<double>(seconds);
    if (!c.coarse_done) {  // the cheap first pass, as run()'s
        Image coarse = render_coarse(m_scene, m_plan, c.settings, 8);
        std::lock_guard lock(m_mutex);
        m_image = std::move(coarse);
        m_updated = true;
        c.coarse_done = true;
        c.state.reset(c.settings.width, c.settings.height);
        return;
    }
    constexpr int kTileW = 64, kTileH = 16;
    do {
        if (c.next_tile == 0) {  // a new pass of one sample per pixel, in tiles
            if (!more_passes(c.state, c.target_spp)) {
                c.done = true;
                return;
            }
            const uint32_t first = c.state.samples.empty() ? 0 : c.state.samples[0];
            const auto spp = static_cast<uint32_t>(std::max(1, c.target_spp));
            c.tiles = c.reference ? tile_parts(c.settings.width, c.settings.height, kTileW, kTileH,
                                               0, spp, spp)
                                  : tile_parts(c.settings.width, c.settings.height, kTileW, kTileH,
                                               first, 1, first + 1);
        }
        render_part(c.tiles[c.next_tile++], m_scene, m_plan, c.settings);
        if (c.next_tile == c.tiles.size()) {  // the pass is complete
            for (const RenderPart& p : c.tiles) add_part_samples(c.state, p);
            ++c.state.passes;
            c.next_tile = 0;
            const double s = std::chrono::duration<double>(Clock::now() - c.t0).count();
            if (publish(c.state, s, c.target_error) || c.reference) c.done = true;
        }
    } while (!c.done && Clock::now() < until);
}

void Tracer::run(RenderSettings settings, int target_spp, double target_error, bool reference) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    // The tracer yields to the interface: this thread and the workers it starts (Linux keeps
    // the policy per thread and passes it on to new threads) run only when a core is idle
    // (SCHED_IDLE), or else at the lowest nice value, so the interface thread and the GL
    // driver's threads get the cores when they need them.
#ifdef __linux__
    const sched_param idle{};
    if (sched_setscheduler(0, SCHED_IDLE, &idle) != 0)
        setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 19);
#endif
    // A cheap first pass so a moving camera stays interactive.
    Image coarse = render_coarse(m_scene, m_plan, settings, 8, &m_stop);
    if (m_stop) return;
    {
        std::lock_guard lock(m_mutex);
        m_image = std::move(coarse);
        m_updated = true;
    }
    RenderState state;
    if (reference) {  // raytrace's image: its sampling, every sample in one pass
        settings.centre_first_sample = true;
        if (!render_samples(state, m_scene, m_plan, settings, std::max(1, target_spp), {}, &m_stop))
            return;
        publish(state, std::chrono::duration<double>(Clock::now() - t0).count(), 0);
        return;
    }
    settings.centre_first_sample = false;  // progressive: every sample jittered
    while (!m_stop && more_passes(state, target_spp)) {
        if (!render_samples(state, m_scene, m_plan, settings, 1, {}, &m_stop)) return;
        const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        if (publish(state, seconds, target_error)) return;
    }
}

bool Tracer::publish(const RenderState& state, double seconds, double target_error) {
    const ErrorEstimate est = estimate_error(state);
    Image img = state.image();
    std::lock_guard lock(m_mutex);
    m_image = std::move(img);
    m_updated = true;
    m_status.spp = static_cast<int>(state.samples[0]);
    m_status.seconds = seconds;
    m_status.rays_per_second = static_cast<double>(state.rays.total()) / seconds;
    m_status.estimate = est.relmse;
    if (est.relmse > 0)
        m_history.emplace_back(static_cast<float>(seconds), static_cast<float>(est.relmse));
    if (target_error > 0 && m_status.spp >= ProgressiveSettings::kTargetMinSpp) {
        // The time to the target, from the passes since the estimate settled.
        m_status.target_seconds = m_forecast.add(seconds, est.relmse, target_error);
        if (est.relmse <= target_error) {
            m_status.reached = true;
            m_status.target_seconds = seconds;
            return true;
        }
    }
    return false;
}

bool Tracer::take_image(Image* out, int* spp) {
    std::lock_guard lock(m_mutex);
    if (!m_updated) return false;
    *out = m_image;
    if (spp) *spp = m_status.spp;  // published with the image, under the same lock
    m_updated = false;
    return true;
}

Tracer::Status Tracer::status() const {
    std::lock_guard lock(m_mutex);
    return m_status;
}

std::vector<std::pair<float, float>> Tracer::history() const {
    std::lock_guard lock(m_mutex);
    return m_history;
}

}  // namespace rt::view
