#include "render_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <utility>

namespace rtapp {

namespace {

// CLI11 reads "-1" into an unsigned number as its two's complement; a seed must not wrap.
const CLI::Validator kNoMinus(
    [](const std::string& value) {
        return value.find('-') == std::string::npos ? std::string() : "must not be negative";
    },
    "");

}  // namespace

void add_render_options(CLI::App& app, RenderOptions& o, const std::string& spp_help,
                        const std::string& group) {
    app.add_option("--width", o.width, "image width in pixels")->type_name("N")->group(group);
    app.add_option("--height", o.height, "image height in pixels")->type_name("N")->group(group);
    app.add_option("--depth", o.max_depth,
                   "recursion depth of camera rays (1 to " + std::to_string(rt::kMaxDepth) + ")")
        ->type_name("N")
        ->group(group);
    app.add_option("--cutoff", o.cutoff, "skip child rays whose path weight is below X")
        ->type_name("X")
        ->group(group);
    app.add_option("--spp", o.spp, spp_help)->type_name("N")->group(group);
    app.add_option("--light-samples", o.light_samples,
                   "points per sphere light whose shadow rays give a point's shadow\n"
                   "factor (1 spp: strata centres; N > 1 spp: jittered strata;\n"
                   "progressive: one random point per sample)")
        ->type_name("N")
        ->group(group);
    app.add_option("--seed", o.seed, "random seed of the jitter and the progressive features")
        ->type_name("N")
        ->check(kNoMinus)
        ->group(group);
    app.add_option("--threads", o.threads,
                   "worker threads, up to " + std::to_string(rt::kMaxThreads) +
                       ", for the render and for loading\n"
                       "(parse and compile); 0 = all cores this process may use (the\n"
                       "image is the same for any count)")
        ->type_name("N")
        ->group(group);
    app.add_flag_callback(
           "--no-shadows", [&o] { o.shadows = false; }, "no shadow rays (lights always visible)")
        ->group(group);
    app.add_flag_callback(
           "--no-specialize", [&o] { o.specialize = false; },
           "render with the generic renderer (every feature tested per ray,\n"
           "every ray walks the top-level BVH and dispatches on each shape's\n"
           "kind) instead of the one specialized to the scene; the image is\n"
           "the same")
        ->group(group);
}

void add_scene_options(CLI::App& app, RenderOptions& o, bool with_dialect,
                       const std::string& group) {
    if (with_dialect)
        app.add_option_function<std::string>(
               "--dialect",
               [&o](const std::string& d) {
                   o.dialect = d == "v0"   ? rt::Dialect::V0
                               : d == "v1" ? rt::Dialect::V1
                                           : rt::Dialect::V3;
               },
               "v0, v1 or v3: override the dialect detected from the file tree")
            ->type_name("D")
            ->transform(CLI::IsMember({"v0", "v1", "v3"}, CLI::ignore_case))
            ->group(group);
    app.add_option_function<std::string>(
           "--missing-textures",
           [&o](const std::string& m) {
               o.missing_textures =
                   m == "checker" ? rt::MissingTextures::Checker : rt::MissingTextures::Error;
           },
           "error or checker: a texture that cannot be opened or decoded is an\n"
           "error, or a magenta/grey checker with a warning")
        ->type_name("M")
        ->transform(CLI::IsMember({"error", "checker"}, CLI::ignore_case))
        ->group(group);
    add_max_pixels_option(app, o.max_pixels, "the render, a texture, a reference", group);
}

void add_max_pixels_option(CLI::App& app, uint64_t& max_pixels, const std::string& images,
                           const std::string& group) {
    app.add_option("--max-pixels", max_pixels,
                   "the largest image in pixels (" + images +
                       ");\nlarger ones are refused before anything is allocated")
        ->type_name("N")
        ->check(kNoMinus)
        ->group(group);
}

void check_max_pixels(uint64_t max_pixels) {
    if (max_pixels < 1 || max_pixels > rt::kMaxImagePixelsLimit)
        throw UsageError("--max-pixels must be between 1 and " +
                         std::to_string(rt::kMaxImagePixelsLimit) + " (2^40)");
}

void add_feature_options(CLI::App& app, RenderOptions& o) {
    const std::string group = "progressive features (off by default; see docs/format.md)";
    app.add_option("--light-radius", o.light_radius,
                   "point and spot lights become spheres of radius R (soft shadows)")
        ->type_name("R")
        ->group(group);
    app.add_option("--aperture", o.aperture, "lens radius A (depth of field)")
        ->type_name("A")
        ->group(group);
    app.add_option("--focus-distance", o.focus_distance,
                   "distance in focus along the view direction (0: the scene centre)")
        ->type_name("F")
        ->group(group);
    app.add_option("--roughness", o.roughness, "glossy reflection: mirror directions spread by X")
        ->type_name("X")
        ->group(group);
}

void validate_render_options(const RenderOptions& o) {
    if (o.width < 1 || o.height < 1 || o.width > 32768 || o.height > 32768)
        throw UsageError("--width and --height must be between 1 and 32768");
    check_max_pixels(o.max_pixels);
    if (const std::string e =
            rt::image_size_error(static_cast<uint64_t>(o.width), static_cast<uint64_t>(o.height),
                                 "--width x --height: an image", o.max_pixels);
        !e.empty())
        throw UsageError(e);
    if (o.max_depth < 1 || o.max_depth > rt::kMaxDepth)
        throw UsageError("--depth must be between 1 and " + std::to_string(rt::kMaxDepth));
    if (!(o.cutoff >= 0.0)) throw UsageError("--cutoff must not be negative");
    if (o.spp < 1) throw UsageError("--spp must be at least 1");
    if (o.light_samples < 1 || o.light_samples > rt::kMaxLightSamples)
        throw UsageError("--light-samples must be between 1 and " +
                         std::to_string(rt::kMaxLightSamples));
    if (o.threads < 0 || o.threads > rt::kMaxThreads)
        throw UsageError("--threads must be between 0 and " + std::to_string(rt::kMaxThreads));
    for (const auto& [name, v] : {std::pair<const char*, double>{"--light-radius", o.light_radius},
                                  {"--aperture", o.aperture},
                                  {"--focus-distance", o.focus_distance},
                                  {"--roughness", o.roughness}})
        if (!(v >= 0.0) || !std::isfinite(v))
            throw UsageError(std::string(name) + " must be a finite number >= 0");
}

void apply_budgets(const RenderOptions& o) { rt::set_max_image_pixels(o.max_pixels); }

}  // namespace rtapp
