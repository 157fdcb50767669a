#include "rt/render/progressive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rt/util/stopwatch.h"

namespace rt {

ImageError compare_images(const Image& image, const Image& ref) {
    if (image.width != ref.width || image.height != ref.height)
        throw std::invalid_argument(
            "reference is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
            ", image is " + std::to_string(image.width) + "x" + std::to_string(image.height));
    ImageError e;
    double sq = 0, rel = 0;
    size_t off = 0;
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    for (size_t p = 0; p < pixels; ++p) {
        bool pixel_off = false;
        for (size_t c = 0; c < 3; ++c) {
            const double x = image.rgb[p * 3 + c], r = ref.rgb[p * 3 + c];
            const double d = x - r;
            sq += d * d;
            rel += d * d / (r * r + kRelMseEpsilon);
            const double dc = std::clamp(x, 0.0, 1.0) - std::clamp(r, 0.0, 1.0);
            pixel_off = pixel_off || std::abs(dc) > 1.0 / 255.0;
        }
        off += pixel_off ? 1 : 0;
    }
    const double n = static_cast<double>(pixels * 3);
    e.rmse = std::sqrt(sq / n);
    e.relmse = rel / n;
    e.off_share = static_cast<double>(off) / static_cast<double>(pixels);
    return e;
}

namespace {

// Variance of a pixel channel's mean, s^2 / n with the unbiased sample variance.
double variance_of_mean(double sum, double sum_sq, double n) {
    const double mean = sum / n;
    const double var = std::max(0.0, (sum_sq - n * mean * mean) / (n - 1));
    return var / n;
}

// Per-pixel relative error estimate, summed over channels; negative when unknown (n < 2).
double pixel_rel_error(const RenderState& s, size_t p) {
    const double n = s.samples[p];
    if (n < 2) return -1;
    double e = 0;
    for (size_t c = 0; c < 3; ++c) {
        const double mean = s.sum[p * 3 + c] / n;
        e += variance_of_mean(s.sum[p * 3 + c], s.sum_sq[p * 3 + c], n) /
             (mean * mean + kRelMseEpsilon);
    }
    return e;
}

}  // namespace

ErrorEstimate estimate_error(const RenderState& state) {
    ErrorEstimate e;
    double mse = 0, rel = 0;
    size_t count = 0;
    for (size_t p = 0; p < state.samples.size(); ++p) {
        const double n = state.samples[p];
        if (n < 2) continue;
        // Two halves: the even samples (indices 0, 2, ...: ceil(n / 2) of them) and the odd.
        const double n_odd = std::floor(n / 2), n_even = n - n_odd;
        for (size_t c = 0; c < 3; ++c) {
            const double sum = state.sum[p * 3 + c], mean = sum / n;
            double v = 0;
            if (state.odd_sums) {
                // The halves are independent estimates (each its own R2 shift, its own random
                // numbers) with variances s2 / n_half: E[(m_even - m_odd)^2] is
                // s2 n / (n_even n_odd), and the variance of the whole mean is s2 / n.
                const double odd = state.sum_odd[p * 3 + c];
                const double d = (sum - odd) / n_even - odd / n_odd;
                v = d * d * n_even * n_odd / (n * n);
            } else {
                v = variance_of_mean(sum, state.sum_sq[p * 3 + c], n);
            }
            mse += v;
            rel += v / (mean * mean + kRelMseEpsilon);
        }
        ++count;
    }
    if (count > 0) {
        e.mse = mse / static_cast<double>(count * 3);
        e.relmse = rel / static_cast<double>(count * 3);
    }
    return e;
}

double loglog_slope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (size_t i = 0; i < x.size() && i < y.size(); ++i) {
        if (!(x[i] > 0) || !(y[i] > 0)) continue;
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
        ++n;
    }
    if (n < 2) return 0;
    const double den = n * sxx - sx * sx;
    return den != 0 ? (n * sxy - sx * sy) / den : 0;
}

