// What `raytrace` reports: the scene and timing summary on the terminal, and for progressive
// rendering the pass table, the fitted slopes, the time each mode needs to reach one error, the
// CSV report and the SVG plot. The library renders and measures; this file only presents.
#pragma once

#include <string>
#include <vector>

#include "options.h"
#include "rt/compile/compile.h"
#include "rt/render/plan.h"
#include "rt/render/progressive.h"
#include "rt/render/render.h"

namespace raytrace {

/// How relMSE is computed (rt::compare_images, with rt::kRelMseEpsilon = 0.01).
inline constexpr const char* kRelMseFormula =
    "relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01)";

/// One progressive run: "uniform" or "adaptive", and its passes.
struct ProgressRun {
    std::string mode;
    std::vector<rt::PassRecord> passes;
};

/// Wall-clock seconds of each phase of a plain render.
struct Timings {
    double parse_s = 0;
    double compile_s = 0;
    double render_s = 0;
};

/// A pass's error: relMSE against the reference when there is one, else the estimate.
double pass_error(const rt::PassRecord& r);

/// Time at which a run's error first reaches `target` (log-log interpolation between passes);
/// negative when it never does. Uses relMSE when there is a reference, else the estimate.
double time_to_reach(const std::vector<rt::PassRecord>& run, double target);

/// CSV: mode,seconds,spp,rays,rmse,relmse,off_share,estimate,estimate_relmse (one row a pass).
std::string progress_csv(const std::vector<ProgressRun>& runs);

/// An SVG plot of error against time on log-log axes, with the fitted slope of each run.
std::string progress_svg(const std::vector<ProgressRun>& runs, const std::string& title);

/// The scene's lights: their count and, when there are any, the count of each kind
/// ("3 (point 2, sphere 1)").
std::string light_summary(const rt::SceneDesc& desc);

/// The scene's summary (files, shapes by kind, lights, ...) and the render settings.
void print_scene_summary(const Options& opt, const rt::SceneDesc& desc,
                         const rt::CompileReport& report);

/// --explain: which renderer runs, and what it left out of this scene and why.
void print_explain(const rt::RenderPlan& plan);

/// A progress bar on stderr when it is a terminal (and not --quiet), else no callback, so
/// scripts and logs stay clean.
rt::ProgressFn terminal_progress_bar(bool quiet);

/// The time of each phase and the rays per second, one line each.
void print_render_summary(const Timings& t, const rt::RayCounters& rays);

/// --stats: the phase table and the rays of each kind per second of render time.
void print_stats(const Timings& t, double build_s, const rt::RayCounters& rays);

/// The pass table's title and header of one progressive run.
void print_pass_header(const std::string& mode, bool has_reference);

/// One row of the pass table.
void print_pass(const rt::PassRecord& r);

/// After the runs: the formula, each run's slope and, with two runs, the time each needs to
/// reach the uniform run's final error.
void print_progress_summary(const std::vector<ProgressRun>& runs, double target_relmse = 0);

}  // namespace raytrace
