// raytrace: the headless renderer. Loads a scene, renders it, writes the image. Errors are
// printed as file:line:col: error: ...; exit 1 for scene errors, 2 for usage errors. The output
// file appears only when everything succeeded.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli_options.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/progressive.h"
#include "rt/render/render.h"
#include "rt/util/file_io.h"

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string si(double v) {
    char buf[32];
    if (v >= 1e9)
        std::snprintf(buf, sizeof buf, "%.2f G", v / 1e9);
    else if (v >= 1e6)
        std::snprintf(buf, sizeof buf, "%.2f M", v / 1e6);
    else if (v >= 1e3)
        std::snprintf(buf, sizeof buf, "%.2f k", v / 1e3);
    else
        std::snprintf(buf, sizeof buf, "%.0f ", v);
    return buf;
}

// Creates and removes path.part: the directory exists, is writable, and path is no directory.
bool probe_writable(const std::string& path, std::string* why) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        *why = "it is a directory";
        return false;
    }
    const std::string probe = path + ".part";
    {
        std::ofstream f(probe, std::ios::binary);
        if (!f) {
            *why = "cannot create files there";
            return false;
        }
    }
    fs::remove(probe, ec);
    return true;
}

// Spec §9: non-finite values must not occur; if one does, save_image writes it as 0 and the
// user gets a warning with the count.
void save_final_image(const rt::Image& image, const rt::cli::Options& opt) {
    if (const size_t bad = rt::count_non_finite(image))
        std::cerr << opt.scene << ": warning: " << bad << " non-finite pixel values written as 0\n";
    rt::save_image(image, opt.output);
}

// ---- progressive mode ------------------------------------------------------------------------

// Part of the reference cache's key: bump it when the renderer's images change.
constexpr const char* kRendererVersion = "raytrace 0.4";

// A 64-bit FNV-1a hash, for the reference cache's key.
uint64_t fnv1a(const std::string& data, uint64_t h = 1469598103934665603ull) {
    for (unsigned char c : data) h = (h ^ c) * 1099511628211ull;
    return h;
}

std::string read_all(const std::string& path) {
    std::string text;
    return rt::read_file(path, &text) ? text : std::string();
}

// The reference image for --reference auto: rendered once at reference_spp samples with an
// independent seed, cached under ~/.cache/raytrace keyed by the scene files and the settings.
rt::Image auto_reference(const rt::cli::Options& opt, const rt::SceneDesc& desc,
                         const rt::RenderScene& scene, const rt::RenderSettings& settings) {
    namespace fs = std::filesystem;
    uint64_t key = 1469598103934665603ull;
    // Every input file (scenes, textures, key files), the settings and the renderer's version.
    for (const rt::FileDesc& f : desc.files) {
        key = fnv1a(read_all(f.path), key);
        for (const rt::TextureDesc& t : f.textures) key = fnv1a(read_all(t.path), key);
        for (const std::string& k : f.key_files) key = fnv1a(read_all(k), key);
    }
    key = fnv1a(std::string(kRendererVersion) + rt::dialect_name(desc.dialect), key);
    char params[512];
    std::snprintf(params, sizeof params, "%d %d %d %.17g %d %.17g %.17g %.17g %.17g %d %llu",
                  settings.width, settings.height, settings.max_depth, settings.cutoff,
                  settings.shadows ? 1 : 0, settings.light_radius, settings.aperture,
                  settings.focus_distance, settings.roughness, opt.reference_spp,
                  static_cast<unsigned long long>(settings.seed));
    key = fnv1a(params, key);
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    const fs::path dir = xdg && *xdg     ? fs::path(xdg) / "raytrace"
                         : home && *home ? fs::path(home) / ".cache" / "raytrace"
                                         : fs::path(".raytrace-cache");
    char name[64];
    std::snprintf(name, sizeof name, "reference-%016llx.pfm", static_cast<unsigned long long>(key));
    const fs::path cached = dir / name;
    std::error_code ec;
    if (fs::exists(cached, ec)) {
        if (!opt.quiet) std::printf("reference %s (cached)\n", cached.string().c_str());
        return rt::load_pfm(cached.string());
    }
    if (!opt.quiet)
        std::printf("reference rendering %d spp (cached afterwards as %s)\n", opt.reference_spp,
                    cached.string().c_str());
    rt::RenderSettings ref_settings = settings;
    ref_settings.seed = settings.seed + 0x5EED5EEDull;  // independent of the measured run
    ref_settings.centre_first_sample = false;  // the progressive sequence: unbiased in chunks
    rt::RenderState ref;
    const rt::RenderPlan ref_plan = rt::make_render_plan(scene, ref_settings);
    for (int done = 0; done < opt.reference_spp;) {
        const int n = std::min(16, opt.reference_spp - done);
        rt::render_samples(ref, scene, ref_plan, ref_settings, n);
        done += n;
        if (!opt.quiet && isatty(STDOUT_FILENO)) {
            std::printf("\r  %d / %d spp", done, opt.reference_spp);
            std::fflush(stdout);
        }
    }
    if (!opt.quiet && isatty(STDOUT_FILENO)) std::printf("\n");
    const rt::Image image = ref.image();
    fs::create_directories(dir, ec);
    try {
        rt::save_image(image, cached.string());
    } catch (const std::exception& e) {
        std::cerr << "raytrace: warning: reference not cached: " << e.what() << "\n";
    }
    return image;
}

