// The viewer's progressive trace: one worker thread family (render_samples' own) driven by a
// controller thread; only the interface thread touches OpenGL. Every edit goes through
// restart(), which stops and joins the worker, then traces a copy of the edited scene that the
// tracer owns (the viewer's own scene moves on with the preview meanwhile).
// Without threads (the web page's single-thread build) the same passes are rendered on the
// interface thread by pump(), a tile at a time between its frames, as the MPI mode splits a
// pass into tiles (render_part, add_part_samples: the same image).
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "rt/image/image.h"
#include "rt/render/progressive.h"
#include "rt/render/render.h"
#include "rt/util/threads.h"

namespace rt::view {

class Tracer {
public:
    /// `threaded` false: restart() starts no thread and pump() renders the trace.
    explicit Tracer(bool threaded = have_threads()) : m_threaded(threaded) {}
    ~Tracer() { stop(); }
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    bool threaded() const { return m_threaded; }
    /// Without threads: renders the trace for about `seconds` on this thread (at least one
    /// tile), then returns. With threads: nothing.
    void pump(double seconds);

    /// Stops the trace and waits for it.
    void stop();
    /// Starts tracing `scene` (the tracer keeps it until the next restart, so the caller's
    /// scene may change meanwhile; its sets are shared, so the copy costs its instances): a
    /// coarse pass first, then passes of one sample per pixel up to `target_spp`, or until the
    /// estimated relMSE reaches `target_error` (from 8 spp; 0: no target). `reference`: after
    /// the coarse pass, one pass of `target_spp` samples with the spec's sampling (§6.2: the
    /// pixel centre at 1 spp), the image raytrace writes, for comparisons. A trace running is
    /// stopped first.
    void restart(RenderScene scene, const RenderSettings& settings, int target_spp,
                 double target_error = 0, bool reference = false);
    /// The scene and the plan of the trace started last (made by restart(), once per restart;
    /// the scene is empty before the first).
    const RenderScene& scene() const { return m_scene; }
    const RenderPlan& plan() const { return m_plan; }

    struct Status {
        int spp = 0;
        double seconds = 0;  // since the restart
        double rays_per_second = 0;
        double estimate = 0;      // relMSE estimated from the samples
        double target_error = 0;  // the restart's target (0: none)
        bool reached = false;     // the estimate reached it: the trace stopped there
        /// The seconds (since the restart) at which the estimate reaches the target
        /// (TargetForecast); negative while it cannot be told.
        double target_seconds = -1;
    };
    /// The latest image if it changed since the last call (returns false otherwise), and its
    /// samples per pixel (0: the coarse pass).
    bool take_image(Image* out, int* spp = nullptr);
    Status status() const;
    /// (seconds, estimated relMSE) after each pass since the restart.
    std::vector<std::pair<float, float>> history() const;

private:
    void run(RenderSettings settings, int target_spp, double target_error, bool reference);
    /// After each pass: the image, the status and the history; true when the trace is done
    /// (the target reached).
    bool publish(const RenderState& state, double seconds, double target_error);
    bool more_passes(const RenderState& state, int target_spp) const;

    // The trace pump() renders (without threads): what restart() was given, the state, and the
    // pass's tiles (those before m_next_tile done).
    struct Cooperative {
        RenderSettings settings;
        int target_spp = 0;
        double target_error = 0;
        bool reference = false;  // one pass of target_spp samples, as raytrace renders
        std::chrono::steady_clock::time_point t0;
        bool coarse_done = false, done = true;
        RenderState state;
        std::vector<RenderPart> tiles;
        size_t next_tile = 0;
    };

    const bool m_threaded;
    Cooperative m_coop;
    // Written by restart() only while no trace runs.
    RenderScene m_scene;
    RenderPlan m_plan;
    std::thread m_thread;
    std::atomic<bool> m_stop{false};
    mutable std::mutex m_mutex;
    Image m_image;
    bool m_updated = false;
    Status m_status;
    std::vector<std::pair<float, float>> m_history;
    TargetForecast m_forecast;  // the time to the target error
};

}  // namespace rt::view
