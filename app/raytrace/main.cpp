// raytrace: the headless renderer. Loads a scene, renders it, writes the image. Errors are
// printed as file:line:col: error: ...; exit 1 for scene errors, 2 for usage errors. The output
// files appear only when everything succeeded.
#include <cstdio>
#include <iostream>
#include <new>
#include <optional>
#include <utility>

#include "cli.h"
#include "frames.h"
#include "inspect.h"
#include "options.h"
#include "output.h"
#include "reference_cache.h"
#include "report.h"
#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/mistakes.h"
#include "rt/render/progressive.h"
#include "rt/render/render.h"
#include "rt/util/stopwatch.h"
#include "sequence.h"
#include "split.h"
#include "version.h"

namespace {

using namespace raytrace;

// Parses and compiles the scene, printing its warnings and errors; nullopt on an error.
std::optional<rt::RenderScene> load_scene(const Options& opt, rt::SceneDesc* desc,
                                          rt::CompileReport* report, Timings* t) {
    rt::Diagnostics diag;
    bool warned = false;  // the parser's warnings, printed once
    auto print_warnings = [&]() {
        if (!std::exchange(warned, true))
            for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
    };
    try {
        const auto t_parse = rt::Clock::now();
        rt::ParseOptions parse_options;
        parse_options.dialect = opt.dialect;
        parse_options.missing_textures = opt.missing_textures;
        parse_options.threads = static_cast<unsigned>(opt.threads);
        *desc = rt::parse_scene_file(opt.scene, diag, parse_options);
        t->parse_s = rt::seconds_since(t_parse);
        print_warnings();
        const auto t_compile = rt::Clock::now();
        // Errors: file:line:col too. At --at's time, or frame 0's of --frames. What follows
        // reads the description's files, lights and tracks, not its meshes: they are freed as
        // soon as they are compiled.
        rt::Diagnostics compile_diag;
        rt::RenderScene scene =
            rt::compile_scene_releasing(*desc, report, opt.animation.time(0), &compile_diag,
                                        static_cast<unsigned>(opt.threads));
        for (const rt::Warning& w : compile_diag.warnings()) std::cerr << w.str() << "\n";
        t->compile_s = rt::seconds_since(t_compile);
        return scene;
    } catch (const rt::SceneError& e) {
        print_warnings();
        std::cerr << e.what() << "\n";
        return std::nullopt;
    } catch (const std::bad_alloc& e) {
        print_warnings();
        std::cerr << "raytrace: error: " << rtapp::error_text(e, "loading " + opt.scene) << "\n";
        return std::nullopt;
    }
}

// The AOVs written and the time of their pass (rt/render/aov.h), when some were asked for.
void print_aovs(const Options& opt, double seconds) {
    if (opt.exr.aovs.any())
        std::printf("aovs      %s (%.3f s)\n", rt::aov_list(opt.exr.aovs).c_str(), seconds);
}

int render_plain(const Options& opt, const rt::RenderScene& scene, const rt::RenderPlan& plan,
                 const rt::CompileReport& report, Timings t) {
    const auto t_render = rt::Clock::now();
    rt::RenderState state;
    rt::render_samples(state, scene, plan, opt, opt.spp, terminal_progress_bar(opt.quiet));
    t.render_s = rt::seconds_since(t_render);
    const auto t_aovs = rt::Clock::now();
    const ExrOutput exr = exr_output(opt, state, scene, plan);
    const double aovs_s = rt::seconds_since(t_aovs);
    write_outputs(state.image(), opt.output, {}, opt.scene, exr);
    if (!opt.quiet) {
        print_render_summary(t, state.rays);
        print_aovs(opt, aovs_s);
        std::printf("wrote     %s\n", opt.output.c_str());
    }
    if (opt.stats) print_stats(t, report.build_seconds, state.rays);
    return 0;
}

// --mistake: the image as a program with those mistakes renders and writes it (teaching only).
int render_mistaken(const Options& opt, const rt::RenderScene& scene, const rt::RenderPlan& plan,
                    const rt::CompileReport& report, Timings t) {
    const auto t_render = rt::Clock::now();
    rt::RenderState state;
    rt::render_with_mistakes(state, scene, plan, opt, opt.mistakes, opt.spp,
                             terminal_progress_bar(opt.quiet));
    t.render_s = rt::seconds_since(t_render);
    rt::Image image = state.image();
    // The output stage's mistakes are in the 8 bits: any output holds those.
    if (opt.mistakes.touches(rt::MistakeStage::Output)) image = rt::as_written(image, opt.mistakes);
    write_outputs(image, opt.output, {}, opt.scene);
    if (!opt.quiet) {
        print_render_summary(t, state.rays);
        std::printf("mistakes  %s (teaching only: not the spec's image)\n",
                    opt.mistakes.names().c_str());
        std::printf("wrote     %s\n", opt.output.c_str());
    }
    if (opt.stats) print_stats(t, report.build_seconds, state.rays);
    return 0;
}

// The uniform run, and with --adaptive an adaptive one, each printed pass by pass.
std::vector<ProgressRun> run_passes(const Options& opt, const rt::RenderScene& scene,
                                    const rt::RenderPlan& plan, const rt::Image* reference,
                                    rt::RenderState& state) {
    std::vector<ProgressRun> runs;
    for (const bool adaptive : {false, true}) {
        if (adaptive && !opt.progressive.adaptive) break;
        rt::ProgressiveSettings ps = opt.progressive;
        ps.adaptive = adaptive;
        const std::string mode = adaptive ? "adaptive" : "uniform";
        if (!opt.quiet) print_pass_header(mode, reference != nullptr);
        auto on_pass = [&](const rt::PassRecord& r) {
            if (!opt.quiet) print_pass(r);
        };
        runs.push_back(
            {mode, rt::run_progressive(state, scene, plan, opt, ps, reference, on_pass)});
    }
    return runs;
}

int render_progressive(const Options& opt, const rt::SceneDesc& desc, const rt::RenderScene& scene,
                       const rt::RenderPlan& plan) {
    const std::optional<rt::Image> reference = load_reference(opt, desc, scene);
    rt::RenderState state;
    const std::vector<ProgressRun> runs =
        run_passes(opt, scene, plan, reference ? &*reference : nullptr, state);
    if (!opt.quiet) print_progress_summary(runs, opt.progressive.target_relmse);
    std::vector<TextFile> texts;
    const ProgressiveOptions& p = opt.progressive;
    if (!p.report.empty()) texts.emplace_back(p.report, progress_csv(runs));
    if (!p.plot.empty())
        texts.emplace_back(p.plot, progress_svg(runs, "Error against render time: " + opt.scene));
    const auto t_aovs = rt::Clock::now();
    const ExrOutput exr = exr_output(opt, state, scene, plan);  // the last run's samples
    const double aovs_s = rt::seconds_since(t_aovs);
    write_outputs(state.image(), opt.output, texts, opt.scene, exr);
    if (!opt.quiet) {
        print_aovs(opt, aovs_s);
        std::printf("wrote     %s\n", opt.output.c_str());
    }
    return 0;
}

int run(const Options& opt) {
    const bool sequence = opt.animation.frames > 0;
    const std::string first = opt.inspect.enabled ? opt.inspect.json
                              : sequence          ? rtapp::frame_path(opt.output, 0)
                                                  : opt.output;
    if (!probe_outputs({first, opt.progressive.report, opt.progressive.plot, opt.animation.video}))
        return 1;
    for (const std::string& w : opt.warnings) std::cerr << "raytrace: warning: " << w << "\n";
    rt::SceneDesc desc;
    rt::CompileReport report;
    report.record_locations = opt.inspect.enabled;  // the tree names each primitive's directive
    Timings t;
    std::optional<rt::RenderScene> scene = load_scene(opt, &desc, &report, &t);
    if (!scene) return 1;
    if (!opt.quiet) print_scene_summary(opt, desc, report);
    if (desc.tracks.empty() && (opt.animation.at || sequence))
        std::cerr << opt.scene << ": warning: the scene has no joints bound to key files; "
                  << (sequence ? "every frame is the same" : "--at changes nothing") << "\n";
    if (opt.inspect.enabled) {
        if (opt.explain) print_explain(rt::make_render_plan(*scene, opt));
        return run_inspect(opt, desc, *scene, report);
    }
    if (sequence) {
        if (opt.explain) print_explain(rt::make_render_plan(*scene, opt));
        return render_sequence(opt, desc, *scene, t);
    }
    if (opt.split.part) return render_part_output(opt, desc, *scene, t);
    const rt::RenderPlan plan = rt::make_render_plan(*scene, opt);
    if (opt.explain) print_explain(plan);  // also with --quiet: it was asked for
    if (!opt.mistakes.empty()) return render_mistaken(opt, *scene, plan, report, t);
    return opt.progressive.enabled ? render_progressive(opt, desc, *scene, plan)
                                   : render_plain(opt, *scene, plan, report, t);
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    try {
        opt = parse_options(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const UsageError& e) {
        std::cerr << "raytrace: " << e.what() << "\n(see raytrace --help)\n";
        return 2;
    }
    if (opt.help) {
        std::cout << usage_text();
        return 0;
    }
    if (opt.version) {
        std::cout << rtapp::version_text("raytrace", true) << "\n";
        return 0;
    }
    if (opt.mistake_list) {
        std::cout << mistake_list_text();
        return 0;
    }
    if (!rtapp::isa_usable("raytrace")) return 2;
    try {
        return run(opt);
    } catch (const std::exception& e) {
        std::cerr << "raytrace: error: " << rtapp::error_text(e, "rendering " + opt.scene) << "\n";
        return 1;
    }
}
