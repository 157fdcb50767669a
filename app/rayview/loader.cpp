#include "loader.h"

#include "rt/util/threads.h"
#include "viewer.h"

namespace rt::view {

struct SceneLoader::Job {
    std::string path;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    std::thread thread;
    std::atomic<bool> done{false};
    std::unique_ptr<LoadedScene> scene;  // written by the thread before done
    std::string error;
    bool textures_missing = false;
    ~Job() {
        if (thread.joinable()) thread.join();
    }
};

SceneLoader::SceneLoader() = default;
SceneLoader::~SceneLoader() = default;  // joins every thread (Job's destructor)

void SceneLoader::start(const std::string& path, LoadFn load) {
    cancel();
    m_job = std::make_unique<Job>();
    m_job->path = path;
    Job* job = m_job.get();
    auto work = [job, load = std::move(load)] {
        try {
            job->scene = load(&job->error, &job->textures_missing);
        } catch (const std::exception& e) {
            job->error = e.what();
        }
        job->done = true;
    };
    if (have_threads())
        job->thread = std::thread(std::move(work));
    else  // the single-thread web page: loaded before this returns, taken at the next poll
        work();
}

void SceneLoader::cancel() {
    if (m_job) m_abandoned.push_back(std::move(m_job));
    reap();
}

void SceneLoader::reap() {
    std::erase_if(m_abandoned, [](const std::unique_ptr<Job>& j) { return j->done.load(); });
}

const std::string& SceneLoader::path() const {
    static const std::string none;
    return m_job ? m_job->path : none;
}

double SceneLoader::seconds() const {
    if (!m_job) return 0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_job->start).count();
}

bool SceneLoader::take(std::unique_ptr<LoadedScene>* scene, std::string* error,
                       bool* textures_missing, std::string* path) {
    reap();
    if (!m_job || !m_job->done) return false;
    m_job->thread.join();
    *scene = std::move(m_job->scene);
    *error = std::move(m_job->error);
    *textures_missing = m_job->textures_missing;
    *path = std::move(m_job->path);
    m_job.reset();
    return true;
}

}  // namespace rt::view
