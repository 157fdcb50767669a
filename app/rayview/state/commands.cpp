#include "state/commands.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <stdexcept>

#include "state/light_edit.h"
#include "state/viewer_compare.h"
#include "state/viewer_output.h"

namespace rt::view {

double command_number(const ScriptLine& l, size_t i, double lo, double hi) {
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

int command_whole(const ScriptLine& l, size_t i, int lo, int hi) {
    const double x = command_number(l, i, lo, hi);
    if (x != std::floor(x)) {  // "0.5" is not pixel 0, nor 1 sample
        std::ostringstream msg;
        msg << l.command << ": '" << l.args[i] << "' is not a whole number (from " << lo << " to "
            << hi << ")";
        throw std::runtime_error(msg.str());
    }
    return static_cast<int>(x);
}

namespace {

double number(const ScriptLine& l, size_t i, double lo, double hi) {
    return command_number(l, i, lo, hi);
}
int whole(const ScriptLine& l, size_t i, int lo, int hi) { return command_whole(l, i, lo, hi); }

bool on(const ScriptLine& l) {
    if (l.args.empty() || (l.args[0] != "on" && l.args[0] != "off"))
        throw std::runtime_error(l.command + ": on or off");
    return l.args[0] == "on";
}

// A line of the run's output: "rayview: frame F: " and `text`.
std::string said(const ScriptLine& l, const std::string& text) {
    return "rayview: frame " + std::to_string(l.frame) + ": " + text;
}

// light I position X Y Z | light I colour|ambient|diffuse|specular R G B | light I NAME X, a
// number of kLightNumbers (radius, constant, linear, quadratic, cutoff, dropoff).
void set_light(const ScriptLine& l, ViewerState& v) {
    constexpr double kBig = 1e6;
    auto arg = [&](size_t i) { return number(l, i, -kBig, kBig); };
    const size_t i = static_cast<size_t>(whole(l, 0, 0, 1 << 20));
    if (i >= v.edits.lights.size())
        throw std::runtime_error("light: the scene has no light " + l.args[0]);
    if (l.args.size() < 3) throw std::runtime_error("light: I WHAT VALUES...");
    LightDesc light = v.edits.lights[i];  // a copy, put back once
    const std::string& what = l.args[1];
    if (what == "position") {
        light.position = Vec3(arg(2), arg(3), arg(4));
    } else {
        const bool one = std::any_of(std::begin(kLightNumbers), std::end(kLightNumbers),
                                     [&](const LightNumber& n) { return what == n.name; });
        if (!edit_light(what, arg(2), one ? 0 : arg(3), one ? 0 : arg(4), &light))
            throw std::runtime_error("light: cannot set " + what + " of light " + l.args[0]);
    }
    v.edits.set_light(i, light, v.edits.light_on[i] != 0);
}

// The camera, the lights and the settings the trace uses, as the mouse, the keys and the panel
// edit them. False for another command.
bool run_edit(const ScriptLine& l, ViewerState& v) {
    constexpr double kBig = 1e6;
    auto arg = [&](size_t i) { return number(l, i, -kBig, kBig); };
    OrbitCamera cam = v.edits.camera;
    ViewSettings s = v.settings;
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
        set_light(l, v);
        return true;
    } else if (c == "add-light" && !l.args.empty()) {
        const std::map<std::string, LightKind> kinds{{"point", LightKind::Point},
                                                     {"spot", LightKind::Spot},
                                                     {"directional", LightKind::Directional},
                                                     {"sphere", LightKind::Sphere}};
        const auto it = kinds.find(l.args[0]);
        if (it == kinds.end())
            throw std::runtime_error("add-light: point, spot, directional or sphere");
        v.edits.add_light(it->second);
        return true;
    } else if (c == "frame-light") {
        v.edits.frame_light(static_cast<size_t>(whole(l, 0, 0, 1 << 20)),
                            v.session.loaded ? v.session.loaded->scene.world_bounds : Bounds3{});
        return true;
    } else if (c == "headlight") {
        s.headlight = on(l);
    } else if (c == "shadows") {
        s.render.shadows = on(l);
    } else if (c == "depth") {
        s.render.max_depth = whole(l, 0, 1, kMaxDepth);
    } else if (c == "threads") {
        s.render.threads = whole(l, 0, 0, 256);
    } else if (c == "target-error") {
        s.target_error = static_cast<float>(number(l, 0, 0, 1));
    } else {
        return false;
    }
    v.edits.camera = cam;  // the copies put back: the viewer sees what changed
    v.settings = s;
    return true;
}

// The timeline, as its bar and the space key drive it. False for another command.
bool run_animation(const ScriptLine& l, ViewerState& v, std::string* out) {
    Timeline& tl = v.timeline;
    const std::string& c = l.command;
    const std::string arg = l.args.empty() ? "" : l.args[0];
    if (c == "play") {
        tl.playing = true;
    } else if (c == "pause") {
        tl.playing = false;
        char t[32];
        std::snprintf(t, sizeof t, "%.9g", tl.time);
        *out = said(l, "paused at t = " + std::string(t) + "\n");
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
        render_animation(v, arg, whole(l, 1, 1, 100000), whole(l, 2, 1, 32768),
                         whole(l, 3, 1, 32768), whole(l, 4, 1, 1 << 16),
                         l.args.size() > 5 ? l.args[5] : "");
    } else {
        return false;
    }
    return true;
}

// compare view|flip|tolerance|neighbourhood|probe on the comparison under way.
void compare_setting(const ScriptLine& l, ViewerState& v, std::string* out) {
    CompareView& c = v.ui.compare;
    const std::string& what = l.args[0];
    if (what == "view") {
        const std::string name = l.args.size() > 1 ? l.args[1] : "";
        bool found = false;
        for (CompareShow s : {CompareShow::Theirs, CompareShow::Ours, CompareShow::Difference,
                              CompareShow::Threshold})
            if (name == compare_show_name(s)) c.show = s, found = true;
        if (!found) throw std::runtime_error("compare view: theirs|ours|difference|threshold");
    } else if (what == "flip") {
        c.flip();
    } else if (what == "tolerance") {
        c.set_tolerance(number(l, 1, 0, 255));
    } else if (what == "neighbourhood") {
        ScriptLine rest = l;
        rest.args.erase(rest.args.begin());
        c.set_neighbourhood(on(rest));
    } else {  // probe X Y: both values there and the reference's ray tree
        const int x = whole(l, 1, 0, std::max(0, c.theirs.width - 1));
        const int y = whole(l, 2, 0, std::max(0, c.theirs.height - 1));
        probe_compare(v, x, y);
        *out += said(l, "compare " + compare_probe_text(c, c.probe_x, c.probe_y) + "\n" +
                            (v.ui.inspect.tree ? v.ui.inspect.text : ""));
    }
    if (c.result) *out += said(l, compare_status(c) + "\n");
}

// The comparison with an image, as the comparison pane and its panel section do. False for
// another command.
bool run_compare(const ScriptLine& l, ViewerState& v, std::string* out) {
    if (l.command != "compare") return false;
    const std::string what = l.args.empty() ? "" : l.args[0];
    if (what.empty()) throw std::runtime_error("compare: PATH, or off, view, flip, tolerance, ...");
    const bool setting = what == "off" || what == "view" || what == "flip" || what == "tolerance" ||
                         what == "neighbourhood" || what == "spp" || what == "probe";
    if (!setting) {
        if (!compare_with(v, what)) throw std::runtime_error("compare: " + v.messages.text);
    } else if (what == "off") {
        stop_compare(v);
    } else if (what == "spp") {  // the reference's samples: rendered again
        set_compare_spp(v, whole(l, 1, 1, 1 << 16));
    } else if (!v.ui.compare.active()) {
        throw std::runtime_error("compare " + what + ": nothing compared");
    } else {
        compare_setting(l, v, out);
    }
    return true;
}

// material I emissive|ambient|diffuse|specular|transparent R G B | material I exponent E |
// material I index N | material I texture T: the panel's material edits.
void set_material(const ScriptLine& l, ViewerState& v) {
    const size_t i = static_cast<size_t>(whole(l, 0, 0, 1 << 20));
    if (i >= v.edits.materials.size() || l.args.size() < 3)
        throw std::runtime_error("material: I WHAT VALUES... (the scene has " +
                                 std::to_string(v.edits.materials.size()) + " materials)");
    MaterialDesc m = v.edits.materials[i];  // a copy, put back once
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
        m.texture = whole(l, 2, -1, o.textures - 1);
    } else
        throw std::runtime_error("material: cannot set " + what);
    v.edits.set_material(i, m);
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
        save_scene(v, path);
    } else if (c == "save-scene-all" && !path.empty()) {
        save_scene(v, path, true);  // and the edited materials of included files
    } else if (c == "save-image" && !path.empty()) {
        save_trace(v, path);
    } else if (c == "render-image" && l.args.size() >= 4) {
        render_image(v, path, whole(l, 1, 1, 32768), whole(l, 2, 1, 32768),
                     whole(l, 3, 1, 1 << 16));
    } else {
        return false;
    }
    return true;
}

