// "Save image" at a size and sample count of the user's choice, and "render animation": rendered
// on a thread of its own from a copy of the scene as edited (the interactive trace goes on), with
// progress and cancel, then written atomically (8-bit formats with the display's exposure and
// tonemap, PFM linear). A cancelled or failed image writes nothing; a sequence keeps the frames
// written before it stopped.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "rt/image/image.h"
#include "rt/render/render.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"
#include "rt/util/threads.h"

namespace rt::view {

/// An animation rendered frame by frame (frames > 0): frame k at start + k / fps, written to
/// ImageJobSpec::path as a %d pattern (raytrace --frames), optionally encoded by ffmpeg.
struct SequenceSpec {
    std::shared_ptr<const SceneDesc> desc;  // what animate() needs
    int frames = 0;
    double fps = 24, start = 0;
    Interpolation interpolation = Interpolation::CatmullRom;
    Rotation rotation = Rotation::Quaternion;
    std::string video;  // "" : no video
};

struct ImageJobSpec {
    std::string path;
    int width = 640, height = 480, spp = 16;
    RenderSettings settings;  // depth, shadows, threads, progressive features
    double exposure = 0;
    Tonemap tonemap = Tonemap::Clamp;
    SequenceSpec sequence;
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
    /// The share done, in [0, 1] (of every frame's samples for a sequence).
    double progress() const { return m_progress; }
    /// Once a job has ended: its message ("saved PATH (WxH, N spp, T s)" or the error) and
    /// whether it succeeded; false while running or when there is no new result.
    bool take_result(std::string* message, bool* ok);

private:
    void run(ImageJobSpec spec);
    /// One image of the job's scene; false when cancelled. Progress from `done` to `done + share`.
    bool render_one(const ImageJobSpec& spec, const std::string& path, double done, double share);
    /// Every frame of spec.sequence; the message says how many were written.
    bool render_sequence(const ImageJobSpec& spec, std::string* message);

    std::unique_ptr<RenderScene> m_scene;
    std::thread m_thread;
    std::atomic<bool> m_stop{false}, m_done{false};
    std::atomic<double> m_progress{0};
    std::mutex m_mutex;
    std::string m_message;
    bool m_ok = false;
};

}  // namespace rt::view
