#include "rt/render.h"

#include <algorithm>
#include <mutex>
#include <thread>

namespace rt {

void RenderState::reset(int w, int h) {
    width = w;
    height = h;
    sum.assign(static_cast<size_t>(w) * h * 3, 0.0);
    samples.assign(static_cast<size_t>(w) * h, 0);
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
    if (threads > 0) return threads;
    return std::max(1u, std::thread::hardware_concurrency());
}

namespace {

// A counter-based generator: the stream depends only on (seed, pixel, sample), never on the
// thread that runs the tile (PCG's output permutation over a SplitMix64-style hash).
struct Rng {
    uint64_t state;
    explicit Rng(uint64_t seed, uint64_t pixel, uint64_t sample) {
        state = mix(seed ^ mix(pixel * 0x9E3779B97F4A7C15ull + sample + 1));
    }
    static uint64_t mix(uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() {  // [0, 1)
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(mix(state) >> 11) * 0x1.0p-53;
    }
};

constexpr int kTile = 16;

}  // namespace

bool render_samples(RenderState& state, const RenderScene& scene, const RenderSettings& settings,
                    int spp, const ProgressFn& progress, const std::atomic<bool>* stop) {
    if (state.width != settings.width || state.height != settings.height)
        state.reset(settings.width, settings.height);
    if (spp <= 0) return true;
    const Camera camera = make_camera(scene, settings.width, settings.height);
    const ShadingSettings shading{settings.max_depth, settings.cutoff, settings.shadows};
    const int m = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(spp))));

    const int tiles_x = (settings.width + kTile - 1) / kTile;
    const int tiles_y = (settings.height + kTile - 1) / kTile;
    const int tiles = tiles_x * tiles_y;
    std::atomic<int> next{0};
    std::atomic<int> rows_done{0};
    std::atomic<bool> stopped{false};
    std::mutex mutex;
    RayCounters total;
    // New sums go to a scratch buffer and are committed only when the pass completes.
    std::vector<double> pass(state.sum.size(), 0.0);

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
                    const uint32_t base = state.samples[pixel];
                    Vec3 acc(0.0);
                    for (int s = 0; s < spp; ++s) {
                        double sx = 0.5, sy = 0.5;
                        if (spp > 1 || base > 0) {
                            Rng rng(settings.seed, pixel, base + static_cast<uint32_t>(s));
                            // One uniform sample in each of the first spp strata, row-major.
                            sx = (s % m + rng.uniform()) / m;
                            sy = (s / m + rng.uniform()) / m;
                        }
                        const Ray ray = camera.generate(x, y, sx, sy);
                        ++counters.camera;
                        acc +=
                            trace_ray(scene, ray, settings.max_depth, Vec3(1.0), shading, counters);
                    }
                    pass[pixel * 3] = acc.x;
                    pass[pixel * 3 + 1] = acc.y;
                    pass[pixel * 3 + 2] = acc.z;
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
    if (stopped) return false;

    for (size_t i = 0; i < state.sum.size(); ++i) state.sum[i] += pass[i];
    for (uint32_t& n : state.samples) n += static_cast<uint32_t>(spp);
    state.rays += total;
    if (progress) progress(settings.height, settings.height);
    return true;
}

}  // namespace rt
