// Opening a scene: load_scene() reads and compiles a file in one call that returns a result,
// and SceneLoader runs it without freezing the window (on a thread of its own while the open
// scene stays interactive), with the bytes parsed of those read, then the compile's share done,
// for a progress bar. A cancelled load is abandoned: its parse or its compile stops at its next
// check (LoadProgress::cancel), its thread finishes in the background and its result is
// dropped, so cancel never waits for a parser.
#pragma once

#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"
#include "state/edits.h"
#include "state/preview_geometry.h"

namespace rt::view {

/// A scene as read from its file, and compiled: one scene, which the preview draws. Its joints
/// follow the timeline every frame; its camera, lights and materials are the edits of the last
/// restart (they live in ViewerState::edits until then), which traces a copy of it.
struct LoadedScene {
    std::string path;
    SceneDesc desc;  // as parsed
    RenderScene scene;
    CameraDesc file_camera;                     // Home returns here
    std::filesystem::file_time_type file_time;  // the file's time when last read
    int id = 0;  // counts the scenes opened, so views of the scene know when it changed
    /// How it was opened: with Checker, desc.missing_textures lists the stand-ins (a reload
    /// opens it the same way).
    MissingTextures missing_textures = MissingTextures::Error;
    std::vector<std::vector<SourceLoc>> prim_locs;  // CompileReport's, for picking
    std::vector<std::string> material_names;
    std::vector<MaterialDesc> file_materials;      // as the files have them (material_descs)
    std::vector<MaterialOrigin> material_origins;  // of each of them
    /// Where compiled material k comes from (file -1: the built-in default).
    MaterialOrigin origin(size_t k) const {
        return k < material_origins.size() ? material_origins[k] : MaterialOrigin{};
    }
    /// The preview's tessellation, made with the scene (on the loader's thread) and freed once
    /// the preview uploaded it.
    PreviewGeometry preview;
};

/// What to open and how.
struct LoadRequest {
    std::string path;
    MissingTextures missing = MissingTextures::Error;
    /// Also tessellate it for the preview (LoadedScene::preview); a headless render does not.
    bool for_preview = true;
    std::optional<Dialect> dialect;  // overrides the one detected from the file tree (--dialect)
};

/// A scene read, or why not.
struct LoadResult {
    std::unique_ptr<LoadedScene> scene;  // null on failure
    std::string error;                   // on failure: "loading PATH: ..." (file:line:col)
    /// With MissingTextures::Error, a failed open is tried again with checker stand-ins: true
    /// when that would open it (the failure was only textures that cannot be opened).
    bool textures_missing = false;
};

/// How far a load is: the parse's bytes, then the compile's units of work, then the preview's
/// tessellation; one cancel for all three.
struct LoadProgress {
    ParseProgress parse;
    CompileProgress compile;
    std::atomic<bool> previewing{false};  // the scene is compiled: its preview is being made
    LoadProgress() { compile.cancel = &parse.cancel; }
    void cancel() { parse.cancel = true; }
    bool cancelled() const { return parse.cancel.load(std::memory_order_relaxed); }
};

/// What SceneLoader::status() shows of the load under way (all 0 when none).
struct LoadStatus {
    uint64_t parsed = 0, read = 0;          // bytes of scene text
    uint64_t compiled = 0, to_compile = 0;  // the compile's units (0, 0 until it starts)
    bool previewing = false;
};

/// Reads and compiles a scene; the parse and the compile report to `progress` and stop when it
/// is cancelled.
LoadResult load_scene(const LoadRequest& request, LoadProgress* progress = nullptr);

/// The panel's note on the textures that stand in as checkers ("" when none).
std::string stand_in_text(const SceneDesc& desc);

class SceneLoader {
public:
    SceneLoader();
    ~SceneLoader();
    SceneLoader(const SceneLoader&) = delete;
    SceneLoader& operator=(const SceneLoader&) = delete;

    /// Starts load_scene(request); a load under way is cancelled first.
    void start(const LoadRequest& request);
    /// Drops the load under way (the open scene stays).
    void cancel();
    bool busy() const { return m_job != nullptr; }
    const std::string& path() const;
    double seconds() const;  // since the load started
    /// How far the load under way is.
    LoadStatus status() const;
    /// Once the load under way has ended: its result and the path it read; false while it runs
    /// or when none runs.
    bool take(LoadResult* result, std::string* path);

private:
    struct Job;
    void reap();  // joins abandoned loads that have finished
    std::unique_ptr<Job> m_job;
    std::vector<std::unique_ptr<Job>> m_abandoned;
};

}  // namespace rt::view
