#include "rt/render/render.h"

#include <algorithm>
#include <mutex>
#include <thread>

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

Image render_coarse(const RenderScene& scene, const RenderSettings& settings, int block,
                    const std::atomic<bool>* stop) {
    block = std::max(1, block);
    Image img(settings.width, settings.height);
    const Camera camera = make_camera(scene, settings.width, settings.height);
    std::vector<Light> lights;
    const ShadingSettings shading = settings.shading(scene, &lights);  // no Rng: deterministic
    const int bx = (settings.width + block - 1) / block, by = (settings.height + block - 1) / block;
    std::atomic<int> next{0};
    auto worker = [&]() {
        RayCounters counters;
        for (int b = next.fetch_add(1); b < bx * by; b = next.fetch_add(1)) {
            if (stop && stop->load(std::memory_order_relaxed)) return;
            const int x0 = (b % bx) * block, y0 = (b / bx) * block;
            const int x1 = std::min(x0 + block, settings.width),
                      y1 = std::min(y0 + block, settings.height);
            // The block's centre, in pixel units.
            const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
            const int ix = static_cast<int>(cx), iy = static_cast<int>(cy);
            const Vec3 c = trace_ray(scene, camera.generate(ix, iy, cx - ix, cy - iy),
                                     settings.max_depth, Vec3(1.0), shading, counters);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) img.set(x, y, c);
        }
    };
    std::vector<std::thread> pool;
    for (int i = 1; i < resolve_thread_count(settings.threads); ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    return img;
}

ShadingSettings RenderSettings::shading(const RenderScene& scene,
                                        std::vector<Light>* lights) const {
    ShadingSettings s = shading();
    if (!specialize) {
        s.geometry = &geometry_queries(kGeomGeneric);
        return s;
    }
    const SceneFeatures f = scene_features(scene, *this);
    s.variant = f.shade_variant();
    s.geometry = &geometry_queries(f.geom_variant);
    // Dark lights are skipped, except where random samples are drawn per light (soft shadows):
    // skipping one there would shift every later sample, and the images must stay the same.
    if (!(s.variant & kShadeStochastic)) {
        *lights = lighting_lights(scene);
        s.lights = lights;
    }
    return s;
}

int resolve_thread_count(int threads) {
    if (threads > 0) return std::min(threads, 256);
    return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 256u));
}

namespace {

constexpr int kTile = 16;

}  // namespace

