#define GL_GLEXT_PROTOTYPES
#include "ui/script.h"

#include <GL/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "state/light_edit.h"

namespace rt::view {

void save_window(int width, int height, const std::string& path) {
    std::vector<unsigned char> px(static_cast<size_t>(width) * height * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, px.data());
    Image shot(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = (static_cast<size_t>(height - 1 - y) * width + x) * 3;
            shot.set(x, y, Vec3(px[i], px[i + 1], px[i + 2]) / 255.0);
        }
    save_image(shot, path);
}

double FrameStats::tick() {
    const auto now = std::chrono::steady_clock::now();
    const double frame_s = std::chrono::duration<double>(now - m_last).count();
    m_last = now;
    if (m_count++ > 0) {
        m_total_s += frame_s;
        m_max_s = std::max(m_max_s, frame_s);
        if (m_count > 3) m_ms.push_back(1000 * frame_s);  // after start-up
    }
    return frame_s;
}

void FrameStats::print(const ViewerState& v) const {
    std::printf(
        "rayview: %d frames, mean %.1f ms, max %.1f ms; first traced pass %.0f ms "
        "after the last change\n",
        m_count, 1000 * m_total_s / (m_count - 1), 1000 * m_max_s, v.trace.first_pass_ms);
    auto quantile = [](std::vector<double> x, double q) {
        std::sort(x.begin(), x.end());
        return x.empty() ? 0.0 : x[static_cast<size_t>(q * static_cast<double>(x.size() - 1))];
    };
    std::printf(
        "rayview: frames after start-up: median %.1f ms, p95 %.1f ms; first "
        "traced pass after a change: median %.0f ms, p95 %.0f ms (%zu changes)\n",
        quantile(m_ms, 0.5), quantile(m_ms, 0.95), quantile(v.trace.first_pass_samples, 0.5),
        quantile(v.trace.first_pass_samples, 0.95), v.trace.first_pass_samples.size());
    std::printf(
        "rayview: first full-resolution pass after a change: median %.0f ms, p95 %.0f ms "
        "(%zu changes)\n",
        quantile(v.trace.first_full_samples, 0.5), quantile(v.trace.first_full_samples, 0.95),
        v.trace.first_full_samples.size());
    const Tracer::Status st = v.trace.tracer.status();
    std::printf("rayview: trace at %d spp, %.2f Mray/s on %d threads\n", st.spp,
                st.rays_per_second / 1e6, resolve_thread_count(v.settings.render.threads));
}

ScriptRun::ScriptRun(const RunOptions& options)
    : m_lines(options.script), m_frames_left(options.frames), m_screenshot(options.screenshot) {}

void ScriptRun::restarted() {
    for (const std::string& cause : m_causes)
        std::printf("rayview: frame %d: %s: trace restarted\n", m_frame, cause.c_str());
    m_causes.clear();
}

namespace {

// Argument i of a script line as a number in [lo, hi]; throws naming the command otherwise (a
// non-finite or out-of-range value never reaches a setting).
double number(const ScriptLine& l, size_t i, double lo, double hi) {
    const std::string text = i < l.args.size() ? l.args[i] : "";
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(x) || x < lo || x > hi) {
        std::ostringstream msg;
        msg << l.command << ": '" << text << "' is not a number from " << lo << " to " << hi;
        throw std::runtime_error(msg.str());
    }
    return x;
}

int whole(const ScriptLine& l, size_t i, int lo, int hi) {
    return static_cast<int>(number(l, i, lo, hi));
}

}  // namespace

