// Command-line options of `raytrace`. Parsing never exits: it returns the options or throws
// UsageError, which main() turns into exit code 2.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rt/scene/scene_desc.h"

namespace rt::cli {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Options {
    std::string scene;
    std::string output = "out.png";
    int width = 640;
    int height = 480;
    int depth = 5;
    double cutoff = 0.001;
    int spp = 1;
    int threads = 0;
    bool shadows = true;
    std::optional<Dialect> dialect;
    bool quiet = false;
    bool stats = false;
    bool explain = false;    // print what the specialized renderer left out, and why
    bool specialize = true;  // false: --no-specialize, the generic renderer
    bool spp_given = false;
    // Progressive rendering and its error report.
    bool progressive = false;
    double time_limit_s = 0;
    std::string reference;  // a .pfm file, "auto", or empty
    int reference_spp = 256;
    std::string report;  // CSV
    std::string plot;    // SVG
    bool adaptive = false;
    // Progressive features (each off at 0).
    double light_radius = 0;
    double aperture = 0;
    double focus_distance = 0;
    double roughness = 0;
    bool help = false;
    uint64_t seed = 0;
};

/// Parses argv (without argv[0]). Throws UsageError.
Options parse_options(const std::vector<std::string>& args);

/// The --help text.
std::string usage_text();

}  // namespace rt::cli
