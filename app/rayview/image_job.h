// "Save image" at a size and sample count of the user's choice: rendered on a thread of its
// own from a copy of the scene as edited (the interactive trace goes on), with progress and
// cancel, then written atomically (8-bit formats with the display's exposure and tonemap, PFM
// linear). A cancelled or failed job writes nothing.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "rt/compile/render_scene.h"
#include "rt/image/image.h"
#include "rt/render/render.h"

namespace rt::view {

struct ImageJobSpec {
    std::string path;
    int width = 640, height = 480, spp = 16;
    RenderSettings settings;  // depth, shadows, threads, progressive features
    double exposure = 0;
    Tonemap tonemap = Tonemap::Clamp;
};

class ImageJob {
public:
    ~ImageJob() { cancel(); }
    /// Starts rendering `scene` (the job's own copy) as `spec` says; a running job is
    /// cancelled first.
    void start(RenderScene scene, const ImageJobSpec& spec);
    /// Stops a running job and waits for it; nothing is written.
    void cancel();
    bool running() const { return m_thread.joinable() && !m_done; }
    /// Samples per pixel done of spec.spp, in [0, 1].
    double progress() const { return m_progress; }
    /// Once a job has ended: its message ("saved PATH (WxH, N spp, T s)" or the error) and
    /// whether it succeeded; false while running or when there is no new result.
    bool take_result(std::string* message, bool* ok);

private:
    void run(ImageJobSpec spec);

    std::unique_ptr<RenderScene> m_scene;
    std::thread m_thread;
    std::atomic<bool> m_stop{false}, m_done{false};
    std::atomic<double> m_progress{0};
    std::mutex m_mutex;
    std::string m_message;
    bool m_ok = false;
};

}  // namespace rt::view
