// raycompare: images of one scene (a class's renders) compared with the reference, rendered once
// at the expected size (--size) with raytrace's settings flags. Prints a summary, the rule and a
// table, writes CSV, an HTML report and Gradescope's results.json on request, and exits 0 only
// when every image passes. The work on the images is
// compare_class.h's (one image at a time), the report's folder report_dir.h's.
// Exit status: 0 every image passes, 1 one fails or cannot be read (or the scene has an error,
// printed as file:line:col: error: ..., or an output cannot be written), 2 usage error (also a
// report folder of other files, or an output that is an input).
#include <sys/stat.h>

// GCC 12 at -O1 sees CLI11's split() move a string it cannot prove non-null (it is never null).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <CLI/CLI.hpp>
#pragma GCC diagnostic pop
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "compare_class.h"
#include "render_options.h"
#include "report.h"
#include "report_dir.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/mistakes.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/util/file_io.h"

namespace {

using namespace raycompare;

struct Options : rtapp::RenderOptions {
    // The size is each image's (read within --max-pixels), not the settings'.
    Options() { width = height = 1; }
    std::string scene;
    std::vector<std::string> images;
    Limits limits;
    std::string csv, html, gradescope, size = "first";
    bool quiet = false, diagnose = false;
};

void make_app(CLI::App& app, Options& o) {
    app.description(
        "Compares images of a .ray scene (students' renders) with the reference render of that\n"
        "scene at each image's size: mean absolute difference, share of pixels off, largest\n"
        "difference, pass or fail.");
    app.footer(
        "exit status: 0 every image passes, 1 an image fails or cannot be read, or the "
        "scene has an error (file:line:col: error: ...), 2 usage error.");
    app.get_formatter()->column_width(28);
    rtapp::setup_cli(app, "raycompare", true);
    app.option_defaults()->always_capture_default();
    app.add_option("scene", o.scene, "the .ray file")->type_name("SCENE.ray")->required();
    app.add_option("images", o.images,
                   "the images: PNG, BMP, PPM, JPEG (8-bit: compared as raytrace writes\n"
                   "them) or PFM and EXR (linear: compared unclamped)")
        ->type_name("IMAGE...")
        ->default_str("")
        ->required();
    app.add_option("--tolerance", o.limits.tolerance,
                   "a pixel is off when a channel differs by more than K (of 255)")
        ->type_name("K");
    app.add_option("--max-bad", o.limits.max_bad,
                   "an image passes with at most this share of its pixels off")
        ->type_name("S");
    app.add_flag("--neighbourhood", o.limits.neighbourhood,
                 "each pixel against the reference's 3x3 neighbourhood of it (the\n"
                 "smallest difference): an edge shifted by a pixel is no error");
    app.add_flag("--lossy", o.limits.lossy,
                 "the lossy rule for every image (always used for .jpg and .jpeg files):\n"
                 "each pixel's difference is that of the 3x3 means of both images, so\n"
                 "that a correct render saved as JPEG at quality 90 or more passes");
    app.add_option("--size", o.size,
                   "the size every image must have: WxH, 'first' (the first readable\n"
                   "image's) or 'any' (each image against a reference of its size); an\n"
                   "image of another size fails, saying so")
        ->type_name("WxH");
    app.add_option("--heat-scale", o.limits.heat_scale,
                   "the heat map's and the signed view's scale for the whole class: full\n"
                   "colour at K steps and beyond")
        ->type_name("K");
    app.add_option("--gradescope", o.gradescope,
                   "also write Gradescope's autograder results (results.json): one test\n"
                   "per image, 1 point for a pass, the reason as its output")
        ->type_name("FILE");
    app.add_flag("--diagnose", o.diagnose,
                 "for each failing 8-bit image, the typical mistakes (docs/mistakes.md)\n"
                 "that best explain it, ranked, each with the share of the difference it\n"
                 "explains: the reference rendered with each mistake on (once per size),\n"
                 "and the global fits (gamma, brightness, flips, channels, camera angle)");
    app.add_option("--csv", o.csv, "also write the table as CSV")->type_name("FILE");
    app.add_option("--html", o.html,
                   "also write a report (DIR/index.html with the images, their heat\n"
                   "maps and figures, sortable) to open from disk; DIR is new, empty\n"
                   "or an earlier report of raycompare's (whose files it replaces)")
        ->type_name("DIR");
    rtapp::add_render_options(app, o, "samples per pixel of the reference");
    // The reference takes each image's size.
    app.remove_option(app.get_option("--width"));
    app.remove_option(app.get_option("--height"));
    rtapp::add_scene_options(app, o, true);
    rtapp::add_feature_options(app, o);
    app.add_flag("-q,--quiet", o.quiet, "print the failures only");
}

// The scene parsed and compiled; nullopt after printing its error.
std::optional<rt::RenderScene> load_scene(const Options& o) {
    rt::Diagnostics diag;
    try {
        rt::ParseOptions po;
        po.dialect = o.dialect;
        po.missing_textures = o.missing_textures;
        const rt::SceneDesc desc = rt::parse_scene_file(o.scene, diag, po);
        for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
        return rt::compile_scene(desc);
    } catch (const rt::SceneError& e) {
        for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
        std::cerr << e.what() << "\n";
        return std::nullopt;
    }
}

// --size: WxH (each from 1 to 65535), "first" or "any", into limits' width and height.
void parse_size(const std::string& text, Limits& limits) {
    if (text == "first") {
        limits.width = limits.height = 0;
        return;
    }
    if (text == "any") {
        limits.width = limits.height = -1;
        return;
    }
    unsigned w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%5ux%5u%c", &w, &h, &tail) != 2 || w == 0 || h == 0 ||
        w > 65535 || h > 65535 || text.find_first_of("+- ") != std::string::npos)
        throw rtapp::UsageError("--size must be WxH (such as 160x120), 'first' or 'any', not '" +
                                escaped(text) + "'");
    limits.width = static_cast<int>(w);
    limits.height = static_cast<int>(h);
}