bool render_samples(RenderState& state, const RenderScene& scene, const RenderSettings& settings,
                    int spp, const ProgressFn& progress, const std::atomic<bool>* stop) {
    if (state.width != settings.width || state.height != settings.height)
        state.reset(settings.width, settings.height);
    if (spp <= 0) return true;
    const Camera camera = make_camera(scene, settings.width, settings.height);
    std::vector<Light> lights;
    const ShadingSettings shading = settings.shading(scene, &lights);
    const bool stochastic = settings.stochastic();
    const double focus = settings.focus_distance > 0
                             ? settings.focus_distance
                             : glm::length(scene.world_bounds.centre() - camera.position);

    const int tiles_x = (settings.width + kTile - 1) / kTile;
    const int tiles_y = (settings.height + kTile - 1) / kTile;
    const int tiles = tiles_x * tiles_y;
    std::atomic<int> next{0};
    std::atomic<int> rows_done{0};
    std::atomic<bool> stopped{false};
    std::mutex mutex;
    RayCounters total;
    // New sums go to a scratch buffer and are committed only when the pass completes. The first
    // pass of a fresh state (all sums zero) writes the sums directly and, when stopped, puts the
    // zeros back: no scratch to fill, commit or fault in.
    const bool direct = state.passes == 0;
    const size_t n = state.sum.size();
    if (!direct) state.scratch.resize(2 * n);
    double* const out_sum = direct ? state.sum.data() : state.scratch.data();
    double* const out_sq = direct ? state.sum_sq.data() : state.scratch.data() + n;
    const bool all_active = state.active.size() != state.samples.size();

    auto worker = [&]() {
        RayCounters counters;
        for (;;) {
            if (stop && stop->load(std::memory_order_relaxed)) {
                stopped = true;
                break;
            }
            const int tile = next.fetch_add(1);
            if (tile >= tiles) break;
            const int tx = (tile % tiles_x) * kTile, ty = (tile / tiles_x) * kTile;
            const int x1 = std::min(tx + kTile, settings.width);
            const int y1 = std::min(ty + kTile, settings.height);
            for (int y = ty; y < y1 && !stopped.load(std::memory_order_relaxed); ++y) {
                // A stop request is seen within one pixel row of a tile (milliseconds even at
                // many samples per pixel); the pass is then discarded.
                if (stop && stop->load(std::memory_order_relaxed)) {
                    stopped = true;
                    break;
                }
                for (int x = tx; x < x1; ++x) {
                    const size_t pixel = static_cast<size_t>(y) * settings.width + x;
                    const int pixel_spp = all_active ? spp : spp * state.active[pixel];
                    if (pixel_spp == 0) {
                        if (!direct)  // (in place, the sums stay as they are)
                            for (size_t c = 0; c < 3; ++c)
                                out_sum[pixel * 3 + c] = out_sq[pixel * 3 + c] = 0.0;
                        continue;
                    }
                    const int m =
                        static_cast<int>(std::ceil(std::sqrt(static_cast<double>(pixel_spp))));
                    const uint32_t base = state.samples[pixel];
                    Vec3 acc(0.0), acc_sq(0.0);
                    // Progressive passes: the R2 sequence (Roberts 2018) under a random shift
                    // per pixel, so any run of sample indices, across passes too, is spread
                    // over the pixel without bias.
                    Vec2 shift(0.0);
                    if (!settings.centre_first_sample) {
                        Rng pixel_rng(settings.seed, pixel, uint64_t{1} << 40);
                        shift = Vec2(pixel_rng.uniform(), pixel_rng.uniform());
                    }
                    for (int s = 0; s < pixel_spp; ++s) {
                        const uint32_t index = base + static_cast<uint32_t>(s);
                        Rng rng(settings.seed, pixel, index);
                        double sx = 0.5, sy = 0.5;
                        if (!settings.centre_first_sample) {
                            constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
                            sx = std::fmod(shift.x + index * a1, 1.0);
                            sy = std::fmod(shift.y + index * a2, 1.0);
                        } else if (pixel_spp > 1 || base > 0 || stochastic) {
                            // Spec §6.2: one uniform sample in each of the first spp strata of
                            // a ceil(sqrt(spp))^2 grid, row-major.
                            sx = (s % m + rng.uniform()) / m;
                            sy = (s / m + rng.uniform()) / m;
                        }
                        Ray ray = camera.generate(x, y, sx, sy);
                        if (settings.aperture > 0) {
                            // Thin lens: from a point of the aperture toward the focused point.
                            const Vec3 focused =
                                ray.o + ray.d * (focus / glm::dot(ray.d, camera.forward));
                            const Vec2 lens = settings.aperture * rng.disc();
                            ray.o += lens.x * camera.right + lens.y * camera.up;
                            ray.d = glm::normalize(focused - ray.o);
                        }
                        ++counters.camera;
                        const Vec3 c = trace_ray(scene, ray, settings.max_depth, Vec3(1.0), shading,
                                                 counters, stochastic ? &rng : nullptr);
                        acc += c;
                        acc_sq += c * c;
                    }
                    for (int k = 0; k < 3; ++k) {
                        out_sum[pixel * 3 + static_cast<size_t>(k)] = acc[k];
                        out_sq[pixel * 3 + static_cast<size_t>(k)] = acc_sq[k];
                    }
                }
            }
            if (tx + kTile >= settings.width) {
                // Last tile of a tile row: report progress by rows.
                rows_done += y1 - ty;
            }
            if (progress && tile % tiles_x == 0) {
                std::lock_guard lock(mutex);
                progress(rows_done.load(), settings.height);
            }
        }
        std::lock_guard lock(mutex);
        total += counters;
    };

    const int n_threads = std::min(resolve_thread_count(settings.threads), tiles);
    std::vector<std::thread> pool;
    for (int i = 1; i < n_threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (stopped) {
        if (direct) {
            std::fill(state.sum.begin(), state.sum.end(), 0.0);
            std::fill(state.sum_sq.begin(), state.sum_sq.end(), 0.0);
        }
        return false;
    }

    if (!direct) {
        for (size_t i = 0; i < n; ++i) {
            state.sum[i] += out_sum[i];
            state.sum_sq[i] += out_sq[i];
        }
    }
    for (size_t i = 0; i < state.samples.size(); ++i)
        state.samples[i] += static_cast<uint32_t>(all_active ? spp : spp * state.active[i]);
    ++state.passes;
    state.rays += total;
    if (progress) progress(settings.height, settings.height);
    return true;
}

}  // namespace rt