double predict_time_to_error(const std::vector<std::pair<double, double>>& points, double target) {
    if (points.empty() || !(target > 0)) return -1;
    const auto& [t_last, e_last] = points.back();
    if (!(t_last > 0) || !(e_last > 0)) return -1;
    if (e_last <= target) return t_last;
    // The points since a quarter of the last time: a span of 4x in time, wide enough that the
    // estimate's noise hardly tilts the line, late enough that the early slope has settled; at
    // most 48 of them, evenly spread.
    size_t first = 0;
    for (size_t i = 0; i < points.size(); ++i)
        if (points[i].first <= 0.25 * t_last) first = i;
    std::vector<double> lt, le;
    const size_t span = points.size() - first, step = (span + 47) / 48;
    for (size_t i = points.size() - 1;; i -= step) {
        if (points[i].first > 0 && points[i].second > 0)
            lt.push_back(std::log(points[i].first)), le.push_back(std::log(points[i].second));
        if (i < first + step) break;
    }
    // The Theil-Sen line on log-log axes (the median of the pairs' slopes, then of the
    // intercepts): one wild pass, a firefly's, tilts a least-squares line for as long as it is
    // in the window, a median not.
    std::vector<double> slopes, offsets;
    for (size_t i = 0; i < lt.size(); ++i)
        for (size_t j = i + 1; j < lt.size(); ++j)
            if (lt[i] != lt[j]) slopes.push_back((le[i] - le[j]) / (lt[i] - lt[j]));
    if (slopes.empty()) return -1;  // fewer than two points
    auto median = [](std::vector<double>& v) {
        const size_t h = v.size() / 2;
        std::nth_element(v.begin(), v.begin() + h, v.end());
        if (v.size() % 2) return v[h];
        return 0.5 * (v[h] + *std::max_element(v.begin(), v.begin() + h));
    };
    const double fitted = median(slopes);
    if (!(fitted < -0.1)) return -1;  // hardly falling
    const double slope = std::clamp(fitted, -1.0, -0.5);
    for (size_t i = 0; i < lt.size(); ++i) offsets.push_back(le[i] - slope * lt[i]);
    // The line read at the last time: one noisy last pass does not move the forecast as it
    // moves the last point.
    const double e_fit = std::exp(median(offsets) + slope * std::log(t_last));
    return t_last * std::max(1.0, std::pow(target / e_fit, 1.0 / slope));
}

double TargetForecast::add(double seconds, double relmse, double target) {
    m_points.emplace_back(seconds, relmse);
    // Six passes at least: the fit then spans three or more.
    const double t = m_points.size() >= 6 ? predict_time_to_error(m_points, target) : -1;
    if (t >= 0) {
        if (m_recent.size() == 5) m_recent.erase(m_recent.begin());
        m_recent.push_back(t);
    }
    if (m_recent.size() < 3) return -1;
    std::vector<double> sorted = m_recent;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    // A pass whose fit could not tell keeps the forecast, until it lies in the past: "in ~0 s"
    // while the error is still above the target would not be true.
    const double median = sorted[sorted.size() / 2];
    return median > seconds ? median : -1;
}

uint64_t choose_adaptive_pixels(RenderState& state, double budget, int explore) {
    const size_t n = state.samples.size();
    const int w = state.width, h = state.height;
    // Relative standard deviation of one sample of each pixel; negative when unknown.
    std::vector<double> raw(n), sd(n);
    for (size_t p = 0; p < n; ++p) {
        const double e = pixel_rel_error(state, p);  // variance of the mean
        raw[p] = e < 0 ? -1 : std::sqrt(e * state.samples[p]);
    }
    double sum_sd = 0;
    size_t known = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t p =
                static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
            double v = raw[p];
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (v < 0 || xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    v = std::max(v, raw[static_cast<size_t>(yy) * static_cast<size_t>(w) +
                                        static_cast<size_t>(xx)]);
                }
            sd[p] = v;
            if (v >= 0) sum_sd += v, ++known;
        }
    const double mean_sd = known ? sum_sd / static_cast<double>(known) : 1.0;
    for (double& v : sd)
        if (v < 0) v = mean_sd, sum_sd += v;  // unknown pixels get an average share
    double total = budget;
    for (uint32_t c : state.samples) total += c;
    // Each pixel's deficit against its target total, scaled to the budget.
    std::vector<double> deficit(n);
    double sum_deficit = 0;
    for (size_t p = 0; p < n; ++p) {
        const double target = sum_sd > 0 ? total * sd[p] / sum_sd : total / static_cast<double>(n);
        deficit[p] = std::max(0.0, target - state.samples[p]);
        sum_deficit += deficit[p];
    }
    const double scale = sum_deficit > 0 ? budget / sum_deficit : 0;
    state.active.assign(n, 0);
    uint64_t allocated = 0;
    const size_t shift = static_cast<size_t>(state.passes) * 7919;  // moves the pattern
    for (size_t p = 0; p < n; ++p) {
        double k = std::min(255.0, std::floor(deficit[p] * scale + 0.5));
        if (k < 1 && explore > 0 && (p + shift) % static_cast<size_t>(explore) == 0) k = 1;
        state.active[p] = static_cast<uint8_t>(k);
        allocated += static_cast<uint64_t>(k);
    }
    return allocated;
}