// The file named twice: `a` and `b` are the same file (by device and inode).
bool same_file(const std::string& a, const std::string& b) {
    struct stat sa = {};
    struct stat sb = {};
    return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

// The reference's settings at an image's size.
rt::RenderSettings settings_at(const Options& o, int width, int height) {
    rt::RenderSettings s = o;
    s.width = width;
    s.height = height;
    return s;
}

// --diagnose: the mutant references as their 8-bit files hold them, at the reference's spp; the
// catalogue's names; the camera's angle, to name a zoom.
Diagnoser make_diagnoser(const Options& o, const rt::RenderScene& scene) {
    Diagnoser d;
    d.render = [&o, &scene](int width, int height, const std::vector<std::string>& mistakes) {
        const rt::RenderSettings s = settings_at(o, width, height);
        return rt::render_written(scene, rt::make_render_plan(scene, s), s,
                                  rt::parse_mistakes(mistakes), o.spp);
    };
    for (const rt::MistakeInfo& m : rt::mistake_catalogue()) d.catalogue.push_back(m.name);
    d.settings.half_angle = scene.camera ? scene.camera->half_height_angle_rad : 0.0;
    return d;
}

// The CSV, Gradescope's results and the report's page, once the class is compared: 1 when one
// of them cannot be written (said), else 0.
int write_outputs(const Options& o, const ClassResult& result, const Limits& used,
                  ReportDir* report) {
    const std::vector<Row>& rows = result.rows;
    int status = 0;
    if (!o.csv.empty()) {
        try {
            rt::write_file_atomic(o.csv, csv_text(rows));
        } catch (const std::exception& e) {
            std::cerr << "raycompare: error: " << escaped(e.what()) << "\n";
            status = 1;
        }
    }
    if (!o.gradescope.empty()) {
        try {
            rt::write_file_atomic(o.gradescope, gradescope_json(o.scene, rows, used));
        } catch (const std::exception& e) {
            std::cerr << "raycompare: error: " << escaped(e.what()) << "\n";
            status = 1;
        }
    }
    if (report) {
        report->write_text(kPageName, page_html(o.scene, result.references, rows, used));
        if (!report->error().empty()) {
            std::cerr << "raycompare: error: the report in '" << escaped(o.html)
                      << "' is not complete: " << escaped(report->error()) << "\n";
            status = 1;
        } else if (!o.quiet) {
            std::printf("wrote %s/index.html\n", escaped(o.html).c_str());
        }
    }
    return status;
}

int run(const Options& o) {
    // The outputs first, so that a long run does not fail at its end: the CSV must be no input
    // (it would replace a student's image) and writable; the report's folder is taken once the
    // scene has loaded (a scene with an error leaves an earlier report as it was).
    std::vector<std::string> inputs = o.images;
    inputs.push_back(o.scene);
    for (const auto& [flag, file] : {std::pair<const char*, const std::string&>{"--csv", o.csv},
                                     {"--gradescope", o.gradescope}}) {
        if (file.empty()) continue;
        for (const std::string& in : inputs)
            if (same_file(file, in)) {
                std::cerr << "raycompare: error: " << flag << " '" << escaped(file)
                          << "' would replace '" << escaped(in)
                          << "', a file given to compare: give another file\n";
                return 2;
            }
        if (const std::string why = rt::writable_error(file); !why.empty()) {
            std::cerr << "raycompare: error: " << escaped(why) << "\n";
            return 1;
        }
    }
    const std::optional<rt::RenderScene> scene = load_scene(o);
    if (!scene) return 1;
    std::optional<ReportDir> report;
    if (!o.html.empty()) {
        if (!o.csv.empty()) inputs.push_back(o.csv);
        if (!o.gradescope.empty()) inputs.push_back(o.gradescope);
        try {
            report.emplace(o.html, inputs);
        } catch (const ReportDirError& e) {
            std::cerr << "raycompare: error: " << e.what() << "\n";
            return e.refused ? 2 : 1;
        }
    }

    const auto render = [&](int width, int height) {
        const rt::RenderSettings s = settings_at(o, width, height);
        rt::RenderState state;
        rt::render_samples(state, *scene, rt::make_render_plan(*scene, s), s, o.spp);
        return state.image();
    };
    const auto rendered = [&](int width, int height) {
        if (!o.quiet)
            std::fprintf(stderr, "raycompare: rendered the %dx%d reference (%d spp)\n", width,
                         height, o.spp);
    };
    const Diagnoser diagnoser = make_diagnoser(o, *scene);
    const ClassResult result =
        compare_class(o.images, render, o.limits, report ? &*report : nullptr, rendered,
                      o.diagnose ? &diagnoser : nullptr);
    if (o.diagnose && !o.quiet)
        std::fprintf(stderr, "raycompare: diagnosed with %zu mutant references\n",
                     result.mutant_renders);
    const std::vector<Row>& rows = result.rows;
    // The rule as it was used: the size the images were held to.
    Limits used = o.limits;
    used.width = result.width;
    used.height = result.height;

    if (o.quiet) {
        for (const Row& r : rows)
            if (!r.pass) std::printf("FAIL %s\n", escaped(r.path).c_str());
    } else {
        std::fputs(table_text(rows, used).c_str(), stdout);
    }
    int status = 0;
    for (const Row& r : rows)
        if (!r.pass) status = 1;
    return write_outputs(o, result, used, report ? &*report : nullptr) == 0 ? status : 1;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app;
    make_app(app, o);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
    }
    try {
        if (!(o.limits.tolerance >= 0) || !(o.limits.max_bad >= 0) || o.limits.max_bad > 1)
            throw rtapp::UsageError("--tolerance must be >= 0 and --max-bad in [0, 1]");
        if (!(o.limits.heat_scale > 0) || !std::isfinite(o.limits.heat_scale))
            throw rtapp::UsageError("--heat-scale must be > 0");
        parse_size(o.size, o.limits);
        rtapp::validate_render_options(o);
        rtapp::apply_budgets(o);
    } catch (const rtapp::UsageError& e) {
        std::cerr << "raycompare: " << e.what() << "\n(see raycompare --help)\n";
        return 2;
    }
    if (!rtapp::isa_usable("raycompare")) return 2;
    try {
        return run(o);
    } catch (const std::exception& e) {
        std::cerr << "raycompare: error: " << escaped(rtapp::error_text(e, "comparing " + o.scene))
                  << "\n";
        return 1;
    }
}
