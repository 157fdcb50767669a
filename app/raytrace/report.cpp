#include "report.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <memory>

#include "rt/util/isa.h"
#include "rt/util/light_kind.h"
#include "rt/util/stopwatch.h"

namespace raytrace {

namespace {

// printf into a std::string of any length.
__attribute__((format(printf, 1, 2))) std::string format(const char* fmt, ...) {
    va_list args, again;
    va_start(args, fmt);
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, fmt, args);
    va_end(args);
    std::string s(static_cast<size_t>(std::max(n, 0)) + 1, '\0');
    std::vsnprintf(s.data(), s.size(), fmt, again);
    va_end(again);
    s.resize(static_cast<size_t>(std::max(n, 0)));
    return s;
}

// A count with an SI prefix: "1.23 M".
std::string si(double v) {
    if (v >= 1e9) return format("%.2f G", v / 1e9);
    if (v >= 1e6) return format("%.2f M", v / 1e6);
    if (v >= 1e3) return format("%.2f k", v / 1e3);
    return format("%.0f ", v);
}

unsigned long long ull(uint64_t v) { return static_cast<unsigned long long>(v); }

std::string escape_xml(const std::string& in) {
    std::string out;
    for (char c : in)
        out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
    return out;
}

// The plot's frame in pixels and its log10 ranges (whole decades) over every point.
struct PlotArea {
    double W = 720, H = 480, left = 80, right = 200, top = 50, bottom = 60;
    double lt0 = 0, lt1 = 1, le0 = 0, le1 = 1;  // log10 of the time and error ranges

    double x(double t) const {
        return left + (std::log10(t) - lt0) / (lt1 - lt0) * (W - left - right);
    }
    double y(double e) const {
        return H - bottom - (std::log10(e) - le0) / (le1 - le0) * (H - top - bottom);
    }
};

PlotArea plot_area(const std::vector<ProgressRun>& runs) {
    double tmin = std::numeric_limits<double>::infinity(), tmax = 0;
    double emin = std::numeric_limits<double>::infinity(), emax = 0;
    for (const ProgressRun& run : runs)
        for (const rt::PassRecord& r : run.passes) {
            const double es[2] = {r.has_reference ? r.error.relmse : 0, r.estimate.relmse};
            for (double e : es)
                if (e > 0 && r.seconds > 0) {
                    tmin = std::min(tmin, r.seconds), tmax = std::max(tmax, r.seconds);
                    emin = std::min(emin, e), emax = std::max(emax, e);
                }
        }
    if (!(tmax > 0)) tmin = 0.01, tmax = 1, emin = 1e-4, emax = 1;
    PlotArea a;
    a.lt0 = std::floor(std::log10(tmin));
    a.lt1 = std::max(a.lt0 + 1, std::ceil(std::log10(tmax)));
    a.le0 = std::floor(std::log10(emin));
    a.le1 = std::max(a.le0 + 1, std::ceil(std::log10(emax)));
    return a;
}

std::string svg_open(const PlotArea& a, const std::string& title) {
    return format(
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
               "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%%\" "
               "height=\"100%%\" fill=\"white\"/>\n",
               a.W, a.H) +
           format("<text x=\"%.0f\" y=\"24\" font-size=\"15\">%s</text>\n", a.left,
                  escape_xml(title).c_str());
}

// A grid line and a label at every decade of both axes.
std::string svg_grid(const PlotArea& a) {
    std::string s;
    for (double d = a.lt0; d <= a.lt1; d += 1) {
        const double x = a.x(std::pow(10, d));
        s += format(
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
            "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">1e%.0f</text>\n",
            x, a.top, x, a.H - a.bottom, x, a.H - a.bottom + 18, d);
    }
    for (double d = a.le0; d <= a.le1; d += 1) {
        const double y = a.y(std::pow(10, d));
        s += format(
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
            "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">1e%.0f</text>\n",
            a.left, y, a.W - a.right, y, a.left - 6, y + 4, d);
    }
    return s;
}

std::string svg_frame(const PlotArea& a) {
    const double mid_y = (a.top + a.H - a.bottom) / 2;
    return format(
        "<rect x=\"%.0f\" y=\"%.0f\" width=\"%.0f\" height=\"%.0f\" fill=\"none\" "
        "stroke=\"black\"/>\n<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">render "
        "time (s)</text>\n<text x=\"18\" y=\"%.0f\" transform=\"rotate(-90 18 %.0f)\" "
        "text-anchor=\"middle\">relative MSE</text>\n",
        a.left, a.top, a.W - a.left - a.right, a.H - a.top - a.bottom, (a.left + a.W - a.right) / 2,
        a.H - 18, mid_y, mid_y);
}

// One curve of a run, solid for relMSE against the reference (estimated = false) or dashed for
// the estimate from the samples, and its legend entry at legend_y (moved down when drawn).
std::string svg_series(const PlotArea& a, const ProgressRun& run, const char* colour,
                       bool estimated, double* legend_y) {
    std::vector<double> xs, ys;
    std::string path;
    for (const rt::PassRecord& r : run.passes) {
        const double e = estimated ? r.estimate.relmse : r.has_reference ? r.error.relmse : 0;
        if (!(e > 0) || !(r.seconds > 0)) continue;
        xs.push_back(r.seconds), ys.push_back(e);
        path += format("%s%.1f,%.1f", path.empty() ? "" : " ", a.x(r.seconds), a.y(e));
    }
    if (xs.size() < 2) return "";
    std::string s = "<polyline points=\"" + path + "\" fill=\"none\" stroke=\"" + colour +
                    "\" stroke-width=\"2\"" + (estimated ? " stroke-dasharray=\"6 4\"" : "") +
                    "/>\n";
    s += format("<text x=\"%.0f\" y=\"%.0f\" fill=\"%s\">%s %s: slope %.2f</text>\n",
                a.W - a.right + 10, *legend_y, colour, escape_xml(run.mode).c_str(),
                estimated ? "estimate" : "relMSE", rt::loglog_slope(xs, ys));
    *legend_y += 18;
    return s;
}

std::string svg_close(const PlotArea& a) {
    return format(
        "<text x=\"%.0f\" y=\"%.0f\" font-size=\"11\">%s; dashed: estimated from the "
        "samples (each pixel's even against its odd samples)</text>\n</svg>\n",
        a.left, a.top - 10, kRelMseFormula);
}

}  // namespace

