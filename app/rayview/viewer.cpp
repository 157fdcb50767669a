#include "viewer.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <iostream>

#include "cli.h"
#include "frames.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/format/writer.h"
#include "rt/render/camera.h"
#include "rt/shapes/shapes.h"
#include "rt/util/charconv.h"
#include "rt/util/file_io.h"
#include "rt/util/stopwatch.h"

namespace rt::view {

namespace {

std::string absolute_path(const std::string& path) {
    std::error_code ec;
    const auto abs = std::filesystem::absolute(path, ec);
    return ec ? path : abs.lexically_normal().string();
}

std::filesystem::file_time_type modified(const std::string& path) {
    std::error_code ec;
    return std::filesystem::last_write_time(path, ec);
}

// Two lists of lights alike but for where they were read (a reload moves lines).
bool same_lights(const std::vector<LightDesc>& a, const std::vector<LightDesc>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        const LightDesc &x = a[i], &y = b[i];
        if (x.kind != y.kind || x.ambient != y.ambient || x.diffuse != y.diffuse ||
            x.specular != y.specular || x.position != y.position || x.direction != y.direction ||
            x.constant_atten != y.constant_atten || x.linear_atten != y.linear_atten ||
            x.quadratic_atten != y.quadratic_atten || x.cutoff_rad != y.cutoff_rad ||
            x.spot_exponent != y.spot_exponent || x.radius != y.radius)
            return false;
    }
    return true;
}

// The settings that follow the window, not the user's edits (undo keeps them as they are): the
// trace's size, which follows the pane, and the panel's width, visibility and scale.
void keep_window_settings(ViewSettings* s, const ViewSettings& window) {
    s->render.width = window.render.width;
    s->render.height = window.render.height;
    s->panel_w = window.panel_w;
    s->ui_scale = window.ui_scale;
    s->show_panel = window.show_panel;
}

// The edits and settings alike in what the user edits.
bool same_state(const SceneEdits& edits, const ViewSettings& settings, const UndoState& b) {
    ViewSettings x = settings;
    keep_window_settings(&x, b.settings);
    return x == b.settings && edits.camera == b.edits.camera &&
           edits.light_on == b.edits.light_on && same_lights(edits.lights, b.edits.lights);
}

bool same_loc(const SourceLoc& a, const SourceLoc& b) {
    return a.line == b.line && a.col == b.col && a.file && b.file && *a.file == *b.file;
}

// The groups (and CSG nodes) from `g` down to the directive at `loc`, outermost first, as
// "group at line 12 > joint 'arm' at line 15"; false when it is not below `g`.
bool find_group_path(const GroupDesc& g, const SourceLoc& loc, std::vector<std::string>* path) {
    for (const ShapeDesc& s : g.shapes)
        if (same_loc(s.loc, loc)) return true;
    auto step = [&](const GroupDesc& child, const std::string& what) {
        path->push_back(what + " at line " + std::to_string(child.loc.line));
        if (find_group_path(child, loc, path)) return true;
        path->pop_back();
        return false;
    };
    for (const GroupDesc& child : g.groups)
        if (step(child, child.joint.empty() ? "group" : "joint '" + child.joint + "'")) return true;
    for (const CsgDesc& c : g.csgs) {
        if (same_loc(c.loc, loc)) return true;
        for (const GroupDesc& operand : c.operands)
            if (step(operand, std::string(csg_op_name(c.op)) + " operand")) return true;
    }
    return false;
}

std::string group_path(const SceneDesc& desc, const SourceLoc& loc) {
    for (const FileDesc& f : desc.files) {
        std::vector<std::string> path;
        if (!find_group_path(f.root, loc, &path)) continue;
        std::string text = std::filesystem::path(f.path).filename().string();
        for (const std::string& p : path) text += " > " + p;
        return text;
    }
    return "";
}

bool same_camera(const CameraDesc& a, const CameraDesc& b) {
    return a.position == b.position && a.direction == b.direction && a.up == b.up &&
           a.half_height_angle_rad == b.half_height_angle_rad;
}

// The edits into the compiled scene, while no trace runs: the camera, the lights that are on
// (compiled from their descriptions) or the headlight, and the trace's size.
void apply_edits(const SceneEdits& edits, bool headlight, int trace_w, int trace_h,
                 RenderScene* scene, RenderSettings* settings) {
    scene->camera = compile_camera(edits.camera.desc());
    scene->lights.clear();
    for (size_t i = 0; i < edits.lights.size(); ++i)
        if (edits.light_on[i]) scene->lights.push_back(compile_light(edits.lights[i]));
    if (headlight) scene->lights.push_back(compile_light(headlight_desc(edits.camera)));
    settings->width = trace_w;
    settings->height = trace_h;
}

}  // namespace

