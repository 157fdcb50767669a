#include "state/scene_session.h"

#include <algorithm>

namespace rt::view {

namespace {

std::string absolute_path(const std::string& path) {
    std::error_code ec;
    const auto abs = std::filesystem::absolute(path, ec);
    return ec ? path : abs.lexically_normal().string();
}

bool same_camera(const CameraDesc& a, const CameraDesc& b) {
    return a.position == b.position && a.direction == b.direction && a.up == b.up &&
           a.half_height_angle_rad == b.half_height_angle_rad;
}

}  // namespace

std::filesystem::file_time_type file_time(const std::string& path) {
    std::error_code ec;
    return std::filesystem::last_write_time(path, ec);
}

void SceneSession::add_recent(const std::string& path) {
    const std::string opened = absolute_path(path);
    std::vector<std::string> files{opened};  // first, and not again below; 8 at most
    for (const std::string& f : recent)
        if (f != opened && files.size() < 8) files.push_back(f);
    recent = std::move(files);
}

void SceneSession::remember_recent(const std::vector<std::string>& files) {
    for (const std::string& f : files) {
        std::error_code ec;
        if (recent.size() >= 8) break;
        if (std::find(recent.begin(), recent.end(), f) == recent.end() &&
            std::filesystem::exists(f, ec))
            recent.push_back(f);
    }
}

bool SceneSession::check_due() {
    const auto now = std::chrono::steady_clock::now();
    if (now - m_last_check < std::chrono::milliseconds(500)) return false;
    m_last_check = now;
    return true;
}

ReloadMerge edits_before_reload(const LoadedScene& old, const SceneEdits& edits) {
    ReloadMerge m;
    OrbitCamera file_view;
    file_view.set_from(old.file_camera, old.scene.world_bounds);
    m.camera_edited = !same_camera(file_view.desc(), edits.camera.desc());
    m.lights_edited = !same_lights(edits.lights, old.desc.lights) ||
                      std::count(edits.light_on.begin(), edits.light_on.end(), 0) > 0;
    m.mine = edits;
    m.old_lights = old.desc.lights;
    m.old_camera = old.file_camera;
    return m;
}

std::string merge_reload(const ReloadMerge& merge, const LoadedScene& now, SceneEdits* edits) {
    if (merge.camera_edited) edits->camera = merge.mine.camera;
    if (merge.lights_edited) {
        edits->lights = merge.mine.lights;
        edits->light_on = merge.mine.light_on;
    }
    std::string both;  // what the user edited and the file changed too
    if (merge.camera_edited && !same_camera(merge.old_camera, now.file_camera)) both = "camera";
    if (merge.lights_edited && !same_lights(merge.old_lights, now.desc.lights))
        both += both.empty() ? "lights" : " and lights";
    return both;
}

}  // namespace rt::view
