#include "state/viewer.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include "rt/compile/compile.h"
#include "rt/render/inspect.h"
#include "rt/util/threads.h"
#include "state/viewer_compare.h"

namespace rt::view {

namespace {

// The edits and the settings the trace uses alike: a change of the others (the exposure, the
// layout, the panel) restarts nothing.
bool same_for_trace(const ViewerState& v, const UndoState& b) {
    const ViewSettings &x = v.settings, &y = b.settings;
    RenderSettings r = x.render;
    r.width = y.render.width;  // the trace's size: set at the restart (set_trace_size)
    r.height = y.render.height;
    return r == y.render && x.target_spp == y.target_spp && x.target_error == y.target_error &&
           x.resolution_scale == y.resolution_scale && x.headlight == y.headlight &&
           same_edits(v.edits, b.edits);
}

UndoState current_state(const ViewerState& v) { return {v.edits, v.settings}; }
void reset_history(ViewerState& v) { v.history.reset(current_state(v)); }

// A scene opened: the edits start from the file's camera, lights and materials.
void on_loaded(ViewerState& v) {
    LoadedScene& s = *v.session.loaded;
    v.trace.tracer.stop();
    v.edits.camera.set_from(s.file_camera, s.scene.world_bounds);
    v.edits.lights = s.desc.lights;
    v.edits.light_on.assign(v.edits.lights.size(), 1);
    v.edits.materials = s.file_materials;
    s.file_time = file_time(s.path);
    v.mark_edited();
    reset_history(v);
    if (v.hooks.on_opened) v.hooks.on_opened(s.path);
}

void restore(ViewerState& v, const UndoState& s) {
    const ViewSettings window = v.settings;
    v.edits = s.edits;
    v.settings = s.settings;
    keep_window_settings(&v.settings, window);
    v.history.settle(current_state(v));
    ++v.ui.changes;
    v.mark_edited();
}

// The second half of opening: a scene read (or the error) becomes the open one.
bool finish_open(ViewerState& v, LoadResult next, const std::string& file, bool keep_camera) {
    SceneSession& session = v.session;
    session.checker_offer = next.textures_missing ? file : "";
    if (!next.scene) {
        v.messages.fail(std::move(next.error));
        session.checker_offer_message = v.messages.serial;
        if (session.loaded)  // do not retry every frame
            session.loaded->file_time = file_time(session.loaded->path);
        return false;
    }
    const OrbitCamera kept = v.edits.camera;
    v.trace.tracer.stop();  // it traces the scene that is replaced here
    session.loaded = std::move(next.scene);
    session.loaded->id = session.next_id();
    v.messages.clear();
    session.reload_conflict.clear();
    v.ui.selection = {};
    v.ui.inspect.clear();
    v.timeline.time = 0;  // a new scene's animation starts at its beginning, paused
    v.timeline.playing = false;
    on_loaded(v);
    if (keep_camera) v.edits.camera = kept;
    session.add_recent(session.loaded->path);
    return true;
}

bool open_as(ViewerState& v, std::string file, bool keep_camera, MissingTextures missing) {
    LoadRequest request = v.session.request(file);
    request.missing = missing;
    return finish_open(v, load_scene(request), file, keep_camera);
}

// Starts jobs.loader on `request`; `reload`: its result is merged as a reload.
void load_in_background(ViewerState& v, const LoadRequest& request, bool reload) {
    v.jobs.loader.start(request);
    v.jobs.reloading = reload;
}

// A reload read: it becomes the open scene, the user's edits merged (see reload()).
bool finish_reload(ViewerState& v, LoadResult next) {
    SceneSession& session = v.session;
    // What the user edited, against the scene as it was read last (edits made while a
    // background reload ran count too).
    const ReloadMerge merge = edits_before_reload(*session.loaded, v.edits);
    const std::vector<MaterialDesc> old_file = session.loaded->file_materials,
                                    mine = v.edits.materials;
    const std::string file = session.loaded->path;  // finish_open replaces `loaded`
    const Timeline playback = v.timeline;           // a reload keeps the time and the playback
    if (!finish_open(v, std::move(next), file, false)) return false;
    v.timeline = playback;
    v.timeline.seek(v.timeline.time, v.animation_length());
    std::string both = merge_reload(merge, *session.loaded, &v.edits);
    // Material edits stay when the file still has as many materials; when the file changed
    // them too, that is said as for the lights.
    if (!same_materials(mine, old_file) && mine.size() == v.edits.materials.size()) {
        if (!same_materials(session.loaded->file_materials, old_file))
            both += both.empty() ? "materials" : " and materials";
        v.edits.materials = mine;
    }
    const std::string name = std::filesystem::path(session.loaded->path).filename().string();
    session.reload_conflict.clear();
    if (!both.empty())
        session.reload_conflict = name + " changed its " + both +
                                  " on disk, which you had edited: " + "your edits are kept.";
    else if (merge.camera_edited || merge.lights_edited)
        v.messages.note("reloaded " + name + "; your edits are kept");
    return true;
}

// The joints to the timeline's time (the trace renders its own copy, made at the restart).
void move_joints(ViewerState& v) {
    LoadedScene& s = *v.session.loaded;
    if (!s.scene.rig.animated()) return;
    const SceneTime t = v.timeline.scene_time();
    if (s.scene.time == t) return;
    Diagnostics diag;
    try {
        animate(s.scene, s.desc, t, &diag);
    } catch (const SceneError& e) {  // the scene stays at the time it held
        v.timeline.playing = false;
        v.messages.fail(e.what());
        return;
    }
    v.ui.selection = {};  // its instance and box were those of the time before
    // A joint singular at this time: said once until the time leaves it.
    std::string warning = diag.warnings().empty() ? "" : diag.warnings()[0].message;
    if (!warning.empty() && warning != v.timeline.joint_warning) v.messages.note(warning);
    v.timeline.joint_warning = warning;
}

// The edits compiled into the scene (the preview's overlays show the same lights), and the
// trace restarted on a copy of it.
void restart(ViewerState& v) {
    LoadedScene& s = *v.session.loaded;
    move_joints(v);
    apply_edits(v.edits, s.material_origins, v.headlight_on(), v.trace.width(), v.trace.height(),
                &s.scene, &v.settings.render);
    CompareView& c = v.ui.compare;
    c.current = false;
    if (c.active())  // the reference: raytrace's image at the compared image's size
        v.trace.restart(s.scene, v.settings.render, c.spp, 0, s.id, true);
    else
        v.trace.restart(s.scene, v.settings.render, v.settings.target_spp, v.settings.target_error,
                        s.id);
}

}  // namespace

ViewerState::ViewerState(const std::string& path, bool print_left_out, MissingTextures missing,
                         std::optional<Dialect> file_dialect) {
    session.missing_textures = missing;
    session.dialect = file_dialect;
    trace.print_left_out = print_left_out;
    // The trace takes every core, at a lower priority than the interface (Tracer::run), so
    // frames stay smooth.
    settings.render.threads = resolve_thread_count(0);
    LoadResult r = load_scene(session.request(path));
    session.loaded = std::move(r.scene);
    messages.text = std::move(r.error);
    ++messages.serial;
    if (r.textures_missing) session.checker_offer = path;
    session.checker_offer_message = messages.serial;
    reset_history(*this);
    if (!session.loaded) {  // keeps running with the message shown, and watches the file
        messages.is_error = true;
        ++messages.failures;
        session.watched = path;
        session.watched_time = file_time(path);
        return;
    }
    session.loaded->id = session.next_id();
    session.add_recent(session.loaded->path);
    on_loaded(*this);
}

void ViewerState::start_with(const ViewSettings& initial) {
    settings = initial;
    if (session.loaded) mark_edited();
    reset_history(*this);
}

bool ViewerState::undo() {
    track_history(false);  // an edit not yet a step becomes one first
    UndoState back;
    if (!history.undo(current_state(*this), &back)) return false;
    restore(*this, back);
    return true;
}

bool ViewerState::redo() {
    track_history(false);
    UndoState forward;
    if (!history.redo(current_state(*this), &forward)) return false;
    restore(*this, forward);
    return true;
}

bool ViewerState::open(std::string file, bool keep_camera) {
    return open_as(*this, std::move(file), keep_camera, session.missing_textures);
}

bool ViewerState::open_with_checker() {
    if (session.checker_offer.empty()) return false;
    // Asked once a session: the files opened after this one open the same way.
    session.missing_textures = MissingTextures::Checker;
    return open_as(*this, session.checker_offer, false, MissingTextures::Checker);
}

void ViewerState::open_in_background(std::string file) {
    load_in_background(*this, session.request(file), false);
    messages.note("loading " + file + " ...");
}

void ViewerState::cancel_loading() {
    if (!jobs.loader.busy()) return;
    messages.note("cancelled loading " + jobs.loader.path() + "; the open scene stays");
    jobs.loader.cancel();
}

bool ViewerState::reload() {
    if (!session.loaded) return false;
    return finish_reload(*this, load_scene(session.reload_request()));
}

void ViewerState::use_file_edits() {
    if (!session.loaded) return;
    const LoadedScene& s = *session.loaded;
    edits.camera.set_from(s.file_camera, s.scene.world_bounds);
    edits.lights = s.desc.lights;
    edits.light_on.assign(edits.lights.size(), 1);
    edits.materials = s.file_materials;
    session.reload_conflict.clear();
    mark_edited();
}

void ViewerState::poll_files() {
    std::string result;
    bool ok = false;
    if (jobs.image.take_result(&result, &ok)) {
        ok ? messages.note(result) : messages.fail(result);
        if (ok && hooks.on_saved && !jobs.image_path.empty()) hooks.on_saved(jobs.image_path);
    }
    take_compare_image(*this);
    LoadResult next;
    std::string loaded_file;
    if (jobs.loader.take(&next, &loaded_file)) {
        if (jobs.reloading && session.loaded && loaded_file == session.loaded->path)
            finish_reload(*this, std::move(next));
        else
            finish_open(*this, std::move(next), loaded_file, false);
        jobs.reloading = false;
    }
    if (!ui.dropped.empty()) {  // the window stays interactive while it loads
        // An image dropped is compared with the trace; a scene opens.
        const std::string file = ui.dropped.back();
        ui.dropped.clear();
        if (is_image_path(file))
            compare_in_background(*this, file);
        else
            open_in_background(file);
    }
    if (!session.check_due()) return;
    LoadedScene* s = session.loaded.get();
    if (s && !jobs.loader.busy() && file_time(s->path) != s->file_time) {
        s->file_time = file_time(s->path);                          // once per change
        load_in_background(*this, session.reload_request(), true);  // the open scene stays
                                                                    // interactive meanwhile
    }
    if (!session.loaded && !session.watched.empty() &&
        file_time(session.watched) != session.watched_time) {
        session.watched_time = file_time(session.watched);  // the file that failed at start-up,
        open(session.watched, false);                       // fixed?
    }
}

void ViewerState::set_file_camera() {
    session.loaded->file_camera = edits.camera.desc();
    session.loaded->desc.camera = session.loaded->file_camera;
    messages.note("the view is the scene's camera now (Save scene writes it)");
}

bool ViewerState::pick(double x, double y) {
    ui.selection = {};
    ++ui.changes;  // the highlight changes
    if (!session.loaded) return false;
    ui.selection = pick_at(*session.loaded, edits.camera, trace.width(), trace.height(), x, y);
    return ui.selection.instance >= 0;
}

bool ViewerState::inspect(double x, double y) {
    if (!session.loaded) return false;
    const int w = trace.width(), h = trace.height();
    if (w <= 0 || h <= 0) return false;
    const int px = std::clamp(static_cast<int>(x * w), 0, w - 1);
    const int py = std::clamp(static_cast<int>(y * h), 0, h - 1);
    const LoadedScene& s = *session.loaded;
    const RenderScene* traced = trace.traced(s.id);
    if (!traced) return false;  // not traced yet
    // The trace's settings as its passes use them (tracer.cpp: every sample jittered; the
    // reference of a comparison samples as raytrace does, the pixel centre first).
    RenderSettings r = settings.render;
    r.width = w;
    r.height = h;
    r.centre_first_sample = ui.compare.active();
    InspectView& in = ui.inspect;
    // The panel lays the tree out as nodes every frame: a smaller tree than raytrace's, which
    // still says how many rays it left out (raytrace --inspect gives the whole 4096).
    in.tree = inspect_pixel(*traced, make_render_plan(*traced, r), r, px, py, 0, 1,
                            InspectLimits{512, 8192});
    in.text = inspect_text(*in.tree, *traced, {&s.desc, &s.prim_locs, &s.material_names});
    const Image& shown = trace.last_trace;
    in.traced = shown.width == w && shown.height == h ? shown.at(px, py) : Vec3(0.0);
    in.traced_spp = shown.width == w && shown.height == h ? trace.tracer.status().spp : 0;
    in.hovered = -1;
    ++in.version;
    ++ui.changes;
    return true;
}

bool ViewerState::restart_if_due() {
    if (!session.loaded || trace.width() <= 0 || trace.height() <= 0)
        return false;                        // no pane to trace for yet
    if (!same_for_trace(*this, m_traced)) {  // an edit marks itself
        mark_edited();
        m_traced = current_state(*this);
    }
    if (trace.edit_pending()) ++ui.changes;  // the panes follow every frame
    if (!trace.due(session.loaded->id)) return false;
    restart(*this);
    m_traced = current_state(*this);
    return true;
}

void ViewerState::set_trace_size(int w, int h) {
    const CompareView& c = ui.compare;
    if (c.active())
        trace.set_size(c.theirs.width, c.theirs.height);
    else
        trace.set_size(w, h);
}

double ViewerState::animation_length() const {
    return session.loaded ? view::animation_length(session.loaded->desc) : 0.0;
}

void ViewerState::step_animation(double frame_s) {
    if (!session.loaded) return;
    if (timeline.advance(frame_s, animation_length())) mark_edited();
    move_joints(*this);  // the preview follows every frame, the trace at its restart
}

void ViewerState::seek(double t) {
    timeline.seek(t, animation_length());
    mark_edited();
}

bool ViewerState::edit_pending() const {
    return trace.edit_pending() || (session.loaded && !same_for_trace(*this, m_traced));
}

std::string status_text(const ViewerState& v) {
    const Tracer::Status st = v.trace.tracer.status();
    auto ms = [](double x) { return x < 0 ? std::string("...") : std::to_string(int(x)) + " ms"; };
    char head[160];
    std::snprintf(head, sizeof head, "%d spp | %.2f Mray/s | relMSE ", st.spp,
                  st.rays_per_second / 1e6);
    std::string s = head;
    // The estimate needs two samples per pixel: "..." until then, not a misleading 0.
    if (st.estimate > 0) {
        char e[32];
        std::snprintf(e, sizeof e, "%.3g", st.estimate);
        s += e;
    } else {
        s += "...";
    }
    if (st.target_error > 0) {
        char target[120];
        if (st.reached)
            std::snprintf(target, sizeof target, " | target %.3g reached at %.1f s",
                          st.target_error, st.target_seconds);
        else if (st.target_seconds >= 0 && st.target_seconds - st.seconds > 3600)
            std::snprintf(target, sizeof target, " | target %.3g in > 1 h", st.target_error);
        else if (st.target_seconds >= 0)
            std::snprintf(target, sizeof target, " | target %.3g in ~%.1f s", st.target_error,
                          std::max(0.0, st.target_seconds - st.seconds));
        else
            std::snprintf(target, sizeof target, " | target %.3g in ... (estimating)",
                          st.target_error);
        s += target;
    }
    // The trace's size: the resolution setting while the view changes, full once still.
    char size[80];
    const bool full = v.trace.seconds_since_edit() > 0.5 || v.settings.resolution_scale >= 1.0f;
    if (full)
        std::snprintf(size, sizeof size, " | %dx%d (full)", v.trace.width(), v.trace.height());
    else
        std::snprintf(size, sizeof size, " | %dx%d (%.2g while editing)", v.trace.width(),
                      v.trace.height(), static_cast<double>(v.settings.resolution_scale));
    s += size;
    s += " | first pass " + ms(v.trace.first_pass_ms) + ", full resolution " +
         ms(v.trace.first_full_ms);
    if (v.headlight_on()) s += " | headlight: the scene has no lights";
    if (v.ui.compare.active()) s += " | " + compare_status(v.ui.compare);
    return s;
}

}  // namespace rt::view
