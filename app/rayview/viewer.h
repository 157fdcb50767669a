// The viewer's state without any window or GL: the open scene (its description and what it
// compiled to), the user's edits to it, the settings, and the progressive trace. Every edit is
// marked with mark_edited(); restart_if_due() then takes the one restart path: stop the trace,
// apply the edits to the compiled scene, start again (yocto-gl's reset_display()).
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "camera_controller.h"
#include "image_job.h"
#include "loader.h"
#include "preview_geometry.h"
#include "rt/compile/render_scene.h"
#include "rt/format/parser.h"
#include "rt/image/image.h"
#include "rt/render/render.h"
#include "rt/scene/scene_desc.h"
#include "timeline.h"
#include "tracer.h"

namespace rt::view {

/// What a click picked: the primitive under the pixel and what the panel says about it.
struct Selection {
    int instance = -1;  // -1: nothing
    uint32_t prim = 0;
    Bounds3 bounds;                      // world bounds of the primitive (a CSG node's whole tree)
    Vec3 point{0.0};                     // where the ray met it
    std::string shape, material, where;  // "sphere"; "glass (material 3)"; "file:line:col"
    std::string groups;                  // its file and groups: "pawn.ray > group at line 3 > ..."
};

/// The user's edits, on the description side: the camera and every light, on or off.
struct SceneEdits {
    OrbitCamera camera;
    std::vector<LightDesc> lights;
    std::vector<char> light_on;
};

/// What the user sets: the renderer's settings and the viewer's own knobs.
struct ViewSettings {
    RenderSettings render;
    int target_spp = 256;
    float target_error = 1e-4f;     // the trace stops at this estimated relMSE too (0: never)
    float resolution_scale = 0.5f;  // trace pixels per pane pixel
    bool show_lights = true;        // light markers over the preview
    int box_depth = 0;              // BVH levels drawn over the preview, 0 = off
    int group_depth = 0;            // scene graph group levels drawn over it, 0 = off
    int layout = 0;                 // 0 both panes, 1 preview alone, 2 trace alone
    bool show_panel = true;         // the control panel left of the panes
    float panel_w = 380;            // its width in pixels (the user resizes it; 0: collapsed)
    float ui_scale = 1;             // fonts and panel, times the monitor's content scale
    bool headlight = true;          // a scene without lights is lit along the view (never saved)
    // How the trace is shown and saved to 8-bit files (display only: no re-render).
    float exposure = 0;  // stops
    Tonemap tonemap = Tonemap::Clamp;
    // The render's size, as raytrace's --width and --height: both panes keep its aspect.
    int image_w = 640, image_h = 480;
    double aspect() const { return static_cast<double>(image_w) / static_cast<double>(image_h); }
    bool operator==(const ViewSettings&) const = default;
};

/// What undo and redo restore: every edit of the camera, the lights and the settings.
struct UndoState {
    SceneEdits edits;
    ViewSettings settings;
};

/// A light edit (the script's `light` command) WHAT (colour: a V0/V1 light's one colour, which sets
/// ambient 0 and diffuse = specular; ambient, diffuse, specular: one of a V3 light's colours;
/// radius: a sphere light's, a >= 0) with arguments (a, b, c). False, and `*l` unchanged, for
/// another WHAT.
bool edit_light(const std::string& what, double a, double b, double c, LightDesc* l);

/// The double a float widget's value stands for: the shortest decimal that reads back as the
/// float (0.3f gives 0.3, not 0.30000001192092896), so a saved scene holds the numbers shown.
double float_as_decimal(float f);

/// The headlight: a white directional light along the view of `camera`.
LightDesc headlight_desc(const OrbitCamera& camera);

/// Without a display: the same renderer, headless (`spp` samples per pixel, `settings`' size),
/// to SCENE.png in the working directory. Returns the exit code.
int render_headless(const std::string& path, MissingTextures missing = MissingTextures::Error,
                    const RenderSettings& settings = {}, int spp = 16,
                    std::optional<Dialect> dialect = std::nullopt);

struct ViewerState {
    using Clock = std::chrono::steady_clock;

    /// Opens `path`; on an error the message is kept in `message`. `print_left_out`: print the
    /// features the renderer leaves out at the first restart (for --frames runs).
    /// `missing`: how every file opens (--missing-textures).
    ViewerState(const std::string& path, bool print_left_out,
                MissingTextures missing = MissingTextures::Error,
                std::optional<Dialect> file_dialect = std::nullopt);
    ~ViewerState();
    ViewerState(const ViewerState&) = delete;
    ViewerState& operator=(const ViewerState&) = delete;

