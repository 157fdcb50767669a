// The render settings that raytrace and rayview both take on the command line, added to either
// program's CLI11 parser by one function each, so the two programs spell, document and check
// them alike (rayview takes them as its initial settings).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "rt/format/parser.h"
#include "rt/render/render.h"
#include "rt/util/limits.h"

namespace CLI {
class App;
}

namespace rtapp {

/// A usage error: the program prints it and exits 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// rt::RenderSettings (what the renderer reads) plus the samples per pixel and how scenes load.
struct RenderOptions : rt::RenderSettings {
    int spp = 1;                         // raytrace: the samples; rayview: where the trace stops
    std::optional<rt::Dialect> dialect;  // overrides the dialect detected from the file tree
    rt::MissingTextures missing_textures = rt::MissingTextures::Error;  // --missing-textures
    uint64_t max_pixels = rt::kDefaultMaxImagePixels;  // --max-pixels: the image budget
};

/// --width --height --depth --cutoff --spp --light-samples --seed --threads --no-shadows
/// --no-specialize, each into its field of `o`; the help shows the values `o` holds now as the
/// defaults. `spp_help` says what --spp means to the program; `group`, the help's heading.
void add_render_options(CLI::App& app, RenderOptions& o, const std::string& spp_help,
                        const std::string& group = "Options");

/// How scenes load: --missing-textures, --max-pixels, and --dialect when `with_dialect`.
void add_scene_options(CLI::App& app, RenderOptions& o, bool with_dialect,
                       const std::string& group = "Options");

/// --max-pixels N, the image budget, into `max_pixels`; `images` says which images it bounds
/// (add_scene_options adds it; raymerge, which loads no scene, takes it alone).
void add_max_pixels_option(CLI::App& app, uint64_t& max_pixels, const std::string& images,
                           const std::string& group = "Options");

/// --max-pixels' range, 1 to rt::kMaxImagePixelsLimit. Throws UsageError.
void check_max_pixels(uint64_t max_pixels);

/// The progressive features (--light-radius --aperture --focus-distance --roughness), in their
/// own help group.
void add_feature_options(CLI::App& app, RenderOptions& o);

/// The ranges of those options (after CLI11 has converted them), --width x --height within
/// --max-pixels among them. Throws UsageError.
void validate_render_options(const RenderOptions& o);

/// Puts the options' process-wide budgets in force (rt::set_max_image_pixels), before any file
/// is read: call it once validate_render_options has passed.
void apply_budgets(const RenderOptions& o);

}  // namespace rtapp
