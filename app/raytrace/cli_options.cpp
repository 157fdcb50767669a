#include "cli_options.h"

#include <charconv>

#include "rt/image.h"

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
      --spp N         samples per pixel; 1 = pixel centres, N > 1 = stratified jitter  [1]
      --seed N        random seed for N > 1 samples                     [0]
      --threads N     worker threads; 0 = all cores (the image is the same for any count) [0]
      --no-shadows    no shadow rays (lights always visible)
      --dialect D     v0 or v1: override the dialect detected from the materials
      --stats         print time per phase (parse, compile, BVH build, render) and rays
                      per second by kind
  -q, --quiet         print errors and warnings only
  -h, --help          this text

exit status: 0 success, 1 scene error (printed as file:line:col: error: ...), 2 usage error.
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
        } else if (a == "--seed") {
            o.seed = number<uint64_t>(a, value());
        } else if (a == "--threads") {
            o.threads = number<int>(a, value());
        } else if (a == "--no-shadows") {
            o.shadows = false;
        } else if (a == "--stats") {
            o.stats = true;
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
    if (o.threads < 0) throw UsageError("--threads must not be negative");
    if (image_format_from_path(o.output) == ImageFormat::Unknown)
        throw UsageError("unknown output format '" + o.output + "' (use .png, .bmp, .ppm or .pfm)");
    return o;
}

}  // namespace rt::cli
