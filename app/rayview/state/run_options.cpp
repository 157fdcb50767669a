#include "state/run_options.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include "cli.h"
#include "data_dir.h"
#include "rt/util/file_io.h"
#include "version.h"

namespace rt::view {

namespace {

// The script commands (the help's footer and the F1 overlay).
constexpr const char* kScriptCommands =
    "script commands (--script FILE: one 'FRAME COMMAND ARGS...' a line, run after that "
    "frame is drawn):\n"
    "  camera:   orbit DYAW DPITCH | look DYAW DPITCH | pan RIGHT UP | dolly FACTOR |\n"
    "            fly DX DY DZ | pick X Y (image fractions from the top left)\n"
    "  inspect:  inspect X Y (the trace's pixel X,Y: column, row from the top, whole numbers,\n"
    "            at the trace's size then (the status bar's): its ray tree, printed and\n"
    "            drawn) | inspect on|off (clicks inspect) | inspect clear\n"
    "  compare:  compare PATH (the trace against an image) | compare view\n"
    "            theirs|ours|difference|threshold | compare flip | compare tolerance K |\n"
    "            compare neighbourhood on|off | compare spp N | compare probe X Y (the pixel\n"
    "            X,Y as inspect counts it: both values and the reference's ray tree) |\n"
    "            compare off | wait-compare [SECONDS]\n"
    "  lights:   light I colour|ambient|diffuse|specular R G B | light I NAME X (radius,\n"
    "            constant, linear, quadratic, cutoff, dropoff) |\n"
    "            light I position X Y Z | add-light point|spot|directional|sphere |\n"
    "            frame-light I | headlight on|off\n"
    "  materials: material I emissive|ambient|diffuse|specular|transparent R G B |\n"
    "            material I exponent E | material I index N |\n"
    "            material I texture T (the file's texture index, -1 none)\n"
    "  settings: shadows on|off | depth D | threads N | resolution SCALE |\n"
    "            boxes GROUP_LEVELS BVH_LEVELS | layout both|preview|trace | markers on|off|all |\n"
    "            target-error E (0: none) | status (prints the status bar) |\n"
    "            exposure STOPS | tonemap clamp|reinhard|aces | help on|off\n"
    "  history:  undo | redo\n"
    "  waiting:  wait-spp N [SECONDS] | wait-jobs [SECONDS] (hold the script, and --frames'\n"
    "            count, until the trace has N samples per pixel, or the background loads and\n"
    "            renders and the preview's reflection maps are done; fails after SECONDS,\n"
    "            default 120)\n"
    "  animation: play | pause | time T | speed X | loop on|off | fps F |\n"
    "            interpolation nearest|linear|catmull-rom|bspline |\n"
    "            rotation matrix|closest|euler|log|quaternion |\n"
    "            render-animation PATTERN FRAMES W H SPP [VIDEO] (in the background)\n"
    "  files:    open PATH | open-background PATH | reload | revert (the file's camera and\n"
    "            lights) | save-scene PATH | save-scene-all PATH (and the edited\n"
    "            materials into their included files) | save-image PATH (the pane's trace) |\n"
    "            render-image PATH W H SPP (in the background) | screenshot PATH\n"
    "A command that fails is reported and the run goes on; the run then exits 1. Frame\n"
    "numbers are at most 100000 (as --frames); a script runs to two frames past its last.";

// The help's last part: the script commands and the exit status.
const std::string kFooter =
    std::string("\n") + kScriptCommands +
    "\n\nexit status: 0 success; 1 a failed --frames, --script or --screenshot run (a command, an\n"
    "open, a background load or render failed, or the scene did not open at start-up); 2 usage\n"
    "error (also a --script that is not a readable file, or a frame number out of range).";

}  // namespace

const char* script_commands_help() { return kScriptCommands; }

std::vector<ScriptLine> read_script(const std::string& path) {
    std::string text, why;
    if (!rt::read_file(path, &text, &why)) throw std::runtime_error("--script: " + why);
    std::istringstream f(text);
    std::vector<ScriptLine> lines;
    std::string line;
    for (int number = 1; std::getline(f, line); ++number) {
        std::istringstream ss(line);
        ScriptLine l;
        long long frame = 0;
        if (!(ss >> frame >> l.command)) continue;
        if (frame < 0 || frame > kMaxFrames)
            throw std::runtime_error(path + ":" + std::to_string(number) + ": frame " +
                                     std::to_string(frame) + " is not in 0.." +
                                     std::to_string(kMaxFrames));
        l.frame = static_cast<int>(frame);
        for (std::string a; ss >> a;) l.args.push_back(a);
        lines.push_back(l);
    }
    return lines;
}

bool parse_size(const std::string& text, int* w, int* h) {
    std::istringstream ss(text);
    char x = 0;
    int a = 0, b = 0;
    if (!(ss >> a >> x >> b) || (x != 'x' && x != 'X') || !ss.eof()) return false;
    if (a < 64 || b < 64 || a > 16384 || b > 16384) return false;
    *w = a;
    *h = b;
    return true;
}

namespace {

// The viewer's own options: the scene, the scripted run, the window and the comparison.
void add_viewer_options(CLI::App& app, RunOptions* out, std::string* script_path,
                        std::string* size) {
    app.add_option("scene", out->scene, "the .ray file (default: the showpiece)")
        ->type_name("SCENE.ray");
    app.add_option("--frames", out->frames,
                   "run N frames (at most " + std::to_string(kMaxFrames) +
                       "), save the window (--screenshot), exit")
        ->type_name("N")
        ->check(CLI::Range(1, kMaxFrames));
    app.add_option("--screenshot", out->screenshot, "where --frames saves the whole window")
        ->type_name("OUT.png");
    app.add_option("--script", *script_path, "replay input at given frames (the commands: below)")
        ->type_name("FILE");
    const std::map<std::string, int> layouts{{"both", 0}, {"preview", 1}, {"trace", 2}};
    app.add_option("--layout", out->layout, "the panes shown: both (default), preview or trace")
        ->type_name("both|preview|trace")
        ->transform(CLI::CheckedTransformer(layouts, CLI::ignore_case).description(""));
    app.add_option("--size", *size,
                   "the window's size in pixels (default: the last run's, 1280x720)")
        ->type_name("WxH");
    const std::map<std::string, bool> on_off{{"on", true}, {"off", false}};
    app.add_option("--panel", out->panel, "the control panel: on (default) or off")
        ->type_name("on|off")
        ->transform(CLI::CheckedTransformer(on_off, CLI::ignore_case).description(""));
    app.add_option("--compare", out->compare,
                   "compare the trace with an image (PNG, BMP, PPM, JPEG, PFM, EXR): the reference "
                   "is rendered at its size from the file's camera, with --spp samples (default 1, "
                   "as raytrace)")
        ->type_name("IMAGE");
}

// raytrace's render flags, as the initial settings (the panel edits them afterwards).
void add_render_flags(CLI::App& app, RunOptions* out) {
    const std::string render_group = "render settings (raytrace's flags: the initial settings)";
    // The render options show their defaults (the viewer's own options say theirs in words).
    app.option_defaults()->always_capture_default();
    rtapp::add_render_options(app, out->render,
                              "the trace stops at N samples per pixel (the panel's target spp)",
                              render_group);
    app.add_option("--target-error", out->target_error,
                   "the trace also stops once the estimated relMSE is at most E (0: never)")
        ->type_name("E")
        ->group(render_group);
    rtapp::add_scene_options(app, out->render, true, render_group);
    rtapp::add_feature_options(app, out->render);
}

// --version: the version, and where this copy finds its shaders and scenes.
void print_version() {
    std::printf("%s\n", rtapp::version_text("rayview", true).c_str());
    try {
        std::printf("data: %s\n", rtapp::find_data_dir("shaders/preview.vert").c_str());
    } catch (const std::exception& e) {
        std::printf("data: %s\n", e.what());
    }
}

}  // namespace

int parse_run_options(int argc, char** argv, const std::string& default_scene, RunOptions* out) {
    out->scene = default_scene;
    std::string script_path, size;
    CLI::App app{
        "Opens a .ray scene in a window: the OpenGL preview beside its progressive ray trace."};
    rtapp::setup_cli(app, "rayview", true);
    add_viewer_options(app, out, &script_path, &size);
    app.get_formatter()->column_width(30);
    add_render_flags(app, out);
    app.footer(kFooter);
    try {
        app.parse(argc, argv);
        if (!size.empty() && !parse_size(size, &out->window_w, &out->window_h))
            throw CLI::ValidationError("--size", "'" + size + "' is not WxH (e.g. 1280x720)");
        rtapp::validate_render_options(out->render);
        rtapp::apply_budgets(out->render);
        if (!(out->target_error >= 0) || !std::isfinite(out->target_error))
            throw rtapp::UsageError("--target-error must be a finite number >= 0");
        out->spp_given = app.count("--spp") > 0;
    } catch (const CLI::CallForHelp&) {
        std::printf("%s", app.help().c_str());
        return 0;
    } catch (const CLI::CallForVersion&) {
        print_version();
        return 0;
    } catch (const std::exception& e) {  // CLI::ParseError, rtapp::UsageError
        std::fprintf(stderr, "rayview: %s (see rayview --help)\n", e.what());
        return 2;
    }
    if (!out->screenshot.empty() && out->frames == 0) out->frames = 60;
    if (!script_path.empty()) {
        try {
            out->script = read_script(script_path);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "rayview: %s\n", e.what());
            return 2;
        }
        for (const ScriptLine& l : out->script) out->frames = std::max(out->frames, l.frame + 2);
    }
    return -1;
}

rtapp::RenderOptions default_render_options() {
    rtapp::RenderOptions o;
    o.spp = ViewSettings().target_spp;
    return o;
}

void apply_run_options(const RunOptions& options, ViewSettings* settings) {
    const rtapp::RenderOptions& r = options.render;
    RenderSettings& s = settings->render;
    // Every render setting of the command line but those the viewer sets itself: the trace's
    // size (the pane's) and how its samples fall (progressive).
    const int trace_w = s.width, trace_h = s.height;
    const bool centre_first = s.centre_first_sample;
    s = r;
    s.width = trace_w;
    s.height = trace_h;
    s.centre_first_sample = centre_first;
    s.threads = resolve_thread_count(r.threads);
    settings->target_spp = r.spp;
    settings->target_error = options.target_error;
    settings->image_w = r.width;
    settings->image_h = r.height;
    settings->layout = options.layout;
    settings->show_panel = options.panel;
}

}  // namespace rt::view
