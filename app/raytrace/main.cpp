// raytrace: the headless renderer. Loads a scene, renders it, writes the image. Errors are
// printed as file:line:col: error: ...; exit 1 for scene errors, 2 for usage errors. The output
// file appears only when everything succeeded.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_options.h"
#include "rt/parser.h"
#include "rt/render.h"
#include "rt/render_scene.h"

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

int run(const rt::cli::Options& opt) {
    rt::Diagnostics diag;
    auto print_warnings = [&]() {
        for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
    };

    // The output must be writable before any work is done (a long render must not fail at the end).
    {
        namespace fs = std::filesystem;
        const fs::path out(opt.output);
        const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
        std::error_code ec;
        if (!fs::is_directory(dir, ec)) {
            std::cerr << "raytrace: error: cannot write '" << opt.output << "': no directory '"
                      << dir.string() << "'\n";
            return 1;
        }
        if (fs::is_directory(out, ec)) {
            std::cerr << "raytrace: error: cannot write '" << opt.output
                      << "': it is a directory\n";
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
    const rt::RenderScene scene = rt::compile_scene(desc);
    const double compile_s = seconds_since(t_compile);

    rt::RenderSettings settings;
    settings.width = opt.width;
    settings.height = opt.height;
    settings.max_depth = opt.depth;
    settings.cutoff = opt.cutoff;
    settings.shadows = opt.shadows;
    settings.threads = opt.threads;
    settings.seed = opt.seed;

    const rt::SceneStats& st = scene.stats;
    if (!opt.quiet) {
        std::printf("scene     %s (%s, %zu file%s)\n", opt.scene.c_str(),
                    rt::dialect_name(scene.dialect), st.files, st.files == 1 ? "" : "s");
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

    const auto t_render = Clock::now();
    rt::RenderState state;
    rt::render_samples(state, scene, settings, opt.spp, progress);
    const double render_s = seconds_since(t_render);

    rt::Image image = state.image();
    const size_t bad = rt::count_non_finite(image);
    if (bad > 0) {
        for (double& v : image.rgb)
            if (!std::isfinite(v)) v = 0.0;
        std::cerr << opt.scene << ": warning: " << bad << " non-finite pixel values written as 0\n";
    }
    try {
        rt::save_image(image, opt.output);
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
        const double build_s = scene.stats.build_seconds;
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