namespace {

bool on(const ScriptLine& l) {
    if (l.args.empty() || (l.args[0] != "on" && l.args[0] != "off"))
        throw std::runtime_error(l.command + ": on or off");
    return l.args[0] == "on";
}

// The camera and the lights, as the mouse, the keys and the panel edit them. False for another
// command.
bool run_edit(const ScriptLine& l, ViewerState& v) {
    constexpr double kBig = 1e6;
    auto arg = [&](size_t i) { return number(l, i, -kBig, kBig); };
    OrbitCamera& cam = v.edits.camera;
    const std::string& c = l.command;
    if (c == "orbit") {
        cam.orbit(arg(0), arg(1));
    } else if (c == "look") {
        cam.look(arg(0), arg(1));
    } else if (c == "pan") {
        cam.pan(arg(0), arg(1));
    } else if (c == "dolly") {
        cam.dolly(number(l, 0, 1e-6, 1e6));
    } else if (c == "fly") {
        cam.move(Vec3(arg(0), arg(1), arg(2)));
    } else if (c == "light") {
        const size_t i = static_cast<size_t>(whole(l, 0, 0, 1 << 20));
        if (i >= v.edits.lights.size())
            throw std::runtime_error("light: the scene has no light " + l.args[0]);
        if (l.args.size() < 3) throw std::runtime_error("light: I WHAT VALUES...");
        LightDesc& light = v.edits.lights[i];
        const std::string& what = l.args[1];
        if (what == "position") {
            light.position = Vec3(arg(2), arg(3), arg(4));
        } else {
            const bool one = what == "radius";
            if (!edit_light(what, arg(2), one ? 0 : arg(3), one ? 0 : arg(4), &light))
                throw std::runtime_error("light: cannot set " + what + " of light " + l.args[0]);
        }
    } else if (c == "add-light" && !l.args.empty()) {
        const std::map<std::string, LightKind> kinds{{"point", LightKind::Point},
                                                     {"spot", LightKind::Spot},
                                                     {"directional", LightKind::Directional},
                                                     {"sphere", LightKind::Sphere}};
        const auto it = kinds.find(l.args[0]);
        if (it == kinds.end())
            throw std::runtime_error("add-light: point, spot, directional or sphere");
        v.add_light(it->second);
    } else if (c == "frame-light") {
        v.frame_light(static_cast<size_t>(whole(l, 0, 0, 1 << 20)));
    } else if (c == "headlight") {
        v.settings.headlight = on(l);
    } else if (c == "shadows") {
        v.settings.render.shadows = on(l);
    } else if (c == "depth") {
        v.settings.render.max_depth = whole(l, 0, 1, kMaxDepth);
    } else if (c == "threads") {
        v.settings.render.threads = whole(l, 0, 0, 256);
    } else if (c == "target-error") {
        v.settings.target_error = static_cast<float>(number(l, 0, 0, 1));
    } else {
        return false;
    }
    v.mark_edited();
    return true;
}

// The timeline, as its bar and the space key drive it. False for another command.
bool run_animation(const ScriptLine& l, ViewerState& v, int frame) {
    Timeline& tl = v.timeline;
    const std::string& c = l.command;
    const std::string arg = l.args.empty() ? "" : l.args[0];
    if (c == "play") {
        tl.playing = true;
    } else if (c == "pause") {
        tl.playing = false;
        std::printf("rayview: frame %d: paused at t = %.9g\n", frame, tl.time);
    } else if (c == "time") {
        tl.playing = false;
        v.seek(number(l, 0, -1e9, 1e9));
    } else if (c == "speed") {
        tl.speed = number(l, 0, 0.05, 8);
    } else if (c == "loop") {
        tl.loop = on(l);
    } else if (c == "fps") {
        tl.fps = number(l, 0, 1, 240);
    } else if (c == "interpolation") {
        if (!parse_interpolation(arg, &tl.interpolation))
            throw std::runtime_error("interpolation: " + interpolation_names(" | "));
        v.seek(tl.time);
    } else if (c == "rotation") {
        if (!parse_rotation(arg, &tl.rotation))
            throw std::runtime_error("rotation: " + rotation_names(" | "));
        v.seek(tl.time);
    } else if (c == "render-animation" && l.args.size() >= 5) {
        v.render_animation(arg, whole(l, 1, 1, 100000), whole(l, 2, 1, 32768),
                           whole(l, 3, 1, 32768), whole(l, 4, 1, 1 << 16),
                           l.args.size() > 5 ? l.args[5] : "");
    } else {
        return false;
    }
    return true;
}

// The comparison with an image, as the comparison pane and its panel section do. False for
// another command.
bool run_compare(const ScriptLine& l, ViewerState& v, int frame) {
    if (l.command != "compare") return false;
    CompareView& c = v.ui.compare;
    const std::string what = l.args.empty() ? "" : l.args[0];
    if (what.empty()) throw std::runtime_error("compare: PATH, or off, view, flip, tolerance, ...");
    const bool setting = what == "off" || what == "view" || what == "flip" || what == "tolerance" ||
                         what == "neighbourhood" || what == "spp" || what == "probe";
    if (!setting) {
        if (!v.compare_with(what)) throw std::runtime_error("compare: " + v.messages.text);
        return true;
    }
    if (what == "off") {
        v.stop_compare();
        return true;
    }
    if (what == "spp") {  // the reference's samples: rendered again
        c.spp = static_cast<int>(whole(l, 1, 1, 1 << 16));
        v.mark_edited();
        return true;
    }
    if (!c.active()) throw std::runtime_error("compare " + what + ": nothing compared");
    if (what == "view") {
        const std::string name = l.args.size() > 1 ? l.args[1] : "";
        bool found = false;
        for (CompareShow s : {CompareShow::Theirs, CompareShow::Ours, CompareShow::Difference,
                              CompareShow::Threshold})
            if (name == compare_show_name(s)) c.show = s, found = true;
        if (!found) throw std::runtime_error("compare view: theirs|ours|difference|threshold");
    } else if (what == "flip") {
        c.show = c.show == CompareShow::Theirs ? CompareShow::Ours : CompareShow::Theirs;
    } else if (what == "tolerance") {
        c.settings.tolerance = number(l, 1, 0, 255);
        c.recompare();
    } else if (what == "neighbourhood") {
        ScriptLine rest = l;
        rest.args.erase(rest.args.begin());
        c.settings.neighbourhood = on(rest);
        c.recompare();
    } else {  // probe X Y: both values there and the reference's ray tree
        c.probe_x = static_cast<int>(whole(l, 1, 0, std::max(0, c.theirs.width - 1)));
        c.probe_y = static_cast<int>(whole(l, 2, 0, std::max(0, c.theirs.height - 1)));
        v.inspect((c.probe_x + 0.5) / c.theirs.width, (c.probe_y + 0.5) / c.theirs.height);
        std::printf("rayview: frame %d: compare %s\n%s", frame,
                    compare_probe_text(c, c.probe_x, c.probe_y).c_str(),
                    v.ui.inspect.tree ? v.ui.inspect.text.c_str() : "");
    }
    if (c.result) std::printf("rayview: frame %d: %s\n", frame, compare_status(c).c_str());
    return true;
}

// material I emissive|ambient|diffuse|specular|transparent R G B | material I exponent E |
// material I index N | material I texture T: the panel's material edits.
void set_material(const ScriptLine& l, ViewerState& v) {
    const size_t i = static_cast<size_t>(whole(l, 0, 0, 1 << 20));
    if (i >= v.edits.materials.size() || l.args.size() < 3)
        throw std::runtime_error("material: I WHAT VALUES... (the scene has " +
                                 std::to_string(v.edits.materials.size()) + " materials)");
    Material& m = v.edits.materials[i];
    const std::string& what = l.args[1];
    auto arg = [&](size_t k) { return number(l, k, -1e30, 1e30); };
    Vec3* colour = what == "emissive"      ? &m.emissive
                   : what == "ambient"     ? &m.ambient
                   : what == "diffuse"     ? &m.diffuse
                   : what == "specular"    ? &m.specular
                   : what == "transparent" ? &m.transparent
                                           : nullptr;
    if (colour)
        *colour = Vec3(arg(2), arg(3), arg(4));
    else if (what == "exponent")
        m.specular_exponent = arg(2);
    else if (what == "index")
        m.refractive_index = arg(2);
    else if (what == "texture") {
        // The file's texture index, as in its #material line; -1 for none.
        const MaterialOrigin o = v.session.loaded->origin(i);
        const int t = static_cast<int>(whole(l, 2, -1, o.textures - 1));
        m.texture = t < 0 ? -1 : o.first_texture + t;
    } else
        throw std::runtime_error("material: cannot set " + what);
    v.mark_edited();
}

// Files: open, open-background, reload, revert, save-scene, save-scene-all, save-image,
// render-image, material.
bool run_file(const ScriptLine& l, ViewerState& v) {
    const std::string& c = l.command;
    const std::string path = l.args.empty() ? "" : l.args[0];
    if (c == "open" && !path.empty()) {
        v.open(path, false);
    } else if (c == "open-background" && !path.empty()) {
        v.open_in_background(path);
    } else if (c == "material") {
        set_material(l, v);
    } else if (c == "reload") {
        v.reload();
    } else if (c == "revert") {
        v.use_file_edits();
    } else if (c == "save-scene" && !path.empty()) {
        v.save_scene(path);
    } else if (c == "save-scene-all" && !path.empty()) {
        v.save_scene(path, true);  // and the edited materials of included files
    } else if (c == "save-image" && !path.empty()) {
        v.save_trace(path);
    } else if (c == "render-image" && l.args.size() >= 4) {
        v.render_image(path, whole(l, 1, 1, 32768), whole(l, 2, 1, 32768), whole(l, 3, 1, 1 << 16));
    } else {
        return false;
    }
    return true;
}

// What the panes show and what was picked or inspected: pick, inspect, boxes, layout,
// exposure, tonemap, help, markers, undo, redo, resolution, status.
bool run_view(const ScriptLine& l, ViewerState& v, int frame) {
    ViewSettings& s = v.settings;
    const std::string& c = l.command;
    const std::string path = l.args.empty() ? "" : l.args[0];
    if (c == "pick") {
        v.pick(number(l, 0, 0, 0.999999), number(l, 1, 0, 0.999999));
        std::printf("rayview: frame %d: picked %s %s %s in %s\n", frame,
                    v.ui.selection.instance < 0 ? "nothing" : v.ui.selection.shape.c_str(),
                    v.ui.selection.material.c_str(), v.ui.selection.where.c_str(),
                    v.ui.selection.groups.c_str());
    } else if (c == "inspect" && (path == "on" || path == "off")) {
        v.ui.inspect.mode = path == "on";
    } else if (c == "inspect" && path == "clear") {
        v.clear_inspect();
    } else if (c == "inspect") {
        // The ray tree of the trace's pixel there, printed as raytrace --inspect prints it.
        v.inspect(number(l, 0, 0, 0.999999), number(l, 1, 0, 0.999999));
        if (v.ui.inspect.tree)
            std::printf("rayview: frame %d: inspected pixel %d,%d\n%s", frame, v.ui.inspect.tree->x,
                        v.ui.inspect.tree->y, v.ui.inspect.text.c_str());
    } else if (c == "boxes") {
        s.group_depth = whole(l, 0, 0, 8);
        s.box_depth = whole(l, 1, 0, 8);
    } else if (c == "layout" && !path.empty()) {
        s.layout = path == "preview" ? 1 : path == "trace" ? 2 : 0;
    } else if (c == "exposure") {
        s.exposure = static_cast<float>(number(l, 0, -8, 8));
    } else if (c == "tonemap" && !path.empty()) {
        const std::map<std::string, Tonemap> names{
            {"clamp", Tonemap::Clamp}, {"reinhard", Tonemap::Reinhard}, {"aces", Tonemap::Aces}};
        const auto it = names.find(path);
        if (it == names.end()) throw std::runtime_error("tonemap: clamp, reinhard or aces");
        s.tonemap = it->second;
    } else if (c == "help") {
        v.ui.show_help = on(l);
    } else if (c == "markers") {
        // on | off | all (every light's direction, not the selected one's only)
        const bool all = !l.args.empty() && l.args[0] == "all";
        s.show_lights = all || on(l);
        s.light_directions = all;
    } else if (c == "undo") {
        if (!v.undo()) throw std::runtime_error("undo: nothing to undo");
    } else if (c == "redo") {
        if (!v.redo()) throw std::runtime_error("redo: nothing to redo");
    } else if (c == "resolution") {
        s.resolution_scale = static_cast<float>(number(l, 0, 0.1, 1));
    } else if (c == "status") {
        std::printf("rayview: frame %d: status: %s\n", frame, status_text(v).c_str());
    } else {
        return false;
    }
    return true;
}

}  // namespace