double pass_error(const rt::PassRecord& r) {
    return r.has_reference ? r.error.relmse : r.estimate.relmse;
}

double time_to_reach(const std::vector<rt::PassRecord>& run, double target) {
    for (size_t i = 0; i < run.size(); ++i) {
        const double e = pass_error(run[i]);
        if (!(e > 0) || e > target) continue;
        if (i == 0) return run[0].seconds;
        // Interpolate on log-log axes between the pass before and this one.
        const double e0 = pass_error(run[i - 1]), t0 = run[i - 1].seconds, t1 = run[i].seconds;
        if (!(e0 > target) || !(t0 > 0)) return t1;
        const double f = std::log(e0 / target) / std::log(e0 / e);
        return std::exp(std::log(t0) + f * (std::log(t1) - std::log(t0)));
    }
    return -1;
}

std::string progress_csv(const std::vector<ProgressRun>& runs) {
    std::string s = "mode,seconds,spp,rays,rmse,relmse,off_share,estimate,estimate_relmse\n";
    for (const ProgressRun& run : runs)
        for (const rt::PassRecord& r : run.passes) {
            if (r.has_reference)
                s += format("%s,%.6f,%.4f,%llu,%.8g,%.8g,%.6f,%.8g,%.8g\n", run.mode.c_str(),
                            r.seconds, r.spp, ull(r.rays), r.error.rmse, r.error.relmse,
                            r.error.off_share, r.estimate.mse, r.estimate.relmse);
            else
                s += format("%s,%.6f,%.4f,%llu,,,,%.8g,%.8g\n", run.mode.c_str(), r.seconds, r.spp,
                            ull(r.rays), r.estimate.mse, r.estimate.relmse);
        }
    return s;
}

std::string progress_svg(const std::vector<ProgressRun>& runs, const std::string& title) {
    const PlotArea a = plot_area(runs);
    std::string s = svg_open(a, title) + svg_grid(a) + svg_frame(a);
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
    double legend_y = a.top + 10;
    for (size_t k = 0; k < runs.size(); ++k)
        for (const bool estimated : {false, true})
            s += svg_series(a, runs[k], colours[k % 4], estimated, &legend_y);
    return s + svg_close(a);
}

