#include "options.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <utility>

#include "cli.h"
#include "frames.h"
#include "rt/image/image.h"

namespace raytrace {

namespace {

constexpr const char* kDescription =
    "Renders a .ray scene (V0, V1 or V3 dialect) with Whitted ray tracing.";
constexpr const char* kFooter =
    "exit status: 0 success, 1 scene error (printed as file:line:col: error: ...), an input or\n"
    "an output that cannot be read or written, a failed frame or running out of memory,\n"
    "2 usage error.";

// CLI11 parses every option straight into its field of `o`; the help shows each field's
// default as it is when the options are added (the defaults of Options and RenderSettings).
void add_render_options(CLI::App& app, Options& o) {
    app.add_option("scene", o.scene, "the .ray file")->type_name("SCENE.ray")->required();
    app.add_option("-o,--output", o.output,
                   "output image; format by extension: .png .bmp .ppm (8-bit), .pfm\n"
                   "(float, unclamped) or .exr (OpenEXR: half or float, unclamped)")
        ->type_name("FILE");
    rtapp::add_render_options(app, o,
                              "samples per pixel; 1 = pixel centres, N > 1 = stratified jitter\n"
                              "(with a progressive feature on, every sample is jittered)");
    rtapp::add_scene_options(app, o, true);
    app.add_flag("--stats", o.stats,
                 "print time per phase (parse, compile, BVH build, render) and rays\n"
                 "per second by kind");
    app.add_flag("--explain", o.explain,
                 "print what the renderer left out for this scene and why, one line\n"
                 "each (\"left out: <feature>: <reason>\"), and what it kept");
}

void add_progressive_options(CLI::App& app, Options& o) {
    const std::string group = "progressive rendering (the error of each pass, against run time)";
    ProgressiveOptions& p = o.progressive;
    app.add_flag("--progressive", p.enabled,
                 "render in passes of 1, 1, 2, 4, 8, ... samples per pixel until\n"
                 "--time, --spp or --target-error is reached, and report the error\n"
                 "of every pass")
        ->group(group);
    app.add_option("--time", p.time_limit_s, "stop after S seconds of rendering")
        ->type_name("S")
        ->group(group);
    app.add_option("--target-error", p.target_relmse,
                   "stop once the estimated relMSE (the 'estimate' column) is at most\n"
                   "E, from 8 samples per pixel on (with --time or --spp: whichever\n"
                   "comes first)")
        ->type_name("E")
        ->group(group);
    app.add_option("--reference", p.reference,
                   "a .pfm image to measure the error against, or 'auto' (rendered\n"
                   "at --reference-spp samples and cached); without it the error is\n"
                   "estimated from the samples themselves")
        ->type_name("R")
        ->group(group);
    app.add_option("--reference-spp", p.reference_spp, "samples per pixel of the auto reference")
        ->type_name("N")
        ->group(group);
    app.add_option("--report", p.report,
                   "one row per pass: mode,seconds,spp,rays,rmse,relmse,off_share,\n"
                   "estimate,estimate_relmse")
        ->type_name("F.csv")
        ->group(group);
    app.add_option("--plot", p.plot, "error against time on log-log axes, with fitted slopes")
        ->type_name("F.svg")
        ->group(group);
    app.add_flag("--adaptive", p.adaptive,
                 "also run adaptive sampling (samples go to the pixels with the\n"
                 "largest estimated error) and compare the time each needs to reach\n"
                 "one error")
        ->group(group);
}

// A name of spec §14.7 into `out`, or a usage error listing the accepted ones.
template <class T>
std::function<void(const std::string&)> enum_option(const char* what, T* out,
                                                    bool (*parse)(const std::string&, T*),
                                                    const std::string& accepted) {
    return [=](const std::string& name) {
        if (!parse(name, out))
            throw CLI::ValidationError(
                std::string("--") + what,
                "unknown " + std::string(what) + " '" + name + "' (accepted: " + accepted + ")");
    };
}

void add_animation_options(CLI::App& app, Options& o) {
    const std::string group = "animation (key-framed joints, spec §14)";
    AnimationOptions& a = o.animation;
    app.add_option("--at", a.at,
                   "render the frame at T seconds (negative and large times wrap\n"
                   "around each key file's loop); without it joints hold key 0")
        ->type_name("T")
        ->group(group);
    app.add_option_function<std::string>(
           "--interpolation",
           enum_option("interpolation", &a.interpolation, rt::parse_interpolation,
                       rt::interpolation_names()),
           "nearest, linear, catmull-rom (default) or bspline")
        ->type_name("I")
        ->group(group);
    app.add_option_function<std::string>(
           "--rotation",
           enum_option("rotation", &a.rotation, rt::parse_rotation, rt::rotation_names()),
           "matrix, closest, euler, log or quaternion (default)")
        ->type_name("R")
        ->group(group);
    app.add_option("--frames", a.frames,
                   "render N frames, frame k at --start + k / --fps, into -o's\n"
                   "pattern (frame_%04d.png); a frame that fails removes those\n"
                   "written before it")
        ->type_name("N")
        ->group(group);
    app.add_option("--fps", a.fps, "frames per second of --frames")->type_name("F")->group(group);
    app.add_option("--start", a.start, "the time of frame 0 of --frames")
        ->type_name("S")
        ->group(group);
    app.add_option("--video", a.video, "also encode the frames with ffmpeg (when it is installed)")
        ->type_name("FILE.mp4")
        ->group(group);
    app.add_option("--frame", a.frame, "render frame K of the sequence alone (--start + K / --fps)")
        ->type_name("K")
        ->group(group);
}

// OpenEXR output: the precision and the AOV channels (rt/render/aov.h); validate() checks that
// -o is an .exr file.
void add_output_options(CLI::App& app, Options& o) {
    const std::string group = "OpenEXR output (-o FILE.exr; linear, unclamped)";
    ExrOptions& e = o.exr;
    app.add_flag("--exr-float", e.full_float, "32-bit float channels instead of half")
        ->group(group);
    app.add_option_function<std::string>(
           "--aov",
           [&e](const std::string& list) {
               e.aovs = {};
               std::string name;
               std::istringstream in(list);
               bool any = false;
               while (std::getline(in, name, ',')) {
                   if (!rt::add_aov(name, &e.aovs))
                       throw CLI::ValidationError("--aov", "unknown AOV '" + name +
                                                               "' (accepted: " + rt::aov_names() +
                                                               ", comma-separated)");
                   any = true;
               }
               if (!any || list.back() == ',')
                   throw CLI::ValidationError(
                       "--aov",
                       "'" + list + "' is not a comma-separated list of " + rt::aov_names());
           },
           "extra channels, comma-separated: albedo (Albedo.RGB: the first\n"
           "hit's diffuse colour), normal (Ns.XYZ: its shading normal, world\n"
           "space), depth (depth.Z: its distance from the camera, +inf for no\n"
           "hit), samples (Samples.N), variance (Variance.RGB: the samples'\n"
           "variance); means over each pixel's samples (depth: those that hit)")
        ->type_name("LIST")
        ->group(group);
}

// "X0,Y0,X1,Y1" and "A:B" into the split options; CLI11 keeps the text, validate() the ranges.
void add_split_options(CLI::App& app, Options& o) {
    const std::string group = "split renders (merge the parts with raymerge; docs/cluster.md)";
    SplitOptions& sp = o.split;
    app.add_option_function<std::string>(
           "--tile",
           [&sp](const std::string& v) {
               char c1 = 0, c2 = 0, c3 = 0;
               std::istringstream in(v);
               if (!(in >> sp.x0 >> c1 >> sp.y0 >> c2 >> sp.x1 >> c3 >> sp.y1) || c1 != ',' ||
                   c2 != ',' || c3 != ',' || !in.eof())
                   throw CLI::ValidationError("--tile", "'" + v + "' is not X0,Y0,X1,Y1");
               sp.tile = true;
           },
           "render only pixels [X0, X1) x [Y0, Y1) into -o NAME.part")
        ->type_name("X0,Y0,X1,Y1")
        ->group(group);
    app.add_option_function<std::string>(
           "--samples",
           [&sp](const std::string& v) {
               long long a = 0, b = 0;
               char colon = 0;
               std::istringstream in(v);
               if (!(in >> a >> colon >> b) || colon != ':' || !in.eof() || a < 0 || b <= a ||
                   b > (1LL << 31))
                   throw CLI::ValidationError("--samples",
                                              "'" + v + "' is not A:B with 0 <= A < B");
               sp.first = static_cast<uint32_t>(a);
               sp.count = static_cast<uint32_t>(b - a);
           },
           "render only samples A..B-1 of --spp's of every pixel into -o NAME.part")
        ->type_name("A:B")
        ->group(group);
}

// Thrown by --mistake list: the catalogue is printed, nothing else is parsed or checked.
struct MistakeListRequested {};

// --mistake NAME (repeatable or comma-separated); validate_mistakes() reads the names.
void add_mistake_options(CLI::App& app, Options& o) {
    const std::string group = "teaching only: a typical mistake switched on (docs/mistakes.md)";
    app.add_option("--mistake", o.mistake_names,
                   "render the scene WRONGLY, with the mistake NAME of the catalogue\n"
                   "switched on in the renderer's own code (at most two: repeat it or\n"
                   "give NAME,NAME), to show what it looks like; 'list' prints the\n"
                   "catalogue. Not the spec's image")
        ->each([](const std::string& v) {
            if (v == "list") throw MistakeListRequested{};
        })
        ->type_name("NAME")
        ->default_str("")
        ->allow_extra_args(false)  // one value per --mistake (the scene is not swallowed)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->group(group);
}

void validate_mistakes(Options& o) {
    if (o.mistake_names.empty()) return;
    try {
        o.mistakes = rt::parse_mistakes(o.mistake_names);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--mistake: ") + e.what());
    }
    if (o.mistakes.list().size() > 2)
        throw UsageError("--mistake: at most two mistakes at once, not " + o.mistakes.names());
    if (o.progressive.enabled || o.animation.frames > 0 || o.split.part || o.inspect.enabled ||
        o.exr.aovs.any())
        throw UsageError(
            "--mistake renders one plain image: not with --progressive, --frames, a .part "
            "output, --inspect or --aov");
}

// "X,Y" into the inspect options; validate_inspect() checks the ranges against the image.
void add_inspect_options(CLI::App& app, Options& o) {
    const std::string group = "the ray tree of a pixel (docs/inspect.md)";
    InspectOptions& in = o.inspect;
    app.add_option_function<std::string>(
           "--inspect",
           [&in](const std::string& v) {
               // Spaces around the numbers are allowed (a quoted "1, 2 " from a script), as
               // >> skips them before each number; anything else after Y is not.
               char comma = 0;
               std::istringstream s(v);
               if (!(s >> in.x >> comma >> in.y) || comma != ',' || !(s >> std::ws).eof())
                   throw CLI::ValidationError("--inspect", "'" + v + "' is not X,Y");
               in.enabled = true;
           },
           "print every ray traced for pixel X,Y (column, row from the top, in\n"
           "the output's size) with every term of its colour, then the pixel's\n"
           "value; renders that pixel only and writes no image")
        ->type_name("X,Y")
        ->group(group);
    app.add_option("--inspect-sample", in.sample, "which of the pixel's --spp samples (from 0)")
        ->type_name("K")
        ->group(group);
    app.add_option_function<std::string>(
           "--inspect-json",
           [&in](const std::string& v) {
               if (v.empty()) throw CLI::ValidationError("--inspect-json", "needs a file name");
               in.json = v;
           },
           "also write the tree as JSON (docs/inspect.md)")
        ->type_name("FILE")
        ->group(group);
    // The filters of a long tree (rt::filter_tree): what is shown, not what is traced.
    app.add_option("--inspect-depth", in.depth,
                   "show the rays down to level N only (the camera ray is 1, as --depth\n"
                   "counts); each ray left out is counted with the rays below it")
        ->type_name("N")
        ->group(group);
    app.add_option("--inspect-light", in.light,
                   "show light K's terms and shadow rays only (K from 0, in the\n"
                   "scene's order)")
        ->type_name("K")
        ->group(group);
}

void make_app(CLI::App& app, Options& o) {
    app.description(kDescription);
    app.footer(kFooter);
    app.get_formatter()->column_width(28);
    // A repeated option takes its last value, as before CLI11 (scripts/run.sh passes -o and
    // forwards the user's own arguments after it).
    rtapp::setup_cli(app, "raytrace", true);
    app.option_defaults()->always_capture_default();
    add_render_options(app, o);
    add_output_options(app, o);
    add_progressive_options(app, o);
    rtapp::add_feature_options(app, o);
    add_animation_options(app, o);
    add_split_options(app, o);
    add_inspect_options(app, o);
    app.add_flag("-q,--quiet", o.quiet, "print errors and warnings only");
    add_mistake_options(app, o);
}

void validate_split(const Options& o) {
    const SplitOptions& sp = o.split;
    const bool tile = sp.tile, samples = sp.count > 0;
    if ((tile || samples) && !sp.part)
        throw UsageError("--tile and --samples write a partial result: -o must end in .part");
    if (!sp.part) return;
    if (o.progressive.enabled) throw UsageError("a .part output is not progressive: use --spp N");
    if (o.animation.frames > 0) throw UsageError("a .part output is one frame: use --frame K");
    if (tile && (sp.x0 < 0 || sp.y0 < 0 || sp.x0 >= sp.x1 || sp.y0 >= sp.y1 || sp.x1 > o.width ||
                 sp.y1 > o.height))
        throw UsageError("--tile " + std::to_string(sp.x0) + "," + std::to_string(sp.y0) + "," +
                         std::to_string(sp.x1) + "," + std::to_string(sp.y1) +
                         " is not inside the " + std::to_string(o.width) + "x" +
                         std::to_string(o.height) + " image");
    if (samples && sp.first + static_cast<uint64_t>(sp.count) > static_cast<uint64_t>(o.spp))
        throw UsageError("--samples " + std::to_string(sp.first) + ":" +
                         std::to_string(sp.first + sp.count) + " is not inside the --spp " +
                         std::to_string(o.spp) + " samples");
}

void validate_animation(const Options& o) {
    const AnimationOptions& a = o.animation;
    if (a.at && !std::isfinite(*a.at)) throw UsageError("--at must be a finite number");
    if (a.frame && (*a.frame < 0 || a.at || a.frames > 0))
        throw UsageError("--frame K: K >= 0, without --at or --frames");
    if (a.frames < 0) throw UsageError("--frames must be at least 1");
    if (!(a.fps > 0) || !std::isfinite(a.fps))
        throw UsageError("--fps must be a finite number > 0");
    if (!std::isfinite(a.start)) throw UsageError("--start must be a finite number");
    if (a.frames == 0 && (!a.video.empty())) throw UsageError("--video needs --frames N");
    if (a.frames > 0) {
        if (a.at) throw UsageError("--at renders one frame; a sequence starts at --start");
        if (o.progressive.enabled)
            throw UsageError("--progressive renders one image, not --frames");
        try {
            rtapp::frame_path(o.output, 0);  // -o must be a pattern
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("-o: ") + e.what());
        }
        if (!a.video.empty() && a.video.find('.') == std::string::npos)
            throw UsageError("--video needs a file name with an extension (out.mp4)");
    }
}

void validate_inspect(const Options& o, bool output_given) {
    const InspectOptions& in = o.inspect;
    if (!in.enabled) {
        if (in.sample != 0 || !in.json.empty() || in.depth || in.light)
            throw UsageError(
                "--inspect-sample, --inspect-json, --inspect-depth and --inspect-light need "
                "--inspect X,Y");
        return;
    }
    if (in.depth && *in.depth < 1)
        throw UsageError("--inspect-depth " + std::to_string(*in.depth) +
                         ": N counts levels of rays from 1 (the camera ray only)");
    if (in.light && *in.light < 0)
        throw UsageError("--inspect-light " + std::to_string(*in.light) +
                         ": K is a light's number in the scene, from 0");
    if (in.x < 0 || in.y < 0 || in.x >= o.width || in.y >= o.height)
        throw UsageError(
            "--inspect " + std::to_string(in.x) + "," + std::to_string(in.y) + " is outside the " +
            std::to_string(o.width) + "x" + std::to_string(o.height) + " image (X in 0.." +
            std::to_string(o.width - 1) + ", Y in 0.." + std::to_string(o.height - 1) + ")");
    if (in.sample < 0 || in.sample >= o.spp)
        throw UsageError("--inspect-sample " + std::to_string(in.sample) +
                         " is not one of the pixel's --spp " + std::to_string(o.spp) +
                         " samples (0.." + std::to_string(o.spp - 1) + ")");
    if (output_given) throw UsageError("--inspect writes no image: drop -o (or --inspect)");
    if (o.progressive.enabled || o.animation.frames > 0 || o.split.tile || o.split.count > 0)
        throw UsageError(
            "--inspect explains one pixel of one image: not with --progressive, --frames, "
            "--tile or --samples");
}

// The checks across options and of ranges, after CLI11 has converted every value.
void validate(Options& o, bool spp_given, bool output_given) {
    rtapp::validate_render_options(o);
    const ProgressiveOptions& p = o.progressive;
    for (const auto& [name, v] : {std::pair<const char*, double>{"--time", p.time_limit_s},
                                  {"--target-error", p.target_relmse}})
        if (!(v >= 0.0) || !std::isfinite(v))
            throw UsageError(std::string(name) + " must be a finite number >= 0");
    if (p.reference_spp < 2) throw UsageError("--reference-spp must be at least 2");
    const bool progressive_only = p.time_limit_s > 0 || p.target_relmse > 0 ||
                                  !p.reference.empty() || !p.report.empty() || !p.plot.empty() ||
                                  p.adaptive;
    if (progressive_only && !p.enabled)
        throw UsageError(
            "--time, --target-error, --reference, --report, --plot and --adaptive need "
            "--progressive");
    if (p.enabled && p.time_limit_s <= 0 && !spp_given && p.target_relmse <= 0)
        throw UsageError("--progressive needs --time S, --spp N or --target-error E");
    if (!p.reference.empty() && p.reference != "auto" &&
        rt::image_format_from_path(p.reference) != rt::ImageFormat::Pfm)
        throw UsageError("--reference takes a .pfm file or 'auto'");
    validate_split(o);
    if (!o.split.part && rt::image_format_from_path(o.output) == rt::ImageFormat::Unknown)
        throw UsageError("unknown output format '" + o.output +
                         "' (use .png, .bmp, .ppm, .pfm, .exr, or .part for a split render)");
    if ((o.exr.aovs.any() || o.exr.full_float) &&
        rt::image_format_from_path(o.output) != rt::ImageFormat::Exr)
        throw UsageError("--aov and --exr-float need an OpenEXR output (-o FILE.exr), not '" +
                         o.output + "'");
    validate_animation(o);
    validate_inspect(o, output_given);
    validate_mistakes(o);
}

}  // namespace

