#include "rt/render/render.h"

#include <algorithm>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "parallel.h"
#include "rt/render/sampler.h"

namespace rt {

void RenderState::reset(int w, int h) {
    width = w;
    height = h;
    sum.assign(static_cast<size_t>(w) * h * 3, 0.0);
    sum_sq.assign(static_cast<size_t>(w) * h * 3, 0.0);
    samples.assign(static_cast<size_t>(w) * h, 0);
    active.clear();
    passes = 0;
    rays = {};
}

Image RenderState::image() const {
    Image img(width, height);
    for (size_t i = 0; i < samples.size(); ++i) {
        const double n = samples[i] > 0 ? samples[i] : 1;
        for (int c = 0; c < 3; ++c) img.rgb[i * 3 + c] = sum[i * 3 + c] / n;
    }
    return img;
}

int resolve_thread_count(int threads) {
    if (threads > 0) return std::min(threads, 256);
    return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 256u));
}

namespace {

// A plan's camera is made for one image size: rendering another would map its pixels wrongly.
void check_plan_size(const RenderPlan& plan, const RenderSettings& settings) {
    if (plan.camera.width != settings.width || plan.camera.height != settings.height)
        throw std::invalid_argument("render plan made for " + std::to_string(plan.camera.width) +
                                    "x" + std::to_string(plan.camera.height) + ", rendered at " +
                                    std::to_string(settings.width) + "x" +
                                    std::to_string(settings.height));
}

constexpr int kTile = 16;

// A rectangle of pixels, [x0, x1) x [y0, y1).
struct PixelRect {
    int x0, y0, x1, y1;
};

// Tile `tile` of a grid of size x size tiles over the image, row-major.
PixelRect tile_rect(int tile, int size, const RenderSettings& settings) {
    const int tiles_x = (settings.width + size - 1) / size;
    const int x0 = (tile % tiles_x) * size, y0 = (tile / tiles_x) * size;
    return {x0, y0, std::min(x0 + size, settings.width), std::min(y0 + size, settings.height)};
}

int tile_count(int size, const RenderSettings& settings) {
    return ((settings.width + size - 1) / size) * ((settings.height + size - 1) / size);
}

// What every pixel of one render_samples() call shares.
struct Pass {
    const RenderScene& scene;
    const RenderPlan& plan;
    const RenderSettings& settings;
    bool stochastic;
};

// Where the s-th of a pixel's n samples of this call falls in the pixel, in [0,1)^2. The pixel
// has `base` samples from earlier calls; `stratum` is ceil(sqrt(n)), `shift` the pixel's R2 shift.
Vec2 sample_position(const Pass& pass, int s, int n, uint32_t base, int stratum, Vec2 shift,
                     Rng& rng) {
    const uint32_t index = base + static_cast<uint32_t>(s);
    if (!pass.settings.centre_first_sample) {
        // Progressive passes: the R2 sequence (Roberts 2018) under a random shift per pixel, so
        // any run of sample indices, across passes too, is spread over the pixel without bias.
        constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
        return {std::fmod(shift.x + index * a1, 1.0), std::fmod(shift.y + index * a2, 1.0)};
    }
    if (n > 1 || base > 0 || pass.stochastic) {
        // Spec §6.2: one uniform sample in each of the first n strata of a ceil(sqrt(n))^2
        // grid, row-major.
        const double sx = (s % stratum + rng.uniform()) / stratum;
        const double sy = (s / stratum + rng.uniform()) / stratum;
        return {sx, sy};
    }
    return {0.5, 0.5};  // one sample: the pixel centre
}

// The camera ray through pixel (x, y) at `sample`; with an aperture, from a point of the lens.
Ray camera_ray(const Pass& pass, int x, int y, Vec2 sample, Rng& rng) {
    const Camera& camera = pass.plan.camera;
    Ray ray = camera.generate(x, y, sample.x, sample.y);
    if (pass.settings.aperture > 0) {
        // Thin lens: from a point of the aperture toward the focused point.
        const Vec3 focused =
            ray.o + ray.d * (pass.plan.focus_distance / glm::dot(ray.d, camera.forward));
        const Vec2 lens = pass.settings.aperture * rng.disc();
        ray.o += lens.x * camera.right + lens.y * camera.up;
        ray.d = glm::normalize(focused - ray.o);
    }
    return ray;
}

// The sum and the sum of squares of n new samples of pixel (x, y), which has `base` already.
struct PixelSums {
    Vec3 sum{0.0}, sum_sq{0.0};
};

PixelSums render_pixel(const Pass& pass, int x, int y, int n, uint32_t base, RayCounters& rays) {
    const RenderSettings& settings = pass.settings;
    const size_t pixel = static_cast<size_t>(y) * settings.width + x;
    const int stratum = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
    Vec2 shift(0.0);
    if (!settings.centre_first_sample) {
        Rng pixel_rng(settings.seed, pixel, uint64_t{1} << 40);
        shift = Vec2(pixel_rng.uniform(), pixel_rng.uniform());
    }
    // Only a single pass's one centre sample is deterministic (spec §13.9); every other sample
    // draws the random numbers of the features that take them, sphere lights among them.
    const bool random = pass.stochastic || n > 1 || base > 0 || !settings.centre_first_sample;
    PixelSums sums;
    for (int s = 0; s < n; ++s) {
        // Every sample's random numbers come from (seed, pixel, index): any thread, same image.
        Rng rng(settings.seed, pixel, base + static_cast<uint32_t>(s));
        const Vec2 sample = sample_position(pass, s, n, base, stratum, shift, rng);
        const Ray ray = camera_ray(pass, x, y, sample, rng);
        ++rays.camera;
        const Vec3 c = trace_ray(pass.scene, pass.plan, settings, ray, settings.max_depth,
                                 Vec3(1.0), rays, random ? &rng : nullptr);
        sums.sum += c;
        sums.sum_sq += c * c;
    }
    return sums;
}

// Where one render_samples() call writes its sums: the state's own sums (the first pass of a
// fresh state, whose sums are all zero) or the scratch buffer, committed when the pass completes.
struct PassOutput {
    double* sum;
    double* sum_sq;
    bool direct;
};

// One tile of a pass; false when a stop request was seen (within one pixel row: milliseconds even
// at many samples per pixel; the pass is then discarded).
bool render_tile(const Pass& pass, const RenderState& state, const PixelRect& r, int spp,
                 const PassOutput& out, const std::atomic<bool>* stop, RayCounters& rays) {
    const bool all_active = state.active.size() != state.samples.size();
    for (int y = r.y0; y < r.y1; ++y) {
        if (stop && stop->load(std::memory_order_relaxed)) return false;
        for (int x = r.x0; x < r.x1; ++x) {
            const size_t pixel = static_cast<size_t>(y) * pass.settings.width + x;
            const int n = all_active ? spp : spp * state.active[pixel];
            PixelSums sums;  // zero: in place, the sums stay as they are
            if (n == 0 && out.direct) continue;
            if (n > 0) sums = render_pixel(pass, x, y, n, state.samples[pixel], rays);
            for (size_t c = 0; c < 3; ++c) {
                out.sum[pixel * 3 + c] = sums.sum[static_cast<int>(c)];
                out.sum_sq[pixel * 3 + c] = sums.sum_sq[static_cast<int>(c)];
            }
        }
    }
    return true;
}

// Adds a completed pass's sums and sample counts to the state.
void commit_pass(RenderState& state, const PassOutput& out, int spp) {
    const bool all_active = state.active.size() != state.samples.size();
    if (!out.direct) {
        for (size_t i = 0; i < state.sum.size(); ++i) {
            state.sum[i] += out.sum[i];
            state.sum_sq[i] += out.sum_sq[i];
        }
    }
    for (size_t i = 0; i < state.samples.size(); ++i)
        state.samples[i] += static_cast<uint32_t>(all_active ? spp : spp * state.active[i]);
    ++state.passes;
}

}  // namespace

