// The viewer's state without any window or GL, composed of parts with one job each: the open
// scene and its file (SceneSession), the user's edits and settings (edits.h), the progressive
// trace (TraceSession), undo and redo (History), the background jobs (Jobs), the panel's
// messages (Messages), the window's own state (ViewUi) and the web page's hooks (PageHooks).
// ViewerState keeps the operations that span them. Every edit is marked with mark_edited();
// restart_if_due() then takes the one restart path: stop the trace, apply the edits to the
// compiled scene, start again (yocto-gl's reset_display()).
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
    ~ViewerState();
    ViewerState(const ViewerState&) = delete;
    ViewerState& operator=(const ViewerState&) = delete;

    SceneSession session;  // before `trace`: the trace stops before the scene it traces dies
    SceneEdits edits;
    ViewSettings settings;
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
    /// reload() on the loader's thread: the open scene stays interactive; poll_files() merges.
    void reload_in_background();
    /// Takes finished background work (an image, a load or a reload), opens the last file
    /// dropped onto the window, and reloads the open file in the background when it changed on
    /// disk (its time is checked twice a second, not every frame).
    void poll_files();
    /// The description with the viewer's camera, lights and materials, as a .ray file. The
    /// materials of included files are written into those files only with `included_too`:
    /// each edited #material directive replaced in place, every other byte kept; every text is
    /// made before any file is written, so an error (a file changed since it was read) writes
    /// nothing. Throws.
    void save_scene(const std::string& path, bool included_too = false) const;
    /// The included files (as resolved) whose materials differ from the file's.
    std::vector<std::string> edited_included_files() const;
    /// The latest traced image: 8-bit formats with the exposure and tonemap shown, PFM linear.
    /// Throws.
    void save_trace(const std::string& path) const;
    /// The latest trace as shown: exposure and tonemap applied.
    Image displayed_trace() const;
    /// Renders the scene as edited at `width` x `height` and `spp` in the background
    /// (jobs.image) and writes it to `path` with the display's exposure and tonemap (PFM
    /// linear); the panel says when it is done. The interactive trace goes on.
    void render_image(const std::string& path, int width, int height, int spp);
    /// The animation rendered as render_image() renders an image: `frames` frames from time 0
    /// at the timeline's fps, interpolation and rotation, to `pattern` (a %d pattern, as
    /// raytrace --frames), encoded to `video` too when it is not empty (needs ffmpeg).
    void render_animation(const std::string& pattern, int frames, int width, int height, int spp,
                          const std::string& video = "");

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
    /// Something the trace shows changed: restart_if_due() restarts the trace.
    void mark_edited() { trace.mark_edited(); }
    bool edit_pending() const { return trace.edit_pending(); }
    /// The trace's size in pixels (from the pane's size and the resolution scale); the
    /// compared image's size while comparing (compare_with()).
    void set_trace_size(int w, int h);
    /// A new light of `kind` at the eye, along the view (a spot's cone 0.5 rad).
    void add_light(LightKind kind);
    /// The scene has no lights and the headlight is on: the trace and the preview are lit by
    /// headlight_desc() of the view.
    bool headlight_on() const { return settings.headlight && edits.lights.empty(); }
    /// Keeps the headlight as a light of the scene (saved with it).
    void keep_headlight();
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
    /// Drops the tree (its lines and the panel's list).
    void clear_inspect();
    /// Turns the view to light i: a point, spot or sphere light at the centre of the view, a
    /// directional light's direction as the view direction.
    void frame_light(size_t i);
    void remove_light(size_t i);
    /// The restart policy (TraceSession::due): with an edit pending, restarts once the running
    /// trace's first pass is on screen or 100 ms after the last restart, not every frame
    /// (otherwise no traced image would appear until a drag stops), and at once for a new
    /// scene. Returns whether it restarted. The trace's plan (trace.tracer.plan()) is then that
    /// of the scene shown.
    bool restart_if_due();

    // ---- comparison with an image (ui.compare) ----
    /// Compares the trace with the image at `path` (a student's render): the trace switches to
    /// the image's size and the file's camera and renders the reference there as raytrace does
    /// (ui.compare.spp samples, the spec's sampling); take_trace() compares once it is done. On
    /// an error (a file that cannot be read) the message is shown and the previous comparison
    /// stays.
    bool compare_with(const std::string& path);
    /// The same with the image read off the interface thread (CompareLoader): the comparison
    /// starts in poll_files() once it is read, or its error is shown. The panel and a dropped
    /// image go this way; compare_with() serves the command line and scripts, which wait.
    void compare_in_background(const std::string& path);
    /// Back to the progressive trace of the pane's size.
    void stop_compare();
    /// Takes the trace's latest image (TraceSession::take_image) and, while comparing, compares
    /// the reference with the image once it is done. False when there is no new image.
    bool take_trace();

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
    bool open_as(std::string file, bool keep_camera, MissingTextures missing);
    /// The second half of opening: a scene read (or the error) becomes the open one.
    bool finish_open(LoadResult next, const std::string& file, bool keep_camera);
    /// A reload read: it becomes the open scene, the user's edits merged (see reload()).
    bool finish_reload(LoadResult next);
    /// Starts jobs.loader on `request`; `reload`: its result is merged as a reload.
    void load_in_background(const LoadRequest& request, bool reload);
    void on_loaded();
    void restart();
    void move_joints();
    bool start_render(const std::string& path, int width, int height, int spp,
                      const SequenceSpec& sequence);
    void start_compare(const std::string& path, Image theirs);
    void take_compare_image();
    UndoState current_state() const { return {edits, settings}; }
    void restore(const UndoState& s);
    void reset_history() { history.reset(current_state()); }
    std::string m_joint_warning;  // the last singular-joint warning noted
};

/// The status bar's text: samples per pixel, rays per second, the estimated error and the time
/// to the target error (or when it was reached), the first (coarse) and first full-resolution
/// pass times, the headlight.
std::string status_text(const ViewerState& v);

}  // namespace rt::view