std::vector<PassRecord> run_progressive(RenderState& state, const RenderScene& scene,
                                        const RenderPlan& plan, const RenderSettings& settings,
                                        const ProgressiveSettings& progressive,
                                        const Image* reference,
                                        const std::function<void(const PassRecord&)>& on_pass,
                                        const std::atomic<bool>* stop,
                                        const PassRenderer& render_pass) {
    state.reset(settings.width, settings.height);
    RenderSettings pass_settings = settings;
    pass_settings.centre_first_sample = false;  // every sample jittered (the plan is the same)
    std::vector<PassRecord> records;
    double render_seconds = 0;
    uint64_t samples_total = 0;
    const double pixels = static_cast<double>(settings.width) * settings.height;
    for (int pass = 0;; ++pass) {
        // Uniform schedule 1, 1, 2, 4, 8, ... samples per pixel (at most 64 a pass).
        int spp = pass == 0 ? 1 : pass > 7 ? 64 : 1 << (pass - 1);
        // The last pass shrinks to end at the sample limit ...
        if (progressive.spp_limit > 0)
            spp =
                std::clamp(static_cast<int>(std::ceil(progressive.spp_limit -
                                                      static_cast<double>(samples_total) / pixels)),
                           1, spp);
        state.active.clear();
        // ... or at the time limit, at the rate measured so far, instead of doubling past it.
        if (progressive.time_limit_s > 0 && samples_total > 0) {
            const double per_spp = render_seconds / (static_cast<double>(samples_total) / pixels);
            const double remaining = progressive.time_limit_s - render_seconds;
            spp = static_cast<int>(std::clamp(remaining / per_spp, 1.0, static_cast<double>(spp)));
        }
        // ... or at the target error: relMSE falls about as 1 / spp, so the pass that should
        // reach it is sized from the last estimate (a little over, to reach it in one pass).
        if (progressive.target_relmse > 0 && !records.empty()) {
            const double have = static_cast<double>(samples_total) / pixels;
            const double est = records.back().estimate.relmse;
            if (have >= ProgressiveSettings::kTargetMinSpp && est > progressive.target_relmse) {
                const double need = 1.1 * have * est / progressive.target_relmse - have;
                spp = static_cast<int>(std::clamp(std::ceil(need), 1.0, static_cast<double>(spp)));
            }
        }
        uint64_t pass_samples = static_cast<uint64_t>(pixels) * static_cast<uint64_t>(spp);
        if (progressive.adaptive && state.passes >= 3) {
            // The samples of the uniform pass, shared by estimated error.
            pass_samples = choose_adaptive_pixels(state, spp * pixels);
            spp = 1;
        }
        const auto t0 = Clock::now();
        const bool rendered =
            render_pass ? render_pass(state, pass_settings, spp)
                        : render_samples(state, scene, plan, pass_settings, spp, {}, stop);
        if (!rendered) break;
        render_seconds += seconds_since(t0);
        samples_total += pass_samples;

        PassRecord r;
        r.seconds = render_seconds;
        r.spp = static_cast<double>(samples_total) / pixels;
        r.rays = state.rays.total();
        r.estimate = estimate_error(state);
        if (reference) {
            r.has_reference = true;
            r.error = compare_images(state.image(), *reference);
        }
        records.push_back(r);
        if (on_pass) on_pass(r);
        if (progressive.time_limit_s > 0 && render_seconds >= progressive.time_limit_s) break;
        if (progressive.spp_limit > 0 && r.spp >= progressive.spp_limit) break;
        if (progressive.target_relmse > 0 && r.spp >= ProgressiveSettings::kTargetMinSpp &&
            r.estimate.relmse <= progressive.target_relmse)
            break;
        if (progressive.time_limit_s <= 0 && progressive.spp_limit <= 0 &&
            progressive.target_relmse <= 0)
            break;
    }
    state.active.clear();
    return records;
}

}  // namespace rt