    // ---- the scene file ----
    /// Opens a file; on an error the message is shown and the previous scene stays.
    bool open(std::string file, bool keep_camera);  // by value: callers pass loaded->path
    /// Opens a file on a background thread (the open scene stays interactive; poll_files()
    /// takes the result); a load under way is cancelled first.
    void open_in_background(std::string file);
    /// Drops the load under way: the open scene stays.
    void cancel_loading();
    SceneLoader loader;
    /// Opens `checker_offer` with checker stand-ins for its missing textures.
    bool open_with_checker();
    /// Reads the open file again and keeps the user's edits: the camera and the lights as edited
    /// stay, the file's new ones are taken where the user edited nothing. When the file changed
    /// what the user had edited, the edits stay and `reload_conflict` says so, with the choice
    /// use_file_edits(). False (and nothing changed) when the file no longer opens.
    bool reload();
    /// Drops the kept edits the last reload() reported in `reload_conflict`: the file's camera
    /// and lights.
    void use_file_edits();
    /// reload() on the loader's thread: the open scene stays interactive; poll_files() merges.
    void reload_in_background();
    /// Takes finished background work (an image, a load or a reload), opens the last file
    /// dropped onto the window, and reloads the open file in the background when it changed on
    /// disk (its time is checked twice a second, not every frame).
    void poll_files();
    /// The description with the viewer's camera and lights, as a .ray file. Throws.
    void save_scene(const std::string& path) const;
    /// The latest traced image: 8-bit formats with the exposure and tonemap shown, PFM linear.
    /// Throws.
    void save_trace(const std::string& path) const;
    /// The latest trace as shown: exposure and tonemap applied.
    Image displayed_trace() const;
    /// Renders the scene as edited at `width` x `height` and `spp` in the background (image_job)
    /// and writes it to `path` with the display's exposure and tonemap (PFM linear); the panel
    /// says when it is done. The interactive trace goes on.
    void render_image(const std::string& path, int width, int height, int spp);
    /// The animation rendered as render_image() renders an image: `frames` frames from time 0
    /// at the timeline's fps, interpolation and rotation, to `pattern` (a %d pattern, as
    /// raytrace --frames), encoded to `video` too when it is not empty (needs ffmpeg).
    void render_animation(const std::string& pattern, int frames, int width, int height, int spp,
                          const std::string& video = "");
    ImageJob image_job;

    // ---- animation ----
    /// The joints' time, playback and choices; restart() moves the joints to its time.
    Timeline timeline;
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
    void mark_edited() { m_edited = true; }
    bool edit_pending() const { return m_edited; }
    /// The trace's size in pixels (from the pane's size and the resolution scale).
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
    /// corner; nothing (selection.instance -1) where the ray leaves the scene. Returns whether
    /// something was picked.
    bool pick(double x, double y);
    /// Turns the view to light i: a point, spot or sphere light at the centre of the view, a
    /// directional light's direction as the view direction.
    void frame_light(size_t i);
    Selection selection;
    void remove_light(size_t i);
    /// The restart policy: with an edit pending, restarts once the running trace's first pass is
    /// on screen or 100 ms after the last restart, not every frame (otherwise no traced image
    /// would appear until a drag stops), and at once for a new scene. Returns whether it
    /// restarted. The trace's plan (tracer.plan()) is then that of the scene shown.
    bool restart_if_due();
    /// Takes the trace's latest image into `last_trace`; false when there is none new.
    bool take_trace_image();
    /// Less than a quarter second since the last restart: the view is moving.
    bool moving() const;

    // ---- undo and redo ----
    /// Once a frame: an edit made since the last step becomes an undo step once no gesture is
    /// under way (`gesture`: a mouse button held or a widget active), so a drag is one step.
    void track_history(bool gesture);
    /// The settings the viewer starts with (the command line's): not an undo step.
    void start_with(const ViewSettings& initial);
    /// Back to the state before the last step (the current one goes to redo), or forward again.
    /// False when there is nothing to undo or redo. Opening a file starts a new history.
    bool undo();
    bool redo();
    size_t undo_steps() const { return m_undo.size(); }
    size_t redo_steps() const { return m_redo.size(); }

