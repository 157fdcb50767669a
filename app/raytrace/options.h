// Command-line options of `raytrace`: the library's settings extended with what only the program
// needs, so every setting is written once. Parsing never exits: it returns the options or throws
// UsageError, which main() turns into exit status 2.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "render_options.h"
#include "rt/format/parser.h"
#include "rt/render/aov.h"
#include "rt/render/mistakes.h"
#include "rt/render/progressive.h"
#include "rt/render/render.h"
#include "rt/scene/scene_desc.h"
#include "rt/scene/scene_time.h"

namespace raytrace {

using UsageError = rtapp::UsageError;

/// --progressive and its error report. The pass limits are the library's: time_limit_s is
/// --time, spp_limit is --spp when given; `adaptive` (--adaptive) adds an adaptive run after the
/// uniform one.
struct ProgressiveOptions : rt::ProgressiveSettings {
    bool enabled = false;   // --progressive
    std::string reference;  // a .pfm file, "auto", or empty
    int reference_spp = 256;
    std::string report;  // CSV
    std::string plot;    // SVG
};

/// Animation (spec §14.7): one frame at --at, or --frames frames at --fps from --start.
struct AnimationOptions {
    std::optional<double> at;
    rt::Interpolation interpolation = rt::Interpolation::CatmullRom;
    rt::Rotation rotation = rt::Rotation::Quaternion;
    int frames = 0;  // 0: one image
    double fps = 24;
    double start = 0;
    std::string video;         // --video: the frames encoded by ffmpeg
    std::optional<int> frame;  // --frame K: one frame of the sequence, at start + K / fps

    /// The render time of frame k of the sequence, or of the one image (none without --at).
    std::optional<rt::SceneTime> time(int k = 0) const;
};

/// A share of a split render: -o NAME.part with --tile and --samples.
struct SplitOptions {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // --tile; x1 = 0: the whole image
    uint32_t first = 0, count = 0;       // --samples A:B as first = A, count = B - A; 0: all
    bool tile = false;                   // --tile given
    bool part = false;                   // -o ends in .part
};

/// OpenEXR output (-o FILE.exr): 32-bit float channels and the AOV channels (rt/render/aov.h).
struct ExrOptions {
    bool full_float = false;  // --exr-float; else half
    rt::AovSet aovs;          // --aov
};

/// --inspect: the ray tree of one pixel sample instead of an image (rt/render/inspect.h).
struct InspectOptions {
    bool enabled = false;      // --inspect given
    int x = 0, y = 0;          // column, row from the top
    int sample = 0;            // --inspect-sample, of --spp's
    std::string json;          // --inspect-json FILE
    std::optional<int> depth;  // --inspect-depth N: rays deeper than N levels left out
    std::optional<int> light;  // --inspect-light K: only light K's terms
};

/// The render options rayview takes too (rtapp::RenderOptions: the renderer's settings, --spp,
/// --dialect, --missing-textures), and raytrace's own.
struct Options : rtapp::RenderOptions {
    std::string scene;
    std::string output = "out.png";
    bool quiet = false;
    bool stats = false;
    bool explain = false;  // print what the specialized renderer left out, and why
    ProgressiveOptions progressive;
    AnimationOptions animation;
    SplitOptions split;
    ExrOptions exr;
    InspectOptions inspect;
    std::vector<std::string> warnings;  // options that are accepted but have no effect
    bool help = false;
    bool version = false;  // --version
    // --mistake NAME (teaching only, docs/mistakes.md): render with at most two mistakes of the
    // catalogue switched on (rt/render/mistakes.h); --mistake list prints the catalogue.
    std::vector<std::string> mistake_names;
    rt::MistakeSet mistakes;
    bool mistake_list = false;
};

/// Parses argv (without argv[0]). Throws UsageError.
Options parse_options(const std::vector<std::string>& args);

/// The --help text, with every option's default.
std::string usage_text();

/// The catalogue of mistakes, one line each (--mistake list).
std::string mistake_list_text();

}  // namespace raytrace