double float_as_decimal(float f) {
    char buf[32];
    const auto r = to_chars_shortest(buf, buf + sizeof buf, f);
    double d = f;
    from_chars_double(buf, r.ptr, d);
    return d;
}

LightDesc headlight_desc(const OrbitCamera& camera) {
    LightDesc l;
    l.kind = LightKind::Directional;
    l.direction = camera.forward();
    l.set_colour(Vec3(1.0));
    return l;
}

bool edit_light(const std::string& what, double a, double b, double c, LightDesc* l) {
    const Vec3 rgb(a, b, c);
    if (what == "colour") {
        l->set_colour(rgb);
    } else if (what == "ambient") {
        l->ambient = rgb;
    } else if (what == "diffuse") {
        l->diffuse = rgb;
    } else if (what == "specular") {
        l->specular = rgb;
    } else if (what == "radius" && l->kind == LightKind::Sphere) {
        l->radius = std::max(0.0, a);
    } else {
        return false;
    }
    return true;
}

int render_headless(const std::string& path, MissingTextures missing,
                    const RenderSettings& settings, int spp, std::optional<Dialect> dialect) {
    const LoadResult r = load_scene({path, missing, false, dialect});  // no preview
    if (!r.scene) {
        std::cerr << r.error << "\n";
        return 1;
    }
    const LoadedScene* s = r.scene.get();
    const std::string out = std::filesystem::path(path).stem().string() + ".png";
    try {
        RenderState state;
        render_samples(state, s->scene, make_render_plan(s->scene, settings), settings, spp);
        save_image(state.image(), out);
    } catch (const std::exception& e) {
        std::cerr << "rayview: error: " << rtapp::error_text(e, "rendering " + path) << "\n";
        return 1;
    }
    std::printf("rayview: rendered %s headless (%dx%d, %d spp) to %s\n", path.c_str(),
                settings.width, settings.height, spp, out.c_str());
    return 0;
}

ViewerState::ViewerState(const std::string& path, bool print_left_out, MissingTextures missing,
                         std::optional<Dialect> file_dialect)
    : missing_textures(missing), dialect(file_dialect), m_print_left_out(print_left_out) {
    // The trace takes every core, at a lower priority than the interface (Tracer::run), so
    // frames stay smooth.
    settings.render.threads = resolve_thread_count(0);
    LoadResult r = load_scene({path, missing, true, dialect});
    loaded = std::move(r.scene);
    message = std::move(r.error);
    if (r.textures_missing) checker_offer = path;
    reset_history();
    if (!loaded) {  // keeps running with the message shown, and watches the file
        message_is_error = true;
        ++failures;
        m_watched = path;
        m_watched_time = modified(path);
        return;
    }
    loaded->id = ++m_scenes_opened;
    recent.push_back(absolute_path(loaded->path));
    on_loaded();
}

ViewerState::~ViewerState() { tracer.stop(); }

void ViewerState::on_loaded() {
    tracer.stop();
    std::printf("rayview: opened %s\n", loaded->path.c_str());
    edits.camera.set_from(loaded->file_camera, loaded->scene.world_bounds);
    edits.lights = loaded->desc.lights;
    edits.light_on.assign(edits.lights.size(), 1);
    loaded->file_time = modified(loaded->path);
    mark_edited();
    reset_history();
    if (on_opened) on_opened(loaded->path);
}

void ViewerState::start_with(const ViewSettings& initial) {
    settings = initial;
    if (loaded) mark_edited();
    reset_history();
}

