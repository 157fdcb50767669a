#include "reference_cache.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "rt/render/render.h"
#include "rt/util/file_io.h"

namespace raytrace {

namespace {

namespace fs = std::filesystem;

// Part of the cache's key: bump it when the renderer's images change.
constexpr const char* kRendererVersion = "raytrace 0.4";

constexpr uint64_t kFnvOffset = 1469598103934665603ull;

// A 64-bit FNV-1a hash, for the cache's key.
uint64_t fnv1a(const std::string& data, uint64_t h = kFnvOffset) {
    for (unsigned char c : data) h = (h ^ c) * 1099511628211ull;
    return h;
}

std::string read_all(const std::string& path) {
    std::string text;
    return rt::read_file(path, &text) ? text : std::string();
}

// Every input file (scenes, textures, key files), the settings and the renderer's version.
uint64_t cache_key(const Options& opt, const rt::SceneDesc& desc) {
    uint64_t key = kFnvOffset;
    for (const rt::FileDesc& f : desc.files) {
        key = fnv1a(read_all(f.path), key);
        for (const rt::TextureDesc& t : f.textures) key = fnv1a(read_all(t.path), key);
        for (const std::string& k : f.key_files) key = fnv1a(read_all(k), key);
    }
    key = fnv1a(std::string(kRendererVersion) + rt::dialect_name(desc.dialect), key);
    char params[512];
    std::snprintf(params, sizeof params, "%d %d %d %.17g %d %.17g %.17g %.17g %.17g %d %llu",
                  opt.width, opt.height, opt.max_depth, opt.cutoff, opt.shadows ? 1 : 0,
                  opt.light_radius, opt.aperture, opt.focus_distance, opt.roughness,
                  opt.progressive.reference_spp, static_cast<unsigned long long>(opt.seed));
    return fnv1a(params, key);
}

fs::path cache_dir() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    return xdg && *xdg     ? fs::path(xdg) / "raytrace"
           : home && *home ? fs::path(home) / ".cache" / "raytrace"
                           : fs::path(".raytrace-cache");
}

// reference_spp samples with a seed independent of the measured run, in chunks of 16 with a
// count on a terminal.
rt::Image render_reference(const Options& opt, const rt::RenderScene& scene) {
    const int spp = opt.progressive.reference_spp;
    const bool tty = !opt.quiet && isatty(STDOUT_FILENO);
    rt::RenderSettings settings = opt;
    settings.seed = opt.seed + 0x5EED5EEDull;
    settings.centre_first_sample = false;  // the progressive sequence: unbiased in chunks
    rt::RenderState ref;
    const rt::RenderPlan plan = rt::make_render_plan(scene, settings);
    for (int done = 0; done < spp;) {
        const int n = std::min(16, spp - done);
        rt::render_samples(ref, scene, plan, settings, n);
        done += n;
        if (tty) {
            std::printf("\r  %d / %d spp", done, spp);
            std::fflush(stdout);
        }
    }
    if (tty) std::printf("\n");
    return ref.image();
}

// The reference image at `path`. load_pfm() opens it itself: a FIFO is refused first, not waited
// on.
rt::Image load_reference_file(const std::string& path) {
    if (const std::string why = rt::regular_file_error(path); !why.empty())
        throw std::runtime_error("--reference: " + why);
    return rt::load_pfm(path);
}

}  // namespace

rt::Image auto_reference(const Options& opt, const rt::SceneDesc& desc,
                         const rt::RenderScene& scene) {
    char name[64];
    std::snprintf(name, sizeof name, "reference-%016llx.pfm",
                  static_cast<unsigned long long>(cache_key(opt, desc)));
    const fs::path dir = cache_dir();
    const fs::path cached = dir / name;
    std::error_code ec;
    if (fs::exists(cached, ec)) {
        if (!opt.quiet) std::printf("reference %s (cached)\n", cached.string().c_str());
        return load_reference_file(cached.string());
    }
    if (!opt.quiet)
        std::printf("reference rendering %d spp (cached afterwards as %s)\n",
                    opt.progressive.reference_spp, cached.string().c_str());
    const rt::Image image = render_reference(opt, scene);
    fs::create_directories(dir, ec);
    try {
        rt::save_image(image, cached.string());
    } catch (const std::exception& e) {
        std::cerr << "raytrace: warning: reference not cached: " << e.what() << "\n";
    }
    return image;
}

std::optional<rt::Image> load_reference(const Options& opt, const rt::SceneDesc& desc,
                                        const rt::RenderScene& scene) {
    const std::string& path = opt.progressive.reference;
    if (path.empty()) return std::nullopt;
    rt::Image image = path == "auto" ? auto_reference(opt, desc, scene) : load_reference_file(path);
    if (image.width != opt.width || image.height != opt.height)
        throw std::runtime_error("reference '" + path + "' is " + std::to_string(image.width) +
                                 "x" + std::to_string(image.height) + ", the image is " +
                                 std::to_string(opt.width) + "x" + std::to_string(opt.height));
    return image;
}

}  // namespace raytrace
