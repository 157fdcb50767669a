#include "state/viewer.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include "frames.h"
#include "rt/compile/compile.h"
#include "rt/format/writer.h"
#include "rt/render/inspect.h"
#include "rt/util/file_io.h"
#include "rt/util/limits.h"
#include "rt/util/threads.h"

namespace rt::view {

namespace {

// The edits into the compiled scene, while no trace runs: the camera, the lights that are on
// (compiled from their descriptions) or the headlight, and the trace's size.
void apply_edits(const SceneEdits& edits, bool headlight, int trace_w, int trace_h,
                 RenderScene* scene, RenderSettings* settings) {
    scene->camera = compile_camera(edits.camera.desc());
    scene->lights.clear();
    for (size_t i = 0; i < edits.lights.size(); ++i)
        if (edits.light_on[i]) scene->lights.push_back(compile_light(edits.lights[i]));
    if (headlight) scene->lights.push_back(compile_light(headlight_desc(edits.camera)));
    if (edits.materials.size() == scene->materials.size()) scene->materials = edits.materials;
    settings->width = trace_w;
    settings->height = trace_h;
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
    reset_history();
    if (!session.loaded) {  // keeps running with the message shown, and watches the file
        messages.is_error = true;
        ++messages.failures;
        session.watched = path;
        session.watched_time = file_time(path);
        return;
    }
    session.loaded->id = session.next_id();
    session.add_recent(session.loaded->path);
    on_loaded();
}

ViewerState::~ViewerState() { trace.tracer.stop(); }

void ViewerState::on_loaded() {
    LoadedScene& s = *session.loaded;
    trace.tracer.stop();
    std::printf("rayview: opened %s\n", s.path.c_str());
    edits.camera.set_from(s.file_camera, s.scene.world_bounds);
    edits.lights = s.desc.lights;
    edits.light_on.assign(edits.lights.size(), 1);
    edits.materials = s.file_materials;
    s.file_time = file_time(s.path);
    mark_edited();
    reset_history();
    if (hooks.on_opened) hooks.on_opened(s.path);
}

void ViewerState::start_with(const ViewSettings& initial) {
    settings = initial;
    if (session.loaded) mark_edited();
    reset_history();
}

void ViewerState::restore(const UndoState& s) {
    const ViewSettings window = settings;
    edits = s.edits;
    settings = s.settings;
    keep_window_settings(&settings, window);
    history.settle(current_state());
    ui.preview_stale = true;
    mark_edited();
}

bool ViewerState::undo() {
    track_history(false);  // an edit not yet a step becomes one first
    UndoState back;
    if (!history.undo(current_state(), &back)) return false;
    restore(back);
    return true;
}

bool ViewerState::redo() {
    track_history(false);
    UndoState forward;
    if (!history.redo(current_state(), &forward)) return false;
    restore(forward);
    return true;
}

bool ViewerState::open(std::string file, bool keep_camera) {
    return open_as(std::move(file), keep_camera, session.missing_textures);
}

bool ViewerState::open_with_checker() {
    if (session.checker_offer.empty()) return false;
    // Asked once a session: the files opened after this one open the same way.
    session.missing_textures = MissingTextures::Checker;
    return open_as(session.checker_offer, false, MissingTextures::Checker);
}

bool ViewerState::open_as(std::string file, bool keep_camera, MissingTextures missing) {
    LoadRequest request = session.request(file);
    request.missing = missing;
    return finish_open(load_scene(request), file, keep_camera);
}

void ViewerState::load_in_background(const LoadRequest& request, bool reload) {
    jobs.loader.start(request);
    jobs.reloading = reload;
}

void ViewerState::open_in_background(std::string file) {
    load_in_background(session.request(file), false);
    messages.note("loading " + file + " ...");
}

void ViewerState::cancel_loading() {
    if (!jobs.loader.busy()) return;
    messages.note("cancelled loading " + jobs.loader.path() + "; the open scene stays");
    jobs.loader.cancel();
}

bool ViewerState::finish_open(LoadResult next, const std::string& file, bool keep_camera) {
    session.checker_offer = next.textures_missing ? file : "";
    if (!next.scene) {
        messages.fail(std::move(next.error));
        session.checker_offer_message = messages.serial;
        if (session.loaded)  // do not retry every frame
            session.loaded->file_time = file_time(session.loaded->path);
        return false;
    }
    const OrbitCamera kept = edits.camera;
    trace.tracer.stop();  // it traces the scene that is replaced here
    session.loaded = std::move(next.scene);
    session.loaded->id = session.next_id();
    messages.clear();
    session.reload_conflict.clear();
    ui.selection = {};
    clear_inspect();
    timeline.time = 0;  // a new scene's animation starts at its beginning, paused
    timeline.playing = false;
    on_loaded();
    if (keep_camera) edits.camera = kept;
    session.add_recent(session.loaded->path);
    return true;
}

bool ViewerState::reload() {
    if (!session.loaded) return false;
    return finish_reload(load_scene(session.reload_request()));
}

void ViewerState::reload_in_background() {
    if (session.loaded) load_in_background(session.reload_request(), true);
}

bool ViewerState::finish_reload(LoadResult next) {
    // What the user edited, against the scene as it was read last (edits made while a
    // background reload ran count too).
    const ReloadMerge merge = edits_before_reload(*session.loaded, edits);
    const std::vector<Material> old_file = session.loaded->file_materials, mine = edits.materials;
    const std::string file = session.loaded->path;  // finish_open replaces `loaded`
    const Timeline playback = timeline;             // a reload keeps the time and the playback
    if (!finish_open(std::move(next), file, false)) return false;
    timeline = playback;
    timeline.seek(timeline.time, animation_length());
    std::string both = merge_reload(merge, *session.loaded, &edits);
    // Material edits stay when the file still has as many materials; when the file changed
    // them too, that is said as for the lights.
    if (!same_materials(mine, old_file) && mine.size() == edits.materials.size()) {
        if (!same_materials(session.loaded->file_materials, old_file))
            both += both.empty() ? "materials" : " and materials";
        edits.materials = mine;
    }
    const std::string name = std::filesystem::path(session.loaded->path).filename().string();
    session.reload_conflict.clear();
    if (!both.empty())
        session.reload_conflict = name + " changed its " + both +
                                  " on disk, which you had edited: " + "your edits are kept.";
    else if (merge.camera_edited || merge.lights_edited)
        messages.note("reloaded " + name + "; your edits are kept");
    return true;
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
    take_compare_image();
    LoadResult next;
    std::string loaded_file;
    if (jobs.loader.take(&next, &loaded_file)) {
        if (jobs.reloading && session.loaded && loaded_file == session.loaded->path)
            finish_reload(std::move(next));
        else
            finish_open(std::move(next), loaded_file, false);
        jobs.reloading = false;
    }
    if (!ui.dropped.empty()) {  // the window stays interactive while it loads
        // An image dropped is compared with the trace; a scene opens.
        const std::string file = ui.dropped.back();
        ui.dropped.clear();
        if (is_image_path(file))
            compare_in_background(file);
        else
            open_in_background(file);
    }
    if (!session.check_due()) return;
    LoadedScene* s = session.loaded.get();
    if (s && !jobs.loader.busy() && file_time(s->path) != s->file_time) {
        s->file_time = file_time(s->path);  // once per change
        reload_in_background();             // the open scene stays interactive meanwhile
    }
    if (!session.loaded && !session.watched.empty() &&
        file_time(session.watched) != session.watched_time) {
        session.watched_time = file_time(session.watched);  // the file that failed at start-up,
        open(session.watched, false);                       // fixed?
    }
}

std::vector<std::string> ViewerState::edited_included_files() const {
    std::vector<std::string> files;
    if (!session.loaded) return files;
    const LoadedScene& s = *session.loaded;
    if (edits.materials.size() != s.file_materials.size()) return files;
    for (size_t k = 0; k < edits.materials.size(); ++k) {
        const MaterialOrigin o = s.origin(k);
        if (o.file <= 0 || same_materials({edits.materials[k]}, {s.file_materials[k]})) continue;
        const std::string& path = s.desc.files[static_cast<size_t>(o.file)].path;
        if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
    }
    return files;
}

void ViewerState::save_scene(const std::string& path, bool included_too) const {
    const LoadedScene& s = *session.loaded;
    SceneDesc desc = s.desc;
    desc.camera = edits.camera.desc();
    desc.lights.clear();
    for (size_t i = 0; i < edits.lights.size(); ++i)
        if (edits.light_on[i]) desc.lights.push_back(edits.lights[i]);
    // The edited materials into their files' descriptions, textures as their files' indices;
    // an included file's edited directives, as text, to replace in that file.
    std::map<size_t, std::vector<std::pair<SourceLoc, std::string>>> included;
    for (size_t k = 0; k < edits.materials.size(); ++k) {
        const MaterialOrigin o = s.origin(k);
        if (o.file < 0) continue;  // the built-in default
        const Material& m = edits.materials[k];
        MaterialDesc& md =
            desc.files[static_cast<size_t>(o.file)].materials[static_cast<size_t>(o.index)];
        material_terms_into(m, &md);
        const int t = m.texture - o.first_texture;
        md.texture = m.texture >= 0 && t >= 0 && t < o.textures ? t : -1;
        if (included_too && o.file > 0 && k < s.file_materials.size() &&
            !same_materials({m}, {s.file_materials[k]}))
            included[static_cast<size_t>(o.file)].emplace_back(md.loc,
                                                               write_material(md, desc.dialect));
    }
    std::vector<std::pair<std::string, std::string>> writes{{path, write_scene_for(desc, path)}};
    for (auto& [f, changes] : included) {
        const std::string& file = desc.files[f].path;
        std::string text, why;
        if (!read_file(file, &text, &why)) throw std::runtime_error(file + ": " + why);
        writes.emplace_back(file, replace_materials(text, file, std::move(changes)));
    }
    for (const auto& [file, text] : writes)
        write_file_atomic(file, text);  // a temporary name, then renamed
    if (hooks.on_saved) hooks.on_saved(path);
}

void ViewerState::save_trace(const std::string& path) const {
    if (trace.last_trace.width == 0) throw std::runtime_error("nothing traced yet");
    save_image(holds_linear(image_format_from_path(path)) ? trace.last_trace : displayed_trace(),
               path);
    if (hooks.on_saved) hooks.on_saved(path);
}

void ViewerState::render_animation(const std::string& pattern, int frames, int width, int height,
                                   int spp, const std::string& video) {
    if (!session.loaded) return;
    try {
        rtapp::frame_path(pattern, 0);
    } catch (const std::invalid_argument& e) {
        messages.fail(std::string("render animation: ") + e.what());
        return;
    }
    SequenceSpec q;
    q.desc = std::make_shared<const SceneDesc>(session.loaded->desc);
    q.frames = frames;
    q.fps = timeline.fps;
    q.interpolation = timeline.interpolation;
    q.rotation = timeline.rotation;
    q.video = video;
    if (!start_render(pattern, width, height, spp, q)) return;
    jobs.image_path.clear();
    messages.note("rendering " + std::to_string(frames) + " frames to " + pattern + " ...");
}

void ViewerState::render_image(const std::string& path, int width, int height, int spp) {
    if (!session.loaded || !start_render(path, width, height, spp, {})) return;
    jobs.image_path = path;  // one file (an animation's frames are not handed to on_saved)
    messages.note("rendering " + path + " ...");
}

// The background job on a copy of the scene with the latest edits, at the display's settings; an
// image over --max-pixels is refused here, as raytrace refuses it, before anything is allocated.
bool ViewerState::start_render(const std::string& path, int width, int height, int spp,
                               const SequenceSpec& sequence) {
    if (const std::string e =
            image_size_error(static_cast<uint64_t>(std::max(width, 0)),
                             static_cast<uint64_t>(std::max(height, 0)), "an image");
        !e.empty()) {
        messages.fail("cannot render " + path + ": " + e);
        return false;
    }
    ImageJobSpec spec;
    spec.path = path;
    spec.width = width;
    spec.height = height;
    spec.spp = spp;
    spec.settings = settings.render;
    spec.exposure = settings.exposure;
    spec.tonemap = settings.tonemap;
    spec.sequence = sequence;
    RenderScene scene = session.loaded->scene;  // shares its sets: the copy costs the instances
    apply_edits(edits, headlight_on(), width, height, &scene, &spec.settings);
    jobs.image.start(std::move(scene), spec);
    return true;
}

Image ViewerState::displayed_trace() const {
    return display_transform(trace.last_trace, settings.exposure, settings.tonemap);
}

void ViewerState::add_light(LightKind kind) {
    // At the eye, along the view: what the user looks at is lit.
    LightDesc l;
    l.kind = kind;
    l.position = edits.camera.eye();
    l.direction = edits.camera.forward();
    if (kind == LightKind::Spot) l.cutoff_rad = 0.5;
    if (kind == LightKind::Sphere) l.radius = 0.05 * edits.camera.distance;
    edits.lights.push_back(l);
    edits.light_on.push_back(1);
    mark_edited();
}

void ViewerState::set_file_camera() {
    session.loaded->file_camera = edits.camera.desc();
    session.loaded->desc.camera = session.loaded->file_camera;
    messages.note("the view is the scene's camera now (Save scene writes it)");
}

bool ViewerState::pick(double x, double y) {
    ui.selection = {};
    ui.preview_stale = true;  // the highlight changes
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
    // The trace's settings as its passes use them (tracer.cpp: every sample jittered; the
    // reference of a comparison samples as raytrace does, the pixel centre first).
    RenderSettings r = settings.render;
    r.width = w;
    r.height = h;
    r.centre_first_sample = ui.compare.active();
    InspectView& in = ui.inspect;
    // The panel lays the tree out as nodes every frame: a smaller tree than raytrace's, which
    // still says how many rays it left out (raytrace --inspect gives the whole 4096).
    in.tree = inspect_pixel(s.scene, make_render_plan(s.scene, r), r, px, py, 0, 1,
                            InspectLimits{512, 8192});
    in.text = inspect_text(*in.tree, s.scene, {&s.desc, &s.prim_locs, &s.material_names});
    const Image& shown = trace.last_trace;
    in.traced = shown.width == w && shown.height == h ? shown.at(px, py) : Vec3(0.0);
    in.traced_spp = shown.width == w && shown.height == h ? trace.tracer.status().spp : 0;
    in.hovered = -1;
    ++in.version;
    ui.preview_stale = true;
    return true;
}

void ViewerState::clear_inspect() {
    ui.inspect.tree.reset();
    ui.inspect.text.clear();
    ui.inspect.hovered = -1;
    ++ui.inspect.version;
    ui.preview_stale = true;
}

void ViewerState::frame_light(size_t i) {
    if (i >= edits.lights.size()) return;
    const LightDesc& l = edits.lights[i];
    OrbitCamera& c = edits.camera;
    if (l.kind == LightKind::Directional) {  // look the way its light travels
        CameraDesc d = c.desc();
        d.direction = l.direction;
        if (glm::length(glm::cross(glm::normalize(d.direction), d.up)) < 1e-6)
            d.up = Vec3(1, 0, 0);  // straight up or down
        c.set_from(d, session.loaded ? session.loaded->scene.world_bounds : Bounds3{});
    } else {
        c.target = l.position;  // the light at the centre of the view
    }
    mark_edited();
}

void ViewerState::keep_headlight() {
    edits.lights.push_back(headlight_desc(edits.camera));
    edits.light_on.push_back(1);
    mark_edited();
}

void ViewerState::remove_light(size_t i) {
    edits.lights.erase(edits.lights.begin() + static_cast<long>(i));
    edits.light_on.erase(edits.light_on.begin() + static_cast<long>(i));
    mark_edited();
}

bool ViewerState::restart_if_due() {
    if (!session.loaded || trace.width() <= 0 || trace.height() <= 0)
        return false;                                   // no pane to trace for yet
    if (trace.edit_pending()) ui.preview_stale = true;  // the preview follows every frame
    if (!trace.due(session.loaded->id)) return false;
    restart();
    return true;
}

// Stop, edit, restart: the compiled scene only changes while no trace runs.
void ViewerState::restart() {
    LoadedScene& s = *session.loaded;
    trace.tracer.stop();
    move_joints();
    apply_edits(edits, headlight_on(), trace.width(), trace.height(), &s.scene, &settings.render);
    s.shown.camera = s.scene.camera;  // the preview's overlays show the same lights
    s.shown.lights = s.scene.lights;
    s.shown.materials = s.scene.materials;
    CompareView& c = ui.compare;
    c.current = false;
    if (c.active())  // the reference: raytrace's image at the compared image's size
        trace.restart(s.scene, settings.render, c.spp, 0, s.id, true);
    else
        trace.restart(s.scene, settings.render, settings.target_spp, settings.target_error, s.id);
}

void ViewerState::set_trace_size(int w, int h) {
    const CompareView& c = ui.compare;
    if (c.active())
        trace.set_size(c.theirs.width, c.theirs.height);
    else
        trace.set_size(w, h);
}

bool ViewerState::compare_with(const std::string& path) {
    Image theirs;
    try {
        theirs = read_compare_image(path);
    } catch (const std::exception& e) {
        messages.fail("cannot compare with " + path + ": " + e.what());
        return false;  // the previous comparison, if any, stays
    }
    start_compare(path, std::move(theirs));
    return true;
}

void ViewerState::compare_in_background(const std::string& path) {
    jobs.compare.start(path);
    messages.note("reading " + path + " to compare with ...");
    if (!have_threads()) take_compare_image();  // read at once: taken now; else in poll_files()
}

void ViewerState::take_compare_image() {
    std::string path, error;
    Image theirs;
    if (!jobs.compare.take(&path, &theirs, &error)) return;
    if (!error.empty())
        messages.fail("cannot compare with " + path + ": " + error);  // the previous one stays
    else
        start_compare(path, std::move(theirs));
}

void ViewerState::start_compare(const std::string& path, Image theirs) {
    CompareView& c = ui.compare;
    c.path = path;
    c.theirs = std::move(theirs);
    c.settings.linear = holds_linear(image_format_from_path(path));
    c.reference = Image();
    c.current = false;
    c.probe_x = c.probe_y = -1;
    c.recompare();
    settings.image_w = c.theirs.width;  // both panes keep its aspect
    settings.image_h = c.theirs.height;
    if (session.loaded)
        edits.camera.set_from(session.loaded->file_camera, session.loaded->scene.world_bounds);
    trace.set_size(c.theirs.width, c.theirs.height);
    mark_edited();
    messages.note("comparing with " + std::filesystem::path(path).filename().string() + " (" +
                  std::to_string(c.theirs.width) + "x" + std::to_string(c.theirs.height) +
                  "): the trace renders the reference at its size from the file's camera, " +
                  std::to_string(c.spp) + " spp as raytrace renders it");
}

void ViewerState::stop_compare() {
    if (!ui.compare.active()) return;
    const int version = ui.compare.version;  // counts on: the pane uploads the next one
    ui.compare = CompareView();
    ui.compare.version = version + 1;
    mark_edited();  // the progressive trace again, of the pane's size
}

bool ViewerState::take_trace() {
    if (!trace.take_image()) return false;
    CompareView& c = ui.compare;
    const Image& t = trace.last_trace;
    if (c.active() && !edit_pending() && t.width == c.theirs.width && t.height == c.theirs.height &&
        trace.last_spp >= c.spp) {
        c.reference = t;
        c.current = true;
        c.recompare();
    }
    return true;
}

double ViewerState::animation_length() const {
    return session.loaded ? view::animation_length(session.loaded->desc) : 0.0;
}

void ViewerState::step_animation(double frame_s) {
    if (!session.loaded) return;
    if (timeline.advance(frame_s, animation_length())) mark_edited();
    RenderScene& shown = session.loaded->shown;
    const SceneTime t = timeline.scene_time();
    if (!shown.rig.animated() || shown.time == t) return;
    try {
        animate(shown, session.loaded->desc, t);  // its warnings come with the trace's restart
        // A joint under a CSG node compiles the scene again, from the file's materials: the
        // edited ones stay (as the traced scene's at its restart).
        if (shown.materials.size() == session.loaded->scene.materials.size())
            shown.materials = session.loaded->scene.materials;
    } catch (const SceneError& e) {
        timeline.playing = false;
        messages.fail(e.what());
    }
}

void ViewerState::seek(double t) {
    timeline.seek(t, animation_length());
    mark_edited();
}

// The joints to the timeline's time (only while the trace is stopped).
void ViewerState::move_joints() {
    LoadedScene& s = *session.loaded;
    if (!s.scene.rig.animated()) return;
    const SceneTime t = timeline.scene_time();
    if (s.scene.time == t) return;
    Diagnostics diag;
    try {
        animate(s.scene, s.desc, t, &diag);
    } catch (const SceneError& e) {  // the scene stays at the time it held
        timeline.playing = false;
        messages.fail(e.what());
        return;
    }
    ui.selection = {};  // its instance and box were those of the time before
    // A joint singular at this time: said once until the time leaves it.
    std::string warning = diag.warnings().empty() ? "" : diag.warnings()[0].message;
    if (!warning.empty() && warning != m_joint_warning) messages.note(warning);
    m_joint_warning = warning;
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