void ViewerState::reset_history() {
    m_undo.clear();
    m_redo.clear();
    m_committed = current_state();
}

void ViewerState::track_history(bool gesture) {
    if (gesture || same_state(edits, settings, m_committed)) return;  // no copy per frame
    m_undo.push_back(std::move(m_committed));
    if (m_undo.size() > 500) m_undo.erase(m_undo.begin());
    m_redo.clear();
    m_committed = current_state();
}

void ViewerState::restore(const UndoState& s) {
    const ViewSettings window = settings;
    edits = s.edits;
    settings = s.settings;
    keep_window_settings(&settings, window);
    m_committed = current_state();
    preview_stale = true;
    mark_edited();
}

bool ViewerState::undo() {
    track_history(false);  // an edit not yet a step becomes one first
    if (m_undo.empty()) return false;
    m_redo.push_back(current_state());
    const UndoState back = std::move(m_undo.back());
    m_undo.pop_back();
    restore(back);
    return true;
}

bool ViewerState::redo() {
    track_history(false);
    if (m_redo.empty()) return false;
    m_undo.push_back(current_state());
    const UndoState forward = std::move(m_redo.back());
    m_redo.pop_back();
    restore(forward);
    return true;
}

bool ViewerState::open(std::string file, bool keep_camera) {
    return open_as(std::move(file), keep_camera, missing_textures);
}

bool ViewerState::open_with_checker() {
    if (checker_offer.empty()) return false;
    return open_as(checker_offer, false, MissingTextures::Checker);
}

bool ViewerState::open_as(std::string file, bool keep_camera, MissingTextures missing) {
    LoadResult next = load_scene({file, missing, true, dialect});
    return finish_open(std::move(next), file, keep_camera);
}

void ViewerState::load_in_background(const LoadRequest& request, bool reload) {
    loader.start(request);
    m_reloading = reload;
}

void ViewerState::open_in_background(std::string file) {
    load_in_background({file, missing_textures, true, dialect}, false);
    note("loading " + file + " ...");
}

void ViewerState::cancel_loading() {
    if (!loader.busy()) return;
    note("cancelled loading " + loader.path() + "; the open scene stays");
    loader.cancel();
}

bool ViewerState::finish_open(LoadResult next, const std::string& file, bool keep_camera) {
    checker_offer = next.textures_missing ? file : "";
    if (!next.scene) {
        fail(std::move(next.error));
        if (loaded) loaded->file_time = modified(loaded->path);  // do not retry every frame
        return false;
    }
    const OrbitCamera kept = edits.camera;
    tracer.stop();  // it traces the scene that is replaced here
    loaded = std::move(next.scene);
    loaded->id = ++m_scenes_opened;
    message.clear();
    message_is_error = false;
    reload_conflict.clear();
    selection = {};
    timeline.time = 0;  // a new scene's animation starts at its beginning, paused
    timeline.playing = false;
    on_loaded();
    if (keep_camera) edits.camera = kept;
    const std::string opened = absolute_path(loaded->path);
    std::vector<std::string> files{opened};  // first, and not again below; 8 at most
    for (const std::string& f : recent)
        if (f != opened && files.size() < 8) files.push_back(f);
    recent = std::move(files);
    return true;
}

bool ViewerState::reload() {
    if (!loaded) return false;
    return finish_reload(load_scene({loaded->path, loaded->missing_textures, true, dialect}));
}

void ViewerState::reload_in_background() {
    if (loaded) load_in_background({loaded->path, loaded->missing_textures, true, dialect}, true);
}

