// The viewer's state without any window or GL, composed of parts with one job each: the open
// scene and its file (SceneSession), the user's edits and settings (edits.h), the progressive
// trace (TraceSession), undo and redo (History), the background jobs (Jobs), the panel's
// messages (Messages), the window's own state (ViewUi) and the web page's hooks (PageHooks).
// ViewerState keeps the operations that span them; what the viewer writes (viewer_output.h)
// and the comparison with an image (viewer_compare.h) are functions over it. An edit marks
// itself: edit_pending() sees the edits and settings change, and restart_if_due() then takes
// the one restart path: stop the trace, apply the edits to the compiled scene, start again
// (yocto-gl's reset_display()).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rt/format/parser.h"
#include "rt/image/image.h"
#include "state/edits.h"
#include "state/history.h"
#include "state/image_job.h"
#include "state/jobs.h"
#include "state/loader.h"
#include "state/messages.h"
#include "state/scene_session.h"
#include "state/selection.h"
#include "state/timeline.h"
#include "state/trace_session.h"
#include "state/view_ui.h"

namespace rt::view {

struct ViewerState {
    /// Opens `path`; on an error the message is kept in `messages`. `print_left_out`: print the
    /// features the renderer leaves out at the first restart (for --frames runs).
    /// `missing`: how every file opens (--missing-textures).
    ViewerState(const std::string& path, bool print_left_out,
                MissingTextures missing = MissingTextures::Error,
                std::optional<Dialect> file_dialect = std::nullopt);

    SceneSession session;  // before `trace`: the trace stops before the scene it traces dies
    /// The camera, the lights and the materials, edited through SceneEdits' verbs (or as a copy
    /// put back whole): a change is seen by edit_pending(), so no writer marks it.
    SceneEdits edits;
    ViewSettings settings;  // also seen when a setting the trace uses changes
    /// The joints' time, playback and choices; restart() moves the joints to its time.
    Timeline timeline;
    TraceSession trace;
    History history;
    Jobs jobs;
    Messages messages;
    ViewUi ui;
    PageHooks hooks;

    // ---- the scene file ----
    /// Opens a file; on an error the message is shown and the previous scene stays.
    bool open(std::string file, bool keep_camera);  // by value: callers pass loaded->path
    /// Opens a file on a background thread (the open scene stays interactive; poll_files()
    /// takes the result); a load under way is cancelled first.
    void open_in_background(std::string file);
    /// Drops the load under way: the open scene stays.
    void cancel_loading();
    /// Opens `session.checker_offer` with checker stand-ins for its missing textures.
    bool open_with_checker();
    /// Reads the open file again and keeps the user's edits: the camera and the lights as edited
    /// stay, the file's new ones are taken where the user edited nothing. When the file changed
    /// what the user had edited, the edits stay and `session.reload_conflict` says so, with the
    /// choice use_file_edits(). False (and nothing changed) when the file no longer opens.
    bool reload();
    /// Drops the kept edits the last reload() reported in `session.reload_conflict`: the file's
    /// camera and lights.
    void use_file_edits();
    /// Takes finished background work (an image, a load or a reload, an image to compare
    /// with), opens the last file dropped onto the window, and reloads the open file in the
    /// background when it changed on disk (its time is checked twice a second, not every frame).
    void poll_files();

    // ---- animation ----
    /// The open scene's animation length in seconds (0: not animated).
    double animation_length() const;
    /// Once a frame: playback advances the time by `frame_s` and the preview's copy of the
    /// scene moves there (the trace restarts there by the restart policy, showing its coarse
    /// pass while the animation plays).
    void step_animation(double frame_s);
    /// The timeline was scrubbed or a choice changed: the trace restarts at the time shown.
    void seek(double t);

    // ---- edits and the one restart path ----
    /// Something the trace shows changed that is not in `edits` or `settings` (a new time, a
    /// new reference): restart_if_due() restarts the trace.
    void mark_edited() { trace.mark_edited(); }
    /// An edit waits for the restart: one marked, a new size, or `edits` or a setting the trace
    /// uses changed since the last restart.
    bool edit_pending() const;
    /// The trace's size in pixels (from the pane's size and the resolution scale); the
    /// compared image's size while comparing (compare_with()).
    void set_trace_size(int w, int h);
    /// The scene has no lights and the headlight is on: the trace and the preview are lit by
    /// headlight_desc() of the view.
    bool headlight_on() const { return settings.headlight && edits.lights.empty(); }
    /// The view becomes the scene's camera: Home returns to it and the scene saves with it.
    void set_file_camera();
    /// Picks what the view shows at (x, y) of the image, each in [0, 1) from the top left
    /// corner into ui.selection; nothing (selection.instance -1) where the ray leaves the
    /// scene. Returns whether something was picked.
    bool pick(double x, double y);
    /// The ray tree of the trace's pixel at (x, y) of the image (fractions as pick()): the
    /// sample the trace traced first there, with the trace's settings and plan, into
    /// ui.inspect (its text too). False where the scene is not open.
    bool inspect(double x, double y);
    /// The restart policy (TraceSession::due): with an edit pending, restarts once the running
    /// trace's first pass is on screen or 100 ms after the last restart, not every frame
    /// (otherwise no traced image would appear until a drag stops), and at once for a new
    /// scene. Returns whether it restarted. The trace's plan (trace.tracer.plan()) is then that
    /// of the scene shown.
    bool restart_if_due();

    // ---- undo and redo ----
    /// Once a frame: an edit made since the last step becomes an undo step once no gesture is
    /// under way (`gesture`: a mouse button held or a widget active), so a drag is one step.
    void track_history(bool gesture) { history.track(edits, settings, gesture); }
    /// The settings the viewer starts with (the command line's): not an undo step.
    void start_with(const ViewSettings& initial);
    /// Back to the state before the last step (the current one goes to redo), or forward again.
    /// False when there is nothing to undo or redo. Opening a file starts a new history.
    bool undo();
    bool redo();

private:
    UndoState m_traced;  // the edits and settings of the last restart (edit_pending() compares)
};

/// The status bar's text: samples per pixel, rays per second, the estimated error and the time
/// to the target error (or when it was reached), the first (coarse) and first full-resolution
/// pass times, the headlight.
std::string status_text(const ViewerState& v);

}  // namespace rt::view