std::string light_summary(const rt::SceneDesc& desc) {
    size_t count[rt::kLightKinds] = {};
    for (const rt::LightDesc& l : desc.lights) ++count[static_cast<int>(l.kind)];
    std::string kinds;
    for (int k = 0; k < rt::kLightKinds; ++k) {
        if (count[k] == 0) continue;
        kinds += (kinds.empty() ? "" : ", ") +
                 std::string(rt::light_kind_name(static_cast<rt::LightKind>(k))) + " " +
                 std::to_string(count[k]);
    }
    return std::to_string(desc.lights.size()) + (kinds.empty() ? "" : " (" + kinds + ")");
}

void print_scene_summary(const Options& opt, const rt::SceneDesc& desc,
                         const rt::CompileReport& st) {
    std::printf("scene     %s (%s, %zu file%s)\n", opt.scene.c_str(),
                rt::dialect_name(desc.dialect), st.files, st.files == 1 ? "" : "s");
    // The kinds the scene has (every kind at zero: "none").
    std::string kinds;
    for (int k = 0; k < rt::kShapeKinds; ++k) {
        if (st.prims_by_kind[k] == 0) continue;
        if (!kinds.empty()) kinds += ", ";
        char kind[64];
        std::snprintf(kind, sizeof kind, "%s %zu",
                      rt::shape_kind_name(static_cast<rt::ShapeKind>(k)), st.prims_by_kind[k]);
        kinds += kind;
    }
    std::printf("shapes    %s", kinds.empty() ? "none" : kinds.c_str());
    std::printf("  (after instancing; %zu unique; %zu degenerate skipped)\n", st.unique_prims,
                st.skipped_shapes);
    std::printf("triangles %zu, lights %s, materials %zu, textures %zu, instances %zu\n",
                st.prims_by_kind[static_cast<int>(rt::ShapeKind::Triangle)],
                light_summary(desc).c_str(), st.materials, st.textures, st.instances);
    const bool spheres = std::any_of(desc.lights.begin(), desc.lights.end(),
                                     [](const auto& l) { return l.kind == rt::LightKind::Sphere; });
    const std::string light_samples =
        spheres ? ", " + std::to_string(opt.light_samples) + " light samples" : "";
    std::printf("render    %dx%d, %d spp, depth %d, cutoff %g, shadows %s, %d threads%s\n",
                opt.width, opt.height, opt.spp, opt.max_depth, opt.cutoff,
                opt.shadows ? "on" : "off", rt::resolve_thread_count(opt.threads),
                light_samples.c_str());
    if (!desc.tracks.empty()) {
        const AnimationOptions& a = opt.animation;
        double loop = 0;
        for (const rt::KeyTrack& t : desc.tracks) loop = std::max(loop, t.duration);
        const std::string how = std::string(rt::interpolation_name(a.interpolation)) + ", " +
                                rt::rotation_name(a.rotation);
        if (a.frames > 0)
            std::printf("animation %zu DOF%s, %g s loop; %d frames at %g fps from t = %g (%s)\n",
                        desc.tracks.size(), desc.tracks.size() == 1 ? "" : "s", loop, a.frames,
                        a.fps, a.start, how.c_str());
        else if (a.at)
            std::printf("animation %zu DOF%s, %g s loop; the frame at t = %g (%s)\n",
                        desc.tracks.size(), desc.tracks.size() == 1 ? "" : "s", loop, *a.at,
                        how.c_str());
        else
            std::printf("animation %zu DOF%s, %g s loop; joints hold key 0 (see --at, --frames)\n",
                        desc.tracks.size(), desc.tracks.size() == 1 ? "" : "s", loop);
    }
    std::fflush(stdout);
}

void print_explain(const rt::RenderPlan& plan) {
    std::printf("renderer  %s\n", plan.specialized
                                      ? "specialized to the scene (--no-specialize: generic)"
                                      : "generic (--no-specialize): every feature kept; the lines "
                                        "below say what the specialized renderer would leave out");
    for (const rt::PlanReason& reason : plan.reasons)
        std::printf("%s\n", rt::reason_line(reason).c_str());
    std::fflush(stdout);
}