// Writes text to path.part; the caller renames it once every output is written.
void write_part(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".part";
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    f.close();
    if (!f) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot write '" + path + "'");
    }
}

int run_progressive(const rt::cli::Options& opt, const rt::SceneDesc& desc,
                    const rt::RenderScene& scene, const rt::RenderSettings& settings) {
    rt::Image reference;
    bool have_reference = false;
    try {
        if (opt.reference == "auto") {
            reference = auto_reference(opt, desc, scene, settings);
            have_reference = true;
        } else if (!opt.reference.empty()) {
            reference = rt::load_pfm(opt.reference);
            have_reference = true;
        }
        if (have_reference &&
            (reference.width != settings.width || reference.height != settings.height))
            throw std::runtime_error(
                "reference '" + opt.reference + "' is " + std::to_string(reference.width) + "x" +
                std::to_string(reference.height) + ", the image is " +
                std::to_string(settings.width) + "x" + std::to_string(settings.height));
    } catch (const std::exception& e) {
        std::cerr << "raytrace: error: " << e.what() << "\n";
        return 1;
    }

    rt::ProgressiveSettings ps;
    ps.time_limit_s = opt.time_limit_s;
    ps.spp_limit = opt.spp_given ? opt.spp : 0;
    std::vector<std::pair<std::string, std::vector<rt::PassRecord>>> runs;
    rt::RenderState state;
    for (const bool adaptive : {false, true}) {
        if (adaptive && !opt.adaptive) break;
        ps.adaptive = adaptive;
        const char* mode = adaptive ? "adaptive" : "uniform";
        if (!opt.quiet) {
            std::printf("\n%s sampling%s\n%10s %10s %12s %12s %12s %10s %12s\n", mode,
                        have_reference ? "" : " (no reference: estimated error only)", "seconds",
                        "spp", "rays", "rmse", "relmse", "off>1/255", "estimate");
        }
        auto on_pass = [&](const rt::PassRecord& r) {
            if (opt.quiet) return;
            if (r.has_reference)
                std::printf("%10.3f %10.2f %12llu %12.4g %12.4g %9.2f%% %12.4g\n", r.seconds, r.spp,
                            static_cast<unsigned long long>(r.rays), r.error.rmse, r.error.relmse,
                            100 * r.error.off_share, r.estimate.relmse);
            else
                std::printf("%10.3f %10.2f %12llu %12s %12s %10s %12.4g\n", r.seconds, r.spp,
                            static_cast<unsigned long long>(r.rays), "-", "-", "-",
                            r.estimate.relmse);
            std::fflush(stdout);
        };
        runs.emplace_back(mode,
                          rt::run_progressive(state, scene, settings, ps,
                                              have_reference ? &reference : nullptr, on_pass));
    }
    if (!opt.quiet) {
        std::printf(
            "\n%s\nestimate = the same from the samples alone (variance of each pixel's "
            "mean)\n",
            rt::kRelMseFormula);
        for (const auto& [mode, run] : runs) {
            std::vector<double> t, e;
            for (const rt::PassRecord& r : run) {
                t.push_back(r.seconds);
                e.push_back(rt::pass_error(r));
            }
            std::printf("%s: relMSE falls as time^%.2f (least squares on log-log axes)\n",
                        mode.c_str(), rt::loglog_slope(t, e));
        }
        if (runs.size() == 2 && !runs[0].second.empty()) {
            const rt::PassRecord& last = runs[0].second.back();
            const double target = rt::pass_error(last);
            const double tu = rt::time_to_reach(runs[0].second, target);
            const double ta = rt::time_to_reach(runs[1].second, target);
            std::printf("time to reach relMSE %.4g: uniform %.3f s, adaptive %s", target, tu,
                        ta > 0 ? "" : "never within the limit\n");
            if (ta > 0) std::printf("%.3f s (%.2fx)\n", ta, tu / ta);
        }
    }
    // All or nothing: the report and the plot go to temporary files first, the image is written
    // (atomically), then the temporary files take their names.
    std::vector<std::string> parts;
    try {
        if (!opt.report.empty()) {
            write_part(opt.report, rt::progress_csv(runs));
            parts.push_back(opt.report);
        }
        if (!opt.plot.empty()) {
            write_part(opt.plot, rt::progress_svg(runs, "Error against render time: " + opt.scene));
            parts.push_back(opt.plot);
        }
        save_final_image(state.image(), opt);
        for (const std::string& p : parts) std::filesystem::rename(p + ".part", p);
    } catch (const std::exception& e) {
        std::error_code ec;
        for (const std::string& p : parts) std::filesystem::remove(p + ".part", ec);
        std::cerr << "raytrace: error: " << e.what() << "\n";
        return 1;
    }
    if (!opt.quiet) std::printf("wrote     %s\n", opt.output.c_str());
    return 0;
}