bool ViewerState::finish_reload(LoadResult next) {
    // What the user edited, against the scene as it was read last (edits made while a
    // background reload ran count too).
    OrbitCamera file_view;
    file_view.set_from(loaded->file_camera, loaded->scene.world_bounds);
    const bool camera_edited = !same_camera(file_view.desc(), edits.camera.desc());
    const bool lights_edited = !same_lights(edits.lights, loaded->desc.lights) ||
                               std::count(edits.light_on.begin(), edits.light_on.end(), 0) > 0;
    const SceneEdits mine = edits;
    const std::vector<LightDesc> old_lights = loaded->desc.lights;
    const CameraDesc old_camera = loaded->file_camera;
    const std::string file = loaded->path;  // finish_open replaces `loaded`
    const Timeline playback = timeline;     // a reload keeps the time and the playback
    if (!finish_open(std::move(next), file, false)) return false;
    timeline = playback;
    timeline.seek(timeline.time, animation_length());
    if (camera_edited) edits.camera = mine.camera;
    if (lights_edited) {
        edits.lights = mine.lights;
        edits.light_on = mine.light_on;
    }
    std::string both;  // what the user edited and the file changed too
    if (camera_edited && !same_camera(old_camera, loaded->file_camera)) both = "camera";
    if (lights_edited && !same_lights(old_lights, loaded->desc.lights))
        both += both.empty() ? "lights" : " and lights";
    const std::string name = std::filesystem::path(loaded->path).filename().string();
    reload_conflict.clear();
    if (!both.empty())
        reload_conflict = name + " changed its " + both +
                          " on disk, which you had edited: " + "your edits are kept.";
    else if (camera_edited || lights_edited)
        note("reloaded " + name + "; your edits are kept");
    return true;
}

void ViewerState::fail(std::string text) {
    ++failures;
    std::fprintf(stderr, "%s\n", text.c_str());
    message = std::move(text);
    message_is_error = true;
}

void ViewerState::note(std::string text) {
    message = std::move(text);
    message_is_error = false;
}

void ViewerState::use_file_edits() {
    if (!loaded) return;
    edits.camera.set_from(loaded->file_camera, loaded->scene.world_bounds);
    edits.lights = loaded->desc.lights;
    edits.light_on.assign(edits.lights.size(), 1);
    reload_conflict.clear();
    mark_edited();
}

void ViewerState::remember_recent(const std::vector<std::string>& files) {
    for (const std::string& f : files) {
        std::error_code ec;
        if (recent.size() >= 8) break;
        if (std::find(recent.begin(), recent.end(), f) == recent.end() &&
            std::filesystem::exists(f, ec))
            recent.push_back(f);
    }
}

void ViewerState::poll_files() {
    std::string result;
    bool ok = false;
    if (image_job.take_result(&result, &ok)) {
        ok ? note(result) : fail(result);
        if (ok && on_saved && !m_render_path.empty()) on_saved(m_render_path);
    }
    LoadResult next;
    std::string loaded_file;
    if (loader.take(&next, &loaded_file)) {
        if (m_reloading && loaded && loaded_file == loaded->path)
            finish_reload(std::move(next));
        else
            finish_open(std::move(next), loaded_file, false);
        m_reloading = false;
    }
    if (!dropped.empty()) {  // the window stays interactive while it loads
        open_in_background(dropped.back());
        dropped.clear();
    }
    const auto now = Clock::now();
    if (now - m_last_check < std::chrono::milliseconds(500)) return;
    m_last_check = now;
    if (loaded && !loader.busy() && modified(loaded->path) != loaded->file_time) {
        loaded->file_time = modified(loaded->path);  // once per change
        reload_in_background();                      // the open scene stays interactive meanwhile
    }
    if (!loaded && !m_watched.empty() && modified(m_watched) != m_watched_time) {
        m_watched_time = modified(m_watched);  // the file that failed at start-up, fixed?
        open(m_watched, false);
    }
}

void ViewerState::save_scene(const std::string& path) const {
    SceneDesc desc = loaded->desc;
    desc.camera = edits.camera.desc();
    desc.lights.clear();
    for (size_t i = 0; i < edits.lights.size(); ++i)
        if (edits.light_on[i]) desc.lights.push_back(edits.lights[i]);
    write_file_atomic(path, write_scene_for(desc, path));  // a temporary name, then renamed
    if (on_saved) on_saved(path);
}

void ViewerState::save_trace(const std::string& path) const {
    if (last_trace.width == 0) throw std::runtime_error("nothing traced yet");
    save_image(holds_linear(image_format_from_path(path)) ? last_trace : displayed_trace(), path);
    if (on_saved) on_saved(path);
}