rt::ProgressFn terminal_progress_bar(bool quiet) {
    if (quiet || !isatty(STDERR_FILENO)) return {};
    auto last_draw = std::make_shared<rt::Clock::time_point>(rt::Clock::now());
    return [last_draw](int done, int total) {
        if (done < total && rt::seconds_since(*last_draw) < 0.1) return;
        *last_draw = rt::Clock::now();
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

void print_render_summary(const Timings& t, const rt::RayCounters& rays) {
    const double total = static_cast<double>(rays.total());
    std::printf("time      parse %.3f s, compile %.3f s, render %.3f s\n", t.parse_s, t.compile_s,
                t.render_s);
    std::printf(
        "rays      %sray/s (%s rays: camera %llu, shadow %llu, reflected %llu, "
        "refracted %llu)\n",
        si(t.render_s > 0 ? total / t.render_s : 0).c_str(), si(total).c_str(), ull(rays.camera),
        ull(rays.shadow), ull(rays.reflected), ull(rays.refracted));
}

void print_stats(const Timings& t, double build_s, const rt::RayCounters& rays) {
    std::printf("\nphase            seconds\n");
    std::printf("parse         %10.3f\n", t.parse_s);
    std::printf("compile       %10.3f   (of which BVH build %.3f)\n", t.compile_s, build_s);
    std::printf("render        %10.3f\n", t.render_s);
    std::printf("total         %10.3f\n", t.parse_s + t.compile_s + t.render_s);
    std::printf("\ninstruction set  %s\n", rt::isa_summary().c_str());
    std::printf("\nrays               count     per second of render time\n");
    const std::pair<const char*, uint64_t> kinds[] = {{"camera", rays.camera},
                                                      {"shadow", rays.shadow},
                                                      {"reflected", rays.reflected},
                                                      {"refracted", rays.refracted},
                                                      {"all", rays.total()}};
    for (const auto& [name, n] : kinds)
        std::printf("%-10s %12llu     %sray/s\n", name, ull(n),
                    si(t.render_s > 0 ? static_cast<double>(n) / t.render_s : 0).c_str());
}

void print_pass_header(const std::string& mode, bool has_reference) {
    std::printf("\n%s sampling%s\n%10s %10s %12s %12s %12s %10s %12s\n", mode.c_str(),
                has_reference ? "" : " (no reference: estimated error only)", "seconds", "spp",
                "rays", "rmse", "relmse", "off>1/255", "estimate");
}

void print_pass(const rt::PassRecord& r) {
    if (r.has_reference)
        std::printf("%10.3f %10.2f %12llu %12.4g %12.4g %9.2f%% %12.4g\n", r.seconds, r.spp,
                    ull(r.rays), r.error.rmse, r.error.relmse, 100 * r.error.off_share,
                    r.estimate.relmse);
    else
        std::printf("%10.3f %10.2f %12llu %12s %12s %10s %12.4g\n", r.seconds, r.spp, ull(r.rays),
                    "-", "-", "-", r.estimate.relmse);
    std::fflush(stdout);
}

void print_progress_summary(const std::vector<ProgressRun>& runs, double target) {
    std::printf(
        "\n%s\nestimate = the same from the samples alone (the difference of each pixel's "
        "even and odd samples)\n",
        kRelMseFormula);
    for (const ProgressRun& run : runs) {
        std::vector<double> t, e;
        for (const rt::PassRecord& r : run.passes) {
            t.push_back(r.seconds);
            e.push_back(pass_error(r));
        }
        std::printf("%s: relMSE falls as time^%.2f (least squares on log-log axes)\n",
                    run.mode.c_str(), rt::loglog_slope(t, e));
        if (target > 0 && !run.passes.empty()) {
            const rt::PassRecord& last = run.passes.back();
            if (last.spp >= rt::ProgressiveSettings::kTargetMinSpp &&
                last.estimate.relmse <= target)
                std::printf("%s: reached the target error %.4g at %.4g spp after %.3f s\n",
                            run.mode.c_str(), target, last.spp, last.seconds);
            else
                std::printf("%s: the target error %.4g was not reached (estimate %.4g)\n",
                            run.mode.c_str(), target, last.estimate.relmse);
        }
    }
    if (runs.size() == 2 && !runs[0].passes.empty()) {
        const double goal = pass_error(runs[0].passes.back());
        const double tu = time_to_reach(runs[0].passes, goal);
        const double ta = time_to_reach(runs[1].passes, goal);
        std::printf("time to reach relMSE %.4g: uniform %.3f s, adaptive %s", goal, tu,
                    ta > 0 ? "" : "never within the limit\n");
        if (ta > 0) std::printf("%.3f s (%.2fx)\n", ta, tu / ta);
    }
}

}  // namespace raytrace