void ScriptRun::run(const ScriptLine& l, ViewerState& v, int fb_w, int fb_h) {
    if (run_edit(l, v) || run_animation(l, v, m_frame) || run_compare(l, v, m_frame) ||
        run_file(l, v) || run_view(l, v, m_frame))
        return;
    const std::string& c = l.command;
    const std::string path = l.args.empty() ? "" : l.args[0];
    if (c == "wait-compare") {
        if (!v.ui.compare.active()) throw std::runtime_error("wait-compare: nothing compared");
        m_wait = Wait::Compare;
        m_wait_limit_s = l.args.empty() ? 120 : number(l, 0, 0.1, 3600);
        m_wait_start = std::chrono::steady_clock::now();
    } else if (c == "wait-spp" || c == "wait-jobs") {
        const bool spp = c == "wait-spp";
        m_wait = spp ? Wait::Spp : Wait::Jobs;
        m_wait_spp = spp ? whole(l, 0, 1, 1 << 20) : 0;
        const size_t limit = spp ? 1 : 0;
        m_wait_limit_s = l.args.size() > limit ? number(l, limit, 0.1, 3600) : 120;
        m_wait_start = std::chrono::steady_clock::now();
    } else if (c == "screenshot" && !path.empty()) {
        save_window(fb_w, fb_h, path);
        std::printf("rayview: frame %d: %s (trace at %d spp)\n", m_frame, path.c_str(),
                    v.trace.tracer.status().spp);
    } else {
        throw std::runtime_error("unknown command or missing argument: '" + c + "'");
    }
}