Image render_coarse(const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, int block, const std::atomic<bool>* stop) {
    check_plan_size(plan, settings);
    block = std::max(1, block);
    Image img(settings.width, settings.height);
    RayCounters rays;
    parallel_tiles(resolve_thread_count(settings.threads), tile_count(block, settings), stop, rays,
                   [&](int tile, RayCounters& counters) {
                       const PixelRect r = tile_rect(tile, block, settings);
                       // The block's centre, in pixel units; no Rng: deterministic.
                       const double cx = 0.5 * (r.x0 + r.x1), cy = 0.5 * (r.y0 + r.y1);
                       const int ix = static_cast<int>(cx), iy = static_cast<int>(cy);
                       const Ray ray = plan.camera.generate(ix, iy, cx - ix, cy - iy);
                       const Vec3 c = trace_ray(scene, plan, settings, ray, settings.max_depth,
                                                Vec3(1.0), counters);
                       for (int y = r.y0; y < r.y1; ++y)
                           for (int x = r.x0; x < r.x1; ++x) img.set(x, y, c);
                       return true;
                   });
    return img;
}

bool render_samples(RenderState& state, const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, int spp, const ProgressFn& progress,
                    const std::atomic<bool>* stop) {
    check_plan_size(plan, settings);
    if (state.width != settings.width || state.height != settings.height)
        state.reset(settings.width, settings.height);
    if (spp <= 0) return true;
    const Pass pass{scene, plan, settings, settings.stochastic()};
    // New sums go to a scratch buffer and are committed only when the pass completes. The first
    // pass of a fresh state (all sums zero) writes the sums directly and, when stopped, puts the
    // zeros back: no scratch to fill, commit or fault in.
    const bool direct = state.passes == 0;
    const size_t n = state.sum.size();
    if (!direct) state.scratch.resize(2 * n);
    const PassOutput out{direct ? state.sum.data() : state.scratch.data(),
                         direct ? state.sum_sq.data() : state.scratch.data() + n, direct};

    const int tiles_x = (settings.width + kTile - 1) / kTile;
    std::atomic<int> rows_done{0};
    std::mutex progress_mutex;
    RayCounters rays;
    const bool done = parallel_tiles(
        resolve_thread_count(settings.threads), tile_count(kTile, settings), stop, rays,
        [&](int tile, RayCounters& counters) {
            const PixelRect r = tile_rect(tile, kTile, settings);
            const bool finished = render_tile(pass, state, r, spp, out, stop, counters);
            // Progress by rows: the last tile of a tile row counts its rows.
            if (r.x1 == settings.width) rows_done += r.y1 - r.y0;
            if (progress && tile % tiles_x == 0) {
                std::lock_guard lock(progress_mutex);
                progress(rows_done.load(), settings.height);
            }
            return finished;
        });
    if (!done) {
        if (direct) {
            std::fill(state.sum.begin(), state.sum.end(), 0.0);
            std::fill(state.sum_sq.begin(), state.sum_sq.end(), 0.0);
        }
        return false;
    }
    commit_pass(state, out, spp);
    state.rays += rays;
    if (progress) progress(settings.height, settings.height);
    return true;
}

}  // namespace rt