void ViewerState::render_animation(const std::string& pattern, int frames, int width, int height,
                                   int spp, const std::string& video) {
    if (!loaded) return;
    try {
        rtapp::frame_path(pattern, 0);
    } catch (const std::invalid_argument& e) {
        fail(std::string("render animation: ") + e.what());
        return;
    }
    SequenceSpec q;
    q.desc = std::make_shared<const SceneDesc>(loaded->desc);
    q.frames = frames;
    q.fps = timeline.fps;
    q.interpolation = timeline.interpolation;
    q.rotation = timeline.rotation;
    q.video = video;
    start_render(pattern, width, height, spp, q);
    m_render_path.clear();
    note("rendering " + std::to_string(frames) + " frames to " + pattern + " ...");
}

void ViewerState::render_image(const std::string& path, int width, int height, int spp) {
    if (!loaded) return;
    start_render(path, width, height, spp, {});
    m_render_path = path;  // one file (an animation's frames are not handed to on_saved)
    note("rendering " + path + " ...");
}

// The background job on a copy of the scene with the latest edits, at the display's settings.
void ViewerState::start_render(const std::string& path, int width, int height, int spp,
                               const SequenceSpec& sequence) {
    ImageJobSpec spec;
    spec.path = path;
    spec.width = width;
    spec.height = height;
    spec.spp = spp;
    spec.settings = settings.render;
    spec.exposure = settings.exposure;
    spec.tonemap = settings.tonemap;
    spec.sequence = sequence;
    RenderScene scene = loaded->scene;  // shares its sets: the copy costs the instances
    apply_edits(edits, headlight_on(), width, height, &scene, &spec.settings);
    image_job.start(std::move(scene), spec);
}

Image ViewerState::displayed_trace() const {
    return display_transform(last_trace, settings.exposure, settings.tonemap);
}

void ViewerState::set_trace_size(int w, int h) {
    if (w == m_trace_w && h == m_trace_h) return;
    m_trace_w = w;
    m_trace_h = h;
    mark_edited();
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
    loaded->file_camera = edits.camera.desc();
    loaded->desc.camera = loaded->file_camera;
    note("the view is the scene's camera now (Save scene writes it)");
}

bool ViewerState::pick(double x, double y) {
    selection = {};
    preview_stale = true;  // the highlight changes
    if (!loaded) return false;
    const RenderScene& scene = loaded->scene;
    const int w = std::max(1, m_trace_w), h = std::max(1, m_trace_h);
    const Camera cam = make_camera(compile_camera(edits.camera.desc()), w, h);
    const Ray ray = cam.generate(0, 0, x * w, y * h);
    Hit hit;
    if (!intersect(scene, ray, {0, kInf}, &hit)) return false;
    const Instance& inst = scene.instances[static_cast<size_t>(hit.instance)];
    const GeometrySet& set = scene.sets[static_cast<size_t>(inst.set)];
    const Primitive& prim = set.prims[hit.prim];
    Selection s;
    s.instance = hit.instance;
    s.prim = hit.prim;
    s.point = ray.o + hit.t * ray.d;
    const Bounds3 b = set.prim_bounds(hit.prim);
    s.bounds = inst.identity ? b : inst.world_from_set.apply(b);
    s.shape = prim.csg >= 0 ? "CSG node" : shape_kind_name(prim.kind);
    const size_t m = static_cast<size_t>(prim.material);
    const std::string name = m < loaded->material_names.size() ? loaded->material_names[m] : "";
    s.material = (name.empty() ? "" : "!" + name + "! ") + "(material " + std::to_string(m) + ")";
    const auto& locs = loaded->prim_locs;
    if (static_cast<size_t>(inst.set) < locs.size() && hit.prim < locs[inst.set].size()) {
        const SourceLoc& loc = locs[inst.set][hit.prim];
        s.where = loc.str();
        s.groups = group_path(loc.file ? loaded->desc : SceneDesc{}, loc);
    }
    selection = std::move(s);
    return true;
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
        c.set_from(d, loaded ? loaded->scene.world_bounds : Bounds3{});
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
    if (!loaded || m_trace_w <= 0 || m_trace_h <= 0) return false;  // no pane to trace for yet
    // A new scene restarts at once: the preview draws with the plan of the scene it shows.
    const bool trace_caught_up =
        first_pass_ms >= 0 || seconds_since(m_change_time) > 0.1 || loaded->id != m_traced_id;
    if (m_edited) preview_stale = true;  // the preview follows every frame
    if (m_edited && !m_input_pending) {
        m_input_pending = true;
        m_input_time = Clock::now();
    }
    if (!m_edited || !trace_caught_up) return false;
    restart();
    return true;
}