int run(const rt::cli::Options& opt) {
    rt::Diagnostics diag;
    auto print_warnings = [&]() {
        for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
    };

    // Every output must be writable before any work is done (a long render must not fail at
    // the end): each is probed by creating and removing its temporary file.
    for (const std::string& out : {opt.output, opt.report, opt.plot}) {
        if (out.empty()) continue;
        std::string why;
        if (!probe_writable(out, &why)) {
            std::cerr << "raytrace: error: cannot write '" << out << "': " << why << "\n";
            return 1;
        }
    }

    const auto t_parse = Clock::now();
    rt::ParseOptions parse_options;
    parse_options.dialect = opt.dialect;
    rt::SceneDesc desc;
    try {
        desc = rt::parse_scene_file(opt.scene, diag, parse_options);
    } catch (const rt::SceneError& e) {
        print_warnings();
        std::cerr << e.what() << "\n";
        return 1;
    }
    const double parse_s = seconds_since(t_parse);
    print_warnings();

    const auto t_compile = Clock::now();
    rt::RenderScene scene;
    rt::CompileReport st;
    try {
        scene =
            rt::compile_scene(desc, &st);  // its errors (geometry beyond 1e300) carry file:line:col
    } catch (const rt::SceneError& e) {
        std::cerr << e.what() << "\n";
        return 1;
    }
    const double compile_s = seconds_since(t_compile);

    rt::RenderSettings settings;
    settings.width = opt.width;
    settings.height = opt.height;
    settings.max_depth = opt.depth;
    settings.cutoff = opt.cutoff;
    settings.shadows = opt.shadows;
    settings.threads = opt.threads;
    settings.seed = opt.seed;
    settings.light_radius = opt.light_radius;
    settings.aperture = opt.aperture;
    settings.focus_distance = opt.focus_distance;
    settings.roughness = opt.roughness;
    settings.specialize = opt.specialize;
    const rt::RenderPlan plan = rt::make_render_plan(scene, settings);

    if (!opt.quiet) {
        std::printf("scene     %s (%s, %zu file%s)\n", opt.scene.c_str(),
                    rt::dialect_name(desc.dialect), st.files, st.files == 1 ? "" : "s");
        std::printf("shapes   ");
        for (int k = 0; k < 5; ++k)
            std::printf(" %s %zu%s", rt::shape_kind_name(static_cast<rt::ShapeKind>(k)),
                        st.prims_by_kind[k], k < 4 ? "," : "");
        std::printf("  (after instancing; %zu unique; %zu degenerate skipped)\n", st.unique_prims,
                    st.skipped_shapes);
        std::printf("triangles %zu, lights %zu, materials %zu, textures %zu, instances %zu\n",
                    st.prims_by_kind[static_cast<int>(rt::ShapeKind::Triangle)], st.lights,
                    st.materials, st.textures, st.instances);
        std::printf("render    %dx%d, %d spp, depth %d, cutoff %g, shadows %s, %d threads\n",
                    opt.width, opt.height, opt.spp, opt.depth, opt.cutoff,
                    opt.shadows ? "on" : "off", rt::resolve_thread_count(opt.threads));
        std::fflush(stdout);
    }
    if (opt.explain) {
        // Also with --quiet: it was asked for.
        std::printf("renderer  %s\n", opt.specialize
                                          ? "specialized to the scene (--no-specialize: generic)"
                                          : "generic (--no-specialize): every feature kept");
        for (const rt::PlanReason& reason : plan.reasons)
            std::printf("%s\n", rt::reason_line(reason).c_str());
        std::fflush(stdout);
    }

    // A progress bar on a terminal only (stderr), so scripts and logs stay clean.
    const bool tty = isatty(STDERR_FILENO) && !opt.quiet;
    auto last_draw = Clock::now();
    rt::ProgressFn progress;
    if (tty) {
        progress = [&](int done, int total) {
            if (done < total && seconds_since(last_draw) < 0.1) return;
            last_draw = Clock::now();
            const int width = 40;
            const int filled = total > 0 ? width * done / total : width;
            std::fprintf(stderr, "\r[%s%s] %3d%%",
                         std::string(static_cast<size_t>(filled), '#').c_str(),
                         std::string(static_cast<size_t>(width - filled), '.').c_str(),
                         total > 0 ? 100 * done / total : 100);
            if (done >= total) std::fprintf(stderr, "\r%*s\r", width + 8, "");
            std::fflush(stderr);
        };
    }

    if (opt.progressive) return run_progressive(opt, desc, scene, settings);

    const auto t_render = Clock::now();
    rt::RenderState state;
    rt::render_samples(state, scene, plan, settings, opt.spp, progress);
    const double render_s = seconds_since(t_render);

    try {
        save_final_image(state.image(), opt);
    } catch (const std::exception& e) {
        std::cerr << "raytrace: error: " << e.what() << "\n";
        return 1;
    }

    if (!opt.quiet) {
        const double rays = static_cast<double>(state.rays.total());
        std::printf("time      parse %.3f s, compile %.3f s, render %.3f s\n", parse_s, compile_s,
                    render_s);
        std::printf(
            "rays      %sray/s (%s rays: camera %llu, shadow %llu, reflected %llu, "
            "refracted %llu)\n",
            si(render_s > 0 ? rays / render_s : 0).c_str(), si(rays).c_str(),
            static_cast<unsigned long long>(state.rays.camera),
            static_cast<unsigned long long>(state.rays.shadow),
            static_cast<unsigned long long>(state.rays.reflected),
            static_cast<unsigned long long>(state.rays.refracted));
        std::printf("wrote     %s\n", opt.output.c_str());
    }
    if (opt.stats) {
        const double build_s = st.build_seconds;
        std::printf("\nphase            seconds\n");
        std::printf("parse         %10.3f\n", parse_s);
        std::printf("compile       %10.3f   (of which BVH build %.3f)\n", compile_s, build_s);
        std::printf("render        %10.3f\n", render_s);
        std::printf("total         %10.3f\n", parse_s + compile_s + render_s);
        std::printf("\nrays               count     per second of render time\n");
        const std::pair<const char*, uint64_t> kinds[] = {{"camera", state.rays.camera},
                                                          {"shadow", state.rays.shadow},
                                                          {"reflected", state.rays.reflected},
                                                          {"refracted", state.rays.refracted},
                                                          {"all", state.rays.total()}};
        for (const auto& [name, n] : kinds)
            std::printf("%-10s %12llu     %sray/s\n", name, static_cast<unsigned long long>(n),
                        si(render_s > 0 ? static_cast<double>(n) / render_s : 0).c_str());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    rt::cli::Options opt;
    try {
        opt = rt::cli::parse_options(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const rt::cli::UsageError& e) {
        std::cerr << "raytrace: " << e.what() << "\n(see raytrace --help)\n";
        return 2;
    }
    if (opt.help) {
        std::cout << rt::cli::usage_text();
        return 0;
    }
    try {
        return run(opt);
    } catch (const std::exception& e) {
        std::cerr << "raytrace: error: " << e.what() << "\n";
        return 1;
    }
}
