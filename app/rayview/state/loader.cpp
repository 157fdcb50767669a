#include "state/loader.h"

#include "cli.h"
#include "rt/compile/compile.h"
#include "rt/render/camera.h"
#include "rt/util/threads.h"

namespace rt::view {

std::string stand_in_text(const SceneDesc& desc) {
    if (desc.missing_textures.empty()) return "";
    std::string text = "checker stand-ins for missing textures:";
    for (const std::string& t : desc.missing_textures) text += "\n  " + t;
    return text;
}

LoadResult load_scene(const LoadRequest& request, LoadProgress* progress) {
    LoadResult result;
    const std::string& path = request.path;
    try {
        Diagnostics diag;
        auto s = std::make_unique<LoadedScene>();
        s->path = path;
        s->missing_textures = request.missing;
        ParseOptions options;
        options.missing_textures = request.missing;
        options.dialect = request.dialect;
        options.progress = progress ? &progress->parse : nullptr;
        try {
            s->desc = parse_scene_file(path, diag, options);
        } catch (const SceneError&) {
            // Would checker stand-ins open it? Then the textures were all that failed (a parse
            // the progress bar does not count).
            options.progress = nullptr;
            if (request.missing == MissingTextures::Error &&
                !(progress && progress->parse.cancel)) {
                Diagnostics quiet;
                options.missing_textures = MissingTextures::Checker;
                try {
                    result.textures_missing =
                        !parse_scene_file(path, quiet, options).missing_textures.empty();
                } catch (const std::exception&) {
                }
            }
            throw;
        }
        CompileReport report;
        report.record_locations = true;  // for picking
        s->scene = compile_scene(s->desc, &report, std::nullopt, nullptr, 0,
                                 progress ? &progress->compile : nullptr);
        s->prim_locs = std::move(report.prim_locs);
        s->material_names = std::move(report.material_names);
        s->file_materials = material_descs(s->desc);
        s->material_origins = material_origins(s->desc);
        if (request.for_preview) {
            if (progress) progress->previewing = true;
            s->preview =
                prepare_preview(s->scene, 48, progress ? &progress->parse.cancel : nullptr);
        }
        if (s->desc.camera) {
            s->file_camera = *s->desc.camera;
        } else {  // spec §6.3's default camera, framed for 4:3
            const CameraPose d = default_camera(s->scene.world_bounds, 640, 480);
            s->file_camera.position = d.position;
            s->file_camera.direction = d.direction;
            s->file_camera.up = d.up;
            s->file_camera.half_height_angle_rad = d.half_height_angle_rad;
        }
        result.scene = std::move(s);
    } catch (const std::exception& e) {
        result.error = rtapp::error_text(e, "loading " + path);
    }
    return result;
}

struct SceneLoader::Job {
    std::string path;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    std::thread thread;
    std::atomic<bool> done{false};
    LoadProgress progress;
    LoadResult result;  // written by the thread before done
    ~Job() {
        if (thread.joinable()) thread.join();
    }
};

SceneLoader::SceneLoader() = default;
SceneLoader::~SceneLoader() = default;  // joins every thread (Job's destructor)

void SceneLoader::start(const LoadRequest& request) {
    cancel();
    m_job = std::make_unique<Job>();
    m_job->path = request.path;
    Job* job = m_job.get();
    auto work = [job, request] {
        try {
            job->result = load_scene(request, &job->progress);
        } catch (const std::exception& e) {
            job->result.error = e.what();
        }
        job->done = true;
    };
    if (have_threads())
        job->thread = std::thread(std::move(work));
    else  // the single-thread web page: loaded before this returns, taken at the next poll
        work();
}

void SceneLoader::cancel() {
    if (m_job) {
        m_job->progress.cancel();
        m_abandoned.push_back(std::move(m_job));
    }
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

LoadStatus SceneLoader::status() const {
    if (!m_job) return {};
    const LoadProgress& p = m_job->progress;
    return {p.parse.done.load(), p.parse.total.load(), p.compile.done.load(),
            p.compile.total.load(), p.previewing.load()};
}

bool SceneLoader::take(LoadResult* result, std::string* path) {
    reap();
    if (!m_job || !m_job->done) return false;
    m_job->thread.join();
    *result = std::move(m_job->result);
    *path = std::move(m_job->path);
    m_job.reset();
    return true;
}

}  // namespace rt::view