bool ScriptRun::end_frame(ViewerState& v, int fb_w, int fb_h, int* exit_code) {
    if (m_wait != Wait::None) {  // this frame again until what the script waits for is there
        const double waited =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - m_wait_start).count();
        const CompareView& cv = v.ui.compare;
        const bool done =
            m_wait == Wait::Spp ? !v.edit_pending() && v.trace.tracer.status().spp >= m_wait_spp
            : m_wait == Wait::Compare
                ? !cv.active() || (!v.edit_pending() && cv.current && cv.result)
                : !v.jobs.loader.busy() && !v.jobs.image.running() && !v.ui.preview_stale;
        if (done && m_wait == Wait::Compare && cv.active())
            std::printf("rayview: frame %d: %s\n", m_frame, compare_status(cv).c_str());
        if (done) {
            m_wait = Wait::None;  // shown from the next frame on, which runs the next commands
        } else if (waited > m_wait_limit_s) {
            std::fprintf(stderr, "rayview: frame %d: error: %s not done in %g s\n", m_frame,
                         m_wait == Wait::Spp       ? "wait-spp"
                         : m_wait == Wait::Compare ? "wait-compare"
                                                   : "wait-jobs",
                         m_wait_limit_s);
            m_failed = true;
            m_wait = Wait::None;
        }
        return false;
    }
    for (const ScriptLine& l : m_lines) {
        if (l.frame != m_frame) continue;
        try {
            run(l, v, fb_w, fb_h);
        } catch (const std::exception& e) {  // a bad number, a screenshot that cannot be written
            std::fprintf(stderr, "rayview: frame %d: error: %s\n", m_frame, e.what());
            m_failed = true;  // reported, and the run goes on; it exits 1 at the end
        }
        if (v.edit_pending()) m_causes.push_back(l.command);  // reported at the restart
    }
    // Scripted runs check GL once a frame: any error fails the run.
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
        std::fprintf(stderr, "rayview: frame %d: GL error 0x%x\n", m_frame, e);
        m_failed = true;
    }
    ++m_frame;
    if (m_frames_left <= 0 || --m_frames_left > 0) return false;
    // A failed command, or any error of the viewer's: an open, a background load or render,
    // the scene at start-up (each printed when it happened).
    if (m_failed || v.messages.failures > 0) *exit_code = 1;
    if (!m_screenshot.empty()) {
        try {
            save_window(fb_w, fb_h, m_screenshot);
            std::printf("rayview: saved %s\n", m_screenshot.c_str());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "rayview: %s\n", e.what());
            *exit_code = 1;
        }
    }
    return true;
}

void ScriptRun::print_summary(const FrameStats& stats, const ViewerState& v) const {
    if (stats.count() > 1 && !m_screenshot.empty()) stats.print(v);
}

}  // namespace rt::view
