// raycompare: images of one scene (a class's renders) compared with the reference, rendered once
// per image size with raytrace's settings flags. Prints a table, writes CSV and an HTML report
// on request, and exits 0 only when every image passes.
// Exit status: 0 every image passes, 1 one fails or cannot be read (or the scene has an error,
// printed as file:line:col: error: ...), 2 usage error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "render_options.h"
#include "report.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
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
    std::string csv, html;
    bool quiet = false;
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
    app.add_option("--csv", o.csv, "also write the table as CSV")->type_name("FILE");
    app.add_option("--html", o.html,
                   "also write a report (DIR/index.html with the images, their heat\n"
                   "maps and figures, sortable) to open from disk")
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

bool linear_file(const std::string& path) {
    return rt::holds_linear(rt::image_format_from_path(path));
}

int run(const Options& o) {
    const std::optional<rt::RenderScene> scene = load_scene(o);
    if (!scene) return 1;
    std::vector<Row> rows;
    std::map<std::pair<int, int>, rt::Image> references;  // by size, rendered once each
    for (const std::string& path : o.images) {
        Row r;
        r.path = path;
        try {
            r.image = rt::load_image(path);
            r.width = r.image.width;
            r.height = r.image.height;
        } catch (const std::exception& e) {
            r.error = rtapp::error_text(e, "reading " + path);
            rows.push_back(std::move(r));
            continue;
        }
        auto it = references.find({r.width, r.height});
        if (it == references.end()) {
            rt::RenderSettings s = o;
            s.width = r.width;
            s.height = r.height;
            rt::RenderState state;
            rt::render_samples(state, *scene, rt::make_render_plan(*scene, s), s, o.spp);
            it = references.emplace(std::make_pair(r.width, r.height), state.image()).first;
            if (!o.quiet)
                std::fprintf(stderr, "raycompare: rendered the %dx%d reference (%d spp)\n", r.width,
                             r.height, o.spp);
        }
        rt::CompareSettings cs;
        cs.tolerance = o.limits.tolerance;
        cs.neighbourhood = o.limits.neighbourhood;
        cs.linear = linear_file(path);
        r.c = rt::compare_images(r.image, it->second, cs);
        r.pass = r.c.share_off <= o.limits.max_bad;
        rows.push_back(std::move(r));
    }
    const std::string table = table_text(rows, o.limits);
    if (o.quiet) {
        for (const Row& r : rows)
            if (!r.pass) std::printf("FAIL %s\n", r.path.c_str());
    } else {
        std::fputs(table.c_str(), stdout);
    }
    if (!o.csv.empty()) rt::write_file_atomic(o.csv, csv_text(rows));
    if (!o.html.empty()) {
        std::vector<Reference> refs;
        for (const auto& [size, image] : references)
            refs.push_back({size.first, size.second, image});
        write_html(o.html, o.scene, refs, rows, o.limits);
        if (!o.quiet) std::printf("wrote %s/index.html\n", o.html.c_str());
    }
    for (const Row& r : rows)
        if (!r.pass) return 1;
    return 0;
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
        std::cerr << "raycompare: error: " << rtapp::error_text(e, "comparing " + o.scene) << "\n";
        return 1;
    }
}