// What the panes show: boxes, layout, exposure, tonemap, markers, resolution.
bool run_display(const ScriptLine& l, ViewerState& v) {
    ViewSettings s = v.settings;
    const std::string& c = l.command;
    const std::string path = l.args.empty() ? "" : l.args[0];
    if (c == "boxes") {
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
    } else if (c == "markers") {
        // on | off | all (every light's direction, not the selected one's only)
        const bool all = !l.args.empty() && l.args[0] == "all";
        s.show_lights = all || on(l);
        s.light_directions = all;
    } else if (c == "resolution") {
        s.resolution_scale = static_cast<float>(number(l, 0, 0.1, 1));
    } else {
        return false;
    }
    v.settings = s;
    return true;
}

// What was picked or inspected, the help, undo and redo, the status line.
bool run_view(const ScriptLine& l, ViewerState& v, std::string* out) {
    const std::string& c = l.command;
    const std::string path = l.args.empty() ? "" : l.args[0];
    if (c == "pick") {
        v.pick(number(l, 0, 0, 0.999999), number(l, 1, 0, 0.999999));
        const Selection& sel = v.ui.selection;
        *out = said(l, "picked " + (sel.instance < 0 ? std::string("nothing") : sel.shape) + " " +
                           sel.material + " " + sel.where + " in " + sel.groups + "\n");
    } else if (c == "inspect" && (path == "on" || path == "off")) {
        v.ui.inspect.set_mode(path == "on");
    } else if (c == "inspect" && path == "clear") {
        v.ui.inspect.clear();
    } else if (c == "inspect") {
        // The ray tree of the trace's pixel X, Y (column, row from the top, as compare probe and
        // raytrace --inspect count), printed as raytrace --inspect prints it.
        const int w = v.trace.width(), h = v.trace.height();
        if (w <= 0 || h <= 0) throw std::runtime_error("inspect: the trace has no pixels yet");
        const int x = whole(l, 0, 0, w - 1), y = whole(l, 1, 0, h - 1);
        v.inspect((x + 0.5) / w, (y + 0.5) / h);
        if (v.ui.inspect.tree)
            *out = said(l, "inspected pixel " + std::to_string(v.ui.inspect.tree->x) + "," +
                               std::to_string(v.ui.inspect.tree->y) + "\n" + v.ui.inspect.text);
    } else if (c == "help") {
        v.ui.set_help(on(l));
    } else if (c == "undo") {
        if (!v.undo()) throw std::runtime_error("undo: nothing to undo");
    } else if (c == "redo") {
        if (!v.redo()) throw std::runtime_error("redo: nothing to redo");
    } else if (c == "status") {
        *out = said(l, "status: " + status_text(v) + "\n");
    } else {
        return false;
    }
    return true;
}

}  // namespace

std::optional<std::string> run_command(ViewerState& v, const ScriptLine& l) {
    std::string out;
    if (run_edit(l, v) || run_animation(l, v, &out) || run_compare(l, v, &out) || run_file(l, v) ||
        run_display(l, v) || run_view(l, v, &out))
        return out;
    return std::nullopt;
}

}  // namespace rt::view
