// The open scene and its file: how files open (--missing-textures, --dialect), the recent
// files, the file watched for changes, the offer to open a file with checker stand-ins, and the
// merge of a reload with the user's edits. No GL.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "state/edits.h"
#include "state/loader.h"

namespace rt::view {

struct SceneSession {
    std::unique_ptr<LoadedScene> loaded;  // null until a file opens
    std::string checker_offer;       // a file that failed to open for its textures only, else ""
    int checker_offer_message = -1;  // Messages::serial of its error: gone with a newer one
    std::string reload_conflict;     // a reload kept edits of what the file changed too, else ""
    MissingTextures missing_textures = MissingTextures::Error;  // how files open
    std::optional<Dialect> dialect;   // --dialect: every file opens in it (else detected)
    std::vector<std::string> recent;  // files opened (absolute), most recent first, at most 8
    /// The file that failed to open at start-up, while none is open, and its time then.
    std::string watched;
    std::filesystem::file_time_type watched_time;

    /// How `path` opens: as every file does, for the preview.
    LoadRequest request(const std::string& path) const {
        return {path, missing_textures, true, dialect};
    }
    /// How the open file opens again (as it was opened).
    LoadRequest reload_request() const {
        return {loaded->path, loaded->missing_textures, true, dialect};
    }
    /// The user keeps the edits a reload reported: the conflict is no longer shown.
    void keep_my_edits() { reload_conflict.clear(); }
    /// The checker offer goes with its message: a newer message (`serial`, Messages::serial)
    /// withdraws it.
    void withdraw_offer_after(int serial) {
        if (!checker_offer.empty() && checker_offer_message != serial) checker_offer.clear();
    }
    /// A new scene takes the next id (LoadedScene::id).
    int next_id() { return ++m_scenes_opened; }
    /// `path` opened: first among the recent files.
    void add_recent(const std::string& path);
    /// Adds files opened in earlier runs after this run's (those that still exist).
    void remember_recent(const std::vector<std::string>& files);
    /// At most twice a second: whether to look at the files' times again.
    bool check_due();

private:
    int m_scenes_opened = 0;
    std::chrono::steady_clock::time_point m_last_check = std::chrono::steady_clock::now();
};

/// The file's time of last change (none when it cannot be read).
std::filesystem::file_time_type file_time(const std::string& path);

/// What the user edited, against the scene as it was read last, taken before a reload
/// replaces it.
struct ReloadMerge {
    bool camera_edited = false, lights_edited = false;
    SceneEdits mine;
    std::vector<LightDesc> old_lights;
    CameraDesc old_camera;
};
ReloadMerge edits_before_reload(const LoadedScene& old, const SceneEdits& edits);
/// After the reload: the user's edits in `merge` stay over the file's new camera and lights in
/// `*edits`. Returns what the user edited and the file changed too ("camera", "lights",
/// "camera and lights"; "" when nothing).
std::string merge_reload(const ReloadMerge& merge, const LoadedScene& now, SceneEdits* edits);

}  // namespace rt::view
