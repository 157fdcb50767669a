#include "cli_options.h"

#include <charconv>
#include <cmath>
#include <utility>

#include "rt/image/image.h"

namespace rt::cli {

std::string usage_text() {
    return R"(usage: raytrace SCENE.ray [options]

Renders a .ray scene (V0 or V1 dialect) with Whitted ray tracing.

options:
  -o, --output FILE   output image; format by extension: .png .bmp .ppm (8-bit) or .pfm
                      (float, unclamped)                                [out.png]
      --width N       image width in pixels                             [640]
      --height N      image height in pixels                            [480]
      --depth N       recursion depth of camera rays (>= 1)             [5]
      --cutoff X      skip child rays whose path weight is below X      [0.001]
      --spp N         samples per pixel; 1 = pixel centres, N > 1 = stratified jitter
                      (with a progressive feature on, every sample is jittered)  [1]
      --seed N        random seed of the jitter and the progressive features  [0]
      --threads N     worker threads, up to 256; 0 = all cores (the image is the same for
                      any count) [0]
      --no-shadows    no shadow rays (lights always visible)
      --dialect D     v0 or v1: override the dialect detected from the materials
      --stats         print time per phase (parse, compile, BVH build, render) and rays
                      per second by kind
      --explain       print what the renderer left out for this scene and why, one line
                      each ("left out: <feature>: <reason>"), and what it kept
      --no-specialize render with the generic renderer (every feature tested per ray, every
                      ray walks the top-level BVH and dispatches on each shape's kind)
                      instead of the one specialized to the scene; the image is the same

progressive rendering (the error of each pass, against run time):
      --progressive   render in passes of 1, 1, 2, 4, 8, ... samples per pixel until --time
                      or --spp is reached, and report the error of every pass
      --time S        stop after S seconds of rendering
      --reference R   a .pfm image to measure the error against, or 'auto' (rendered at
                      --reference-spp samples and cached); without it the error is
                      estimated from the samples themselves
      --reference-spp N  samples per pixel of the auto reference        [256]
      --report F.csv  one row per pass: mode,seconds,spp,rays,rmse,relmse,off_share,
                      estimate,estimate_relmse
      --plot F.svg    error against time on log-log axes, with fitted slopes
      --adaptive      also run adaptive sampling (samples go to the pixels with the largest
                      estimated error) and compare the time each needs to reach one error

progressive features (off by default; see scenes/README.md):
      --light-radius R    point and spot lights become spheres of radius R (soft shadows)
      --aperture A        lens radius A (depth of field)
      --focus-distance F  distance in focus along the view direction [scene centre]
      --roughness X       glossy reflection: mirror directions spread by X

  -q, --quiet         print errors and warnings only
  -h, --help          this text

exit status: 0 success, 1 scene error (printed as file:line:col: error: ...) or an output
that cannot be written, 2 usage error.
)";
}

namespace {

template <class T>
T number(const std::string& opt, const std::string& value) {
    T v{};
    const auto r = std::from_chars(value.data(), value.data() + value.size(), v);
    if (r.ec != std::errc() || r.ptr != value.data() + value.size())
        throw UsageError("option " + opt + " needs a number, got '" + value + "'");
    return v;
}

}  // namespace

Options parse_options(const std::vector<std::string>& args) {
    Options o;
    bool have_scene = false;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError("option " + a + " needs a value");
            return args[++i];
        };
        if (a == "-h" || a == "--help") {
            o.help = true;
        } else if (a == "-o" || a == "--output") {
            o.output = value();
        } else if (a == "--width") {
            o.width = number<int>(a, value());
        } else if (a == "--height") {
            o.height = number<int>(a, value());
        } else if (a == "--depth") {
            o.depth = number<int>(a, value());
        } else if (a == "--cutoff") {
            o.cutoff = number<double>(a, value());
        } else if (a == "--spp") {
            o.spp = number<int>(a, value());
            o.spp_given = true;
        } else if (a == "--progressive") {
            o.progressive = true;
        } else if (a == "--time") {
            o.time_limit_s = number<double>(a, value());
        } else if (a == "--reference") {
            o.reference = value();
        } else if (a == "--reference-spp") {
            o.reference_spp = number<int>(a, value());
        } else if (a == "--report") {
            o.report = value();
        } else if (a == "--plot") {
            o.plot = value();
        } else if (a == "--adaptive") {
            o.adaptive = true;
        } else if (a == "--light-radius") {
            o.light_radius = number<double>(a, value());
        } else if (a == "--aperture") {
            o.aperture = number<double>(a, value());
        } else if (a == "--focus-distance") {
            o.focus_distance = number<double>(a, value());
        } else if (a == "--roughness") {
            o.roughness = number<double>(a, value());
        } else if (a == "--seed") {
            o.seed = number<uint64_t>(a, value());
        } else if (a == "--threads") {
            o.threads = number<int>(a, value());
        } else if (a == "--no-shadows") {
            o.shadows = false;
        } else if (a == "--stats") {
            o.stats = true;
        } else if (a == "--explain") {
            o.explain = true;
        } else if (a == "--no-specialize") {
            o.specialize = false;
        } else if (a == "-q" || a == "--quiet") {
            o.quiet = true;
        } else if (a == "--dialect") {
            const std::string& d = value();
            if (d == "v0" || d == "V0")
                o.dialect = Dialect::V0;
            else if (d == "v1" || d == "V1")
                o.dialect = Dialect::V1;
            else
                throw UsageError("--dialect takes v0 or v1, got '" + d + "'");
        } else if (a.size() > 1 && a[0] == '-') {
            throw UsageError("unknown option '" + a + "'");
        } else if (!have_scene) {
            o.scene = a;
            have_scene = true;
        } else {
            throw UsageError("more than one scene file given ('" + o.scene + "' and '" + a + "')");
        }
    }
    if (o.help) return o;
    if (!have_scene) throw UsageError("no scene file given");
    if (o.width < 1 || o.height < 1 || o.width > 32768 || o.height > 32768)
        throw UsageError("--width and --height must be between 1 and 32768");
    if (o.depth < 1) throw UsageError("--depth must be at least 1");
    if (!(o.cutoff >= 0.0)) throw UsageError("--cutoff must not be negative");
    if (o.spp < 1) throw UsageError("--spp must be at least 1");
    if (o.threads < 0 || o.threads > 256) throw UsageError("--threads must be between 0 and 256");
    for (const auto& [name, v] : {std::pair<const char*, double>{"--light-radius", o.light_radius},
                                  {"--aperture", o.aperture},
                                  {"--focus-distance", o.focus_distance},
                                  {"--roughness", o.roughness},
                                  {"--time", o.time_limit_s}})
        if (!(v >= 0.0) || !std::isfinite(v))
            throw UsageError(std::string(name) + " must be a finite number >= 0");
    if (o.reference_spp < 2) throw UsageError("--reference-spp must be at least 2");
    const bool progressive_only = o.time_limit_s > 0 || !o.reference.empty() || !o.report.empty() ||
                                  !o.plot.empty() || o.adaptive;
    if (progressive_only && !o.progressive)
        throw UsageError("--time, --reference, --report, --plot and --adaptive need --progressive");
    if (o.progressive && o.time_limit_s <= 0 && !o.spp_given)
        throw UsageError("--progressive needs --time S or --spp N");
    if (!o.reference.empty() && o.reference != "auto" &&
        image_format_from_path(o.reference) != ImageFormat::Pfm)
        throw UsageError("--reference takes a .pfm file or 'auto'");
    if (image_format_from_path(o.output) == ImageFormat::Unknown)
        throw UsageError("unknown output format '" + o.output + "' (use .png, .bmp, .ppm or .pfm)");
    return o;
}

}  // namespace rt::cli
