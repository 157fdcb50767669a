// Opening a scene without freezing the window: the file is read and compiled on a thread of
// its own while the open scene stays interactive. A cancelled load is abandoned (its thread
// finishes in the background and its result is dropped), so cancel never waits for a parser.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace rt::view {

struct LoadedScene;

class SceneLoader {
public:
    /// Reads and compiles a scene: nullptr and *error on failure; *textures_missing as
    /// load_scene() says.
    using LoadFn =
        std::function<std::unique_ptr<LoadedScene>(std::string* error, bool* textures_missing)>;
    SceneLoader();
    ~SceneLoader();
    SceneLoader(const SceneLoader&) = delete;
    SceneLoader& operator=(const SceneLoader&) = delete;

    /// Starts loading `path` with `load`; a load under way is cancelled first.
    void start(const std::string& path, LoadFn load);
    /// Drops the load under way (the open scene stays).
    void cancel();
    bool busy() const { return m_job != nullptr; }
    const std::string& path() const;
    double seconds() const;  // since the load started
    /// Once the load under way has ended: its scene (nullptr on failure), error and whether
    /// only textures failed; false while it runs or when none runs.
    bool take(std::unique_ptr<LoadedScene>* scene, std::string* error, bool* textures_missing,
              std::string* path);

private:
    struct Job;
    void reap();  // joins abandoned loads that have finished
    std::unique_ptr<Job> m_job;
    std::vector<std::unique_ptr<Job>> m_abandoned;
};

}  // namespace rt::view