    std::unique_ptr<LoadedScene> loaded;  // null until a file opens
    SceneEdits edits;
    ViewSettings settings;
    /// The panel's message line: an error (also printed to stderr) or a note ("saved ...").
    void fail(std::string text);
    void note(std::string text);
    std::string message;  // the last error or note shown in the panel
    bool message_is_error = false;
    /// Errors so far (fail(), and a scene that did not open at start-up): a scripted run
    /// (--frames, --script, --screenshot) that had any exits 1.
    int failures = 0;
    std::string checker_offer;    // a file that failed to open for its textures only, else ""
    std::string reload_conflict;  // a reload kept edits of what the file changed too, else ""
    MissingTextures missing_textures = MissingTextures::Error;  // how files open
    std::optional<Dialect> dialect;   // --dialect: every file opens in it (else detected)
    std::vector<std::string> recent;  // files opened (absolute), most recent first, at most 8
    /// Adds files opened in earlier runs after this run's (those that still exist).
    void remember_recent(const std::vector<std::string>& files);
    std::vector<OrbitCamera> bookmarks;  // views the user kept
    bool show_help = false;              // the shortcuts overlay
    std::vector<std::string> dropped;    // files dropped onto the window, picked up by poll_files
    /// Called with each file the viewer saves (a scene, a trace, a rendered image); the web
    /// page downloads it. Nothing on the desktop.
    std::function<void(const std::string& path)> on_saved;
    /// Called with each scene file that opens (at start, an open, a drop, a reload); the web
    /// page makes its folder the working directory. Nothing on the desktop.
    std::function<void(const std::string& path)> on_opened;

    Tracer tracer;  // after `loaded`: stops before the scene it traces dies
    Image last_trace;
    std::vector<std::string> explained;  // the running trace's plan.reasons
    bool preview_stale = true;           // an edit the preview has not drawn yet
    double first_pass_ms =
        -1;  // edit -> first traced image (the coarse pass) on screen; -1: waiting
    double first_full_ms = -1;  // edit -> first full-resolution pass on screen; -1: waiting
    std::vector<double> first_pass_samples;  // every first_pass_ms, for the --frames summary
    std::vector<double> first_full_samples;  // every first_full_ms

private:
    bool open_as(std::string file, bool keep_camera, MissingTextures missing);
    /// The second half of opening: a scene read (or the error) becomes the open one.
    bool finish_open(LoadResult next, const std::string& file, bool keep_camera);
    /// A reload read: it becomes the open scene, the user's edits merged (see reload()).
    bool finish_reload(LoadResult next);
    /// Starts `loader` on `file`; `reload`: its result is merged as a reload.
    void load_in_background(const LoadRequest& request, bool reload);
    bool m_reloading = false;   // the loader's job is a reload of the open file
    std::string m_render_path;  // the image the background job writes ("" for an animation)
    void on_loaded();
    void restart();
    void move_joints();
    void start_render(const std::string& path, int width, int height, int spp,
                      const SequenceSpec& sequence);
    std::string m_joint_warning;  // the last singular-joint warning noted
    UndoState current_state() const { return {edits, settings}; }
    void restore(const UndoState& s);
    void reset_history();

    bool m_edited = true;
    bool m_print_left_out = false;
    int m_trace_w = 0, m_trace_h = 0;
    int m_scenes_opened = 0;
    int m_traced_id = -1;                                  // LoadedScene::id the trace started on
    bool m_input_pending = false;                          // an edit waits for the restart policy
    Clock::time_point m_input_time = Clock::now();         // the first edit since the restart
    Clock::time_point m_served_input_time = m_input_time;  // the edit the running trace answers
    Clock::time_point m_change_time{};                     // the last restart
    Clock::time_point m_last_check = Clock::now();         // the file's time was read
    std::vector<UndoState> m_undo, m_redo;
    UndoState m_committed;  // the state the last undo step ends in
    std::string m_watched;  // the file that failed to open at start-up, while none is open
    std::filesystem::file_time_type m_watched_time;
};

/// The status bar's text: samples per pixel, rays per second, the estimated error and the time
/// to the target error (or when it was reached), the first (coarse) and first full-resolution
/// pass times, the headlight.
std::string status_text(const ViewerState& v);

}  // namespace rt::view