// Stop, edit, restart: the compiled scene only changes while no trace runs.
void ViewerState::restart() {
    tracer.stop();
    move_joints();
    apply_edits(edits, headlight_on(), m_trace_w, m_trace_h, &loaded->scene, &settings.render);
    loaded->shown.camera = loaded->scene.camera;  // the preview's overlays show the same lights
    loaded->shown.lights = loaded->scene.lights;
    tracer.restart(loaded->scene, settings.render, settings.target_spp, settings.target_error);
    m_traced_id = loaded->id;
    explained.clear();
    for (const PlanReason& r : tracer.plan().reasons) explained.push_back(reason_line(r));
    if (m_print_left_out)
        for (const std::string& l : explained)
            if (l.rfind("left out", 0) == 0) std::printf("rayview: %s\n", l.c_str());
    m_print_left_out = false;
    m_edited = false;
    m_input_pending = false;
    m_served_input_time = m_input_time;
    m_change_time = Clock::now();
    first_pass_ms = -1;
    first_full_ms = -1;
}

bool ViewerState::take_trace_image() {
    if (!tracer.take_image(&last_trace)) return false;
    // From the edit, not the (possibly deferred) restart.
    const double ms =
        std::chrono::duration<double, std::milli>(Clock::now() - m_served_input_time).count();
    if (first_pass_ms < 0) {
        first_pass_ms = ms;
        first_pass_samples.push_back(first_pass_ms);
    }
    if (first_full_ms < 0 && tracer.status().spp >= 1) {
        first_full_ms = ms;
        first_full_samples.push_back(first_full_ms);
    }
    return true;
}

double ViewerState::animation_length() const {
    return loaded ? view::animation_length(loaded->desc) : 0.0;
}

void ViewerState::step_animation(double frame_s) {
    if (!loaded) return;
    if (timeline.advance(frame_s, animation_length())) mark_edited();
    RenderScene& shown = loaded->shown;
    const SceneTime t = timeline.scene_time();
    if (!shown.rig.animated() || shown.time == t) return;
    try {
        animate(shown, loaded->desc, t);  // its warnings come with the trace's restart
    } catch (const SceneError& e) {
        timeline.playing = false;
        fail(e.what());
    }
}

void ViewerState::seek(double t) {
    timeline.seek(t, animation_length());
    mark_edited();
}

// The joints to the timeline's time (only while the trace is stopped).
void ViewerState::move_joints() {
    if (!loaded->scene.rig.animated()) return;
    const SceneTime t = timeline.scene_time();
    if (loaded->scene.time == t) return;
    Diagnostics diag;
    try {
        animate(loaded->scene, loaded->desc, t, &diag);
    } catch (const SceneError& e) {  // the scene stays at the time it held
        timeline.playing = false;
        fail(e.what());
        return;
    }
    selection = {};  // its instance and box were those of the time before
    // A joint singular at this time: said once until the time leaves it.
    std::string warning = diag.warnings().empty() ? "" : diag.warnings()[0].message;
    if (!warning.empty() && warning != m_joint_warning) note(warning);
    m_joint_warning = warning;
}

bool ViewerState::moving() const { return seconds_since(m_change_time) < 0.25; }

std::string status_text(const ViewerState& v) {
    const Tracer::Status st = v.tracer.status();
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
    s += " | first pass " + ms(v.first_pass_ms) + ", full resolution " + ms(v.first_full_ms);
    if (v.headlight_on()) s += " | headlight: the scene has no lights";
    return s;
}

}  // namespace rt::view
