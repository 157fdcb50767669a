// Progressive rendering with its error measured against run time: passes of render_samples() on
// one RenderState, the error of each pass against a reference image (or estimated from the
// samples themselves), and adaptive sampling. Presenting the passes (tables, CSV, plots) is the
// programs' job.
#pragma once

#include <atomic>
#include <functional>
#include <vector>

#include "rt/image/image.h"
#include "rt/render/render.h"

namespace rt {

/// relMSE's denominator offset: (x - ref)^2 / (ref^2 + kRelMseEpsilon), so black pixels do not
/// dominate.
inline constexpr double kRelMseEpsilon = 0.01;

struct ImageError {
    double rmse = 0;    // sqrt of the mean over pixels and channels of (x - ref)^2
    double relmse = 0;  // mean over pixels and channels of (x - ref)^2 / (ref^2 + kRelMseEpsilon)
    double off_share = 0;  // share of pixels with a channel off by more than 1/255 (clamped)
};

/// Error of `image` against `ref` (same size; throws std::invalid_argument otherwise).
ImageError compare_images(const Image& image, const Image& ref);

/// Error estimated from the samples alone, as two-buffer estimates do: each pixel's even and odd
/// samples are independent estimates of it (their own R2 shifts and random numbers), so the
/// square of their difference, times n_even n_odd / n^2, is an unbiased estimate of the squared
/// error of the pixel's mean, under any sampling pattern of the halves (stratified, QMC).
/// Averaged over pixels and channels (MSE), and divided by (mean^2 + 0.01) (relMSE). Pixels with
/// fewer than two samples are left out. A state merged from part files, which keep no odd sums,
/// falls back to the variance of the mean, s^2 / n, which the samples' stratification makes an
/// overestimate.
struct ErrorEstimate {
    double mse = 0;
    double relmse = 0;
};
ErrorEstimate estimate_error(const RenderState& state);

/// Least-squares slope of log(y) against log(x) over the points with x, y > 0 (0 for fewer than
/// two): how fast the error falls against time or samples.
double loglog_slope(const std::vector<double>& x, const std::vector<double>& y);

/// When the error will reach `target`: a line through (seconds, relMSE) points on log-log axes,
/// extrapolated. The line is fitted to the points since a quarter of the last time (a span wide
/// enough that the estimate's noise hardly tilts it) by Theil-Sen (medians: a wild pass does not
/// tilt it at all), and its slope bounded to [-1, -1/2]: Monte Carlo error falls as 1 / samples
/// (-1), faster only while stratification or adaptive sampling still pays off early, which does
/// not last (a steeper fit made the forecast optimistic); slower than -1/2 is the estimate's own
/// noise, whose extrapolation is unbounded. Returns the predicted seconds (the last point's when
/// it is already reached), or a negative number when it cannot be told: fewer than two usable
/// points, or an error that hardly falls (a slope above -0.1).
double predict_time_to_error(const std::vector<std::pair<double, double>>& points, double target);

/// The time to a target error as an interactive trace shows it, from one (seconds, relMSE) point
/// per pass: predict_time_to_error() over the points given, and the median of the last five
/// predictions, so one noisy pass does not move it. Negative ("estimating") until three passes
/// gave a prediction.
class TargetForecast {
public:
    /// Adds a pass; returns the forecast (seconds from the start at which the error reaches
    /// `target`), or a negative number while it cannot be told.
    double add(double seconds, double relmse, double target);
    /// Forgets every pass (a restart).
    void clear() { *this = {}; }

private:
    std::vector<std::pair<double, double>> m_points;
    std::vector<double> m_recent;  // the last predictions, oldest first
};

/// Adaptive sampling: shares `budget` samples among the pixels so that each pixel's total
/// moves toward a share proportional to its estimated relative standard deviation (the optimal
/// allocation for independent samples), taken as the maximum over its 3x3 neighbourhood so
/// features a pixel's few samples missed are not ignored; one pixel in `explore`, on a pattern
/// that moves every pass, gets at least one sample. Fills state.active (samples per pixel for a
/// render_samples() call with spp = 1) and returns the number of samples allocated.
uint64_t choose_adaptive_pixels(RenderState& state, double budget, int explore = 8);

struct ProgressiveSettings {
    double time_limit_s = 0;  // stop after this much render time (0: no limit)
    int spp_limit = 0;        // stop at this many samples per pixel on average (0: no limit)
    /// Stop once the estimated relMSE (estimate_error) is at most this (0: no target), as
    /// Cycles' noise threshold does; not before kTargetMinSpp samples per pixel, where the
    /// estimate has settled.
    double target_relmse = 0;
    static constexpr int kTargetMinSpp = 8;
    bool adaptive = false;
};

struct PassRecord {
    double seconds = 0;  // render time so far (error computation excluded)
    double spp = 0;      // mean samples per pixel
    uint64_t rays = 0;
    bool has_reference = false;
    ImageError error;
    ErrorEstimate estimate;
};

/// What adds a pass's samples to the state: `spp` more samples per pixel with `settings` (the
/// pass settings: every sample jittered), as render_samples(state, scene, plan, settings, spp)
/// adds them; false when stopped. The MPI mode's rank 0 hands the pass out to its workers.
using PassRenderer =
    std::function<bool(RenderState& state, const RenderSettings& settings, int spp)>;

/// Runs passes (1, 1, 2, 4, 8, ... samples per pixel, every sample jittered; adaptive: after the
/// first four samples, the same number of samples per pass shared by choose_adaptive_pixels())
/// until a limit, recording each pass. `render_pass`, when given, renders the passes instead of
/// render_samples() (it must honour state.active for adaptive runs).
std::vector<PassRecord> run_progressive(RenderState& state, const RenderScene& scene,
                                        const RenderPlan& plan, const RenderSettings& settings,
                                        const ProgressiveSettings& progressive,
                                        const Image* reference,
                                        const std::function<void(const PassRecord&)>& on_pass = {},
                                        const std::atomic<bool>* stop = nullptr,
                                        const PassRenderer& render_pass = {});

}  // namespace rt