std::optional<rt::SceneTime> AnimationOptions::time(int k) const {
    if (frames == 0 && !at && !frame) return std::nullopt;
    const double t = frames > 0 ? start + k / fps : frame ? start + *frame / fps : *at;
    return rt::SceneTime{t, interpolation, rotation};
}

std::string usage_text() {
    Options o;
    CLI::App app("", "raytrace");
    make_app(app, o);
    return app.help();
}

std::string mistake_list_text() {
    std::string s = "The catalogue of mistakes (teaching only; docs/mistakes.md):\n";
    for (const rt::MistakeInfo& m : rt::mistake_catalogue()) {
        std::string line = "  " + std::string(m.name);
        line.resize(std::max<size_t>(line.size() + 1, 26), ' ');
        std::string stage = rt::stage_name(m.stage);
        stage.resize(8, ' ');
        std::string section = m.section;  // padded by characters, not UTF-8 bytes ("§")
        const size_t chars = static_cast<size_t>(std::count_if(
            section.begin(), section.end(), [](char c) { return (c & 0xC0) != 0x80; }));
        section.append(chars < 11 ? 11 - chars : 1, ' ');
        s += line + stage + " " + section + m.description + "\n";
    }
    return s;
}

Options parse_options(const std::vector<std::string>& args) {
    Options o;
    CLI::App app("", "raytrace");
    make_app(app, o);
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them reversed
    try {
        app.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        o.help = true;
        return o;
    } catch (const CLI::CallForVersion&) {
        o.version = true;
        return o;
    } catch (const MistakeListRequested&) {
        o.mistake_list = true;
        return o;
    } catch (const CLI::ParseError& e) {
        throw UsageError(e.what());
    }
    const bool spp_given = app.count("--spp") > 0;
    o.split.part = o.output.size() > 5 && o.output.compare(o.output.size() - 5, 5, ".part") == 0;
    validate(o, spp_given, app.count("--output") > 0);
    rtapp::apply_budgets(o);
    if (o.split.part) {  // the defaults: the whole image, every sample
        if (!o.split.tile) o.split.x1 = o.width, o.split.y1 = o.height;
        if (o.split.count == 0) o.split.count = static_cast<uint32_t>(o.spp);
    }
    // Spec §14.7: without a time they have no effect.
    if ((app.count("--interpolation") > 0 || app.count("--rotation") > 0) && !o.animation.at &&
        o.animation.frames == 0)
        o.warnings.push_back(
            "--interpolation and --rotation have no effect without --at or "
            "--frames: the joints hold key 0");
    if (spp_given && o.progressive.enabled) o.progressive.spp_limit = o.spp;
    return o;
}

}  // namespace raytrace
