// Rendering: an explicit state (per-pixel sums and sample counts) and one call that adds samples
// to it, with a plan made once per scene and settings (rt/render/plan.h). The CLI, the viewer and
// the tests all call render_samples(). Every pixel's samples are derived from (seed, pixel, sample
// index), so the image is the same for any thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rt/image/image.h"
#include "rt/render/camera.h"
#include "rt/render/plan.h"
#include "rt/render/shading.h"
#include "rt/render_scene.h"

namespace rt {

struct RenderSettings {
    int width = 640;
    int height = 480;
    int max_depth = 5;  // at most kMaxDepth (rt/util/limits.h)
    double cutoff = 0.001;
    bool shadows = true;
    int threads = 0;  // 0: all cores
    uint64_t seed = 0;
    // Progressive features, each off at 0 (docs/format.md, "our choices").
    double light_radius = 0.0;    // soft shadows: point and spot lights become spheres
    double aperture = 0.0;        // depth of field: lens radius, scene units
    double focus_distance = 0.0;  // distance of the plane in focus along the view direction;
                                  // 0: the distance to the scene's centre
    double roughness = 0.0;       // glossy reflection
    /// Sphere lights (spec §13.9): the points on the sphere whose shadow rays give a shading
    /// point's shadow factor in a single pass (N >= 1, the centres of the first N strata of a
    /// ceil(sqrt(N))^2 grid) and, jittered, per sample of a supersampled render. Progressive
    /// passes (centre_first_sample false) trace one random point per sample instead.
    int light_samples = 64;
    /// True: spec §6.2's sampling (one sample at the pixel centre; N samples jittered in the first
    /// N strata of a ceil(sqrt(N))^2 grid). False (progressive rendering): the pixel's samples
    /// follow a randomly shifted R2 sequence indexed by its sample count, unbiased across passes.
    bool centre_first_sample = true;
    /// Leave out what the scene does not need (make_render_plan); false: the generic renderer
    /// (raytrace --no-specialize), for comparison. Both give the same image.
    bool specialize = true;

    bool stochastic() const { return light_radius > 0 || aperture > 0 || roughness > 0; }
    bool operator==(const RenderSettings&) const = default;
};

/// Accumulated samples. Sums are doubles so millions of samples stay exact enough. The sums of
/// squares give each pixel's variance (adaptive sampling's guide); the sums of the odd-indexed
/// samples split each pixel's samples into two independent halves, whose difference estimates
/// the image's error without a reference (estimate_error).
struct RenderState {
    int width = 0, height = 0;
    std::vector<double> sum;        // 3 per pixel
    std::vector<double> sum_sq;     // 3 per pixel
    std::vector<double> sum_odd;    // 3 per pixel: the samples of odd index
    bool odd_sums = true;           // false after a merge of parts read from files (they have none)
    std::vector<uint32_t> samples;  // per pixel
    /// Adaptive sampling: how many times `spp` samples each pixel gets in the next
    /// render_samples() call (0: none). Empty: every pixel gets `spp`.
    std::vector<uint8_t> active;
    int passes = 0;  // 0: every sum is zero (reset() or a new state), so a pass may write in place
    RayCounters rays;
    /// A pass's new sums, sums of squares and odd sums (3 + 3 + 3 per pixel), committed when it
    /// completes; kept between calls so later passes reuse it. The first pass of a fresh state
    /// needs none.
    std::vector<double> scratch;

    void reset(int w, int h);
    /// The mean of each pixel's samples (spec §9: linear, unclamped).
    Image image() const;
};

/// Progress report: pixel rows done so far out of the total.
using ProgressFn = std::function<void(int rows_done, int rows_total)>;

/// Adds `spp` samples to every pixel (or spp times state.active[p] to pixel p). Where the samples
/// fall is set by RenderSettings::centre_first_sample. `plan` is make_render_plan(scene, settings)
/// (a plan made for another image size throws std::invalid_argument). `stop`, when set, is
/// polled between tiles and pixel rows; a stopped call leaves the state unchanged. Returns false
/// when stopped.
bool render_samples(RenderState& state, const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, int spp, const ProgressFn& progress = {},
                    const std::atomic<bool>* stop = nullptr);

/// One process's share of a render split across processes or machines (raytrace --tile,
/// --samples; the MPI mode's tiles): samples [first, first + count) of `total` per pixel of the
/// rectangle [x0, x1) x [y0, y1), each placed where the whole render of `total` samples places it
/// (spec §6.2's strata, the same random numbers). The sums are kept per maximal dyadic block of
/// sample indices ([m 2^k, (m + 1) 2^k)): merge_parts() adds them in the order the whole render
/// does, so any split merges into the very bits of render_samples(state, ..., total).
struct RenderPart {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    uint32_t first = 0, count = 0, total = 0;
    struct Block {
        uint32_t start = 0;
        int level = 0;                // samples [start, start + 2^level)
        std::vector<double> sum;      // 3 per pixel of the rectangle, row-major
        std::vector<double> sum_sq;   // 3 per pixel
        std::vector<double> sum_odd;  // 3 per pixel, the odd samples; empty in part files
    };
    std::vector<Block> blocks;  // in the order of their samples
    RayCounters rays;

    size_t pixels() const { return static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0); }
};

/// The maximal dyadic blocks of samples [first, first + count): (start, level) pairs in order.
std::vector<std::pair<uint32_t, int>> dyadic_blocks(uint32_t first, uint32_t count);

/// A width x height image cut into tiles of tile_w x tile_h (those on the right and bottom edges
/// clipped), row by row, each to be rendered with samples [first, first + count) of `total`: the
/// work items of the MPI mode and of the viewer's trace on one thread.
std::vector<RenderPart> tile_parts(int width, int height, int tile_w, int tile_h, uint32_t first,
                                   uint32_t count, uint32_t total);

/// Renders `part`'s rectangle and samples (its blocks are filled; the rectangle must lie in the
/// image and the samples in [0, total)). Throws std::invalid_argument otherwise. Returns false
/// when stopped.
bool render_part(RenderPart& part, const RenderScene& scene, const RenderPlan& plan,
                 const RenderSettings& settings, const ProgressFn& progress = {},
                 const std::atomic<bool>* stop = nullptr);

/// Adds a part's samples to the pixels it covers, as a render_samples() call that rendered
/// those samples would (its blocks folded as one call folds them); counts them in
/// state.samples and its rays in state.rays. The state's size must be the image's. A pass of a
/// progressive render split over processes: add every tile's part, then ++state.passes.
void add_part_samples(RenderState& state, const RenderPart& part);

/// The parts of one width x height render of `total` samples per pixel, combined: every pixel
/// must be covered by exactly samples [0, total), else std::invalid_argument names the first pixel
/// and the samples missing or covered twice, and the parts involved (by `names`, or "part K").
RenderState merge_parts(const std::vector<const RenderPart*>& parts, int width, int height,
                        uint32_t total, const std::vector<std::string>& names = {});

/// A cheap preview for a moving camera: one centre sample per block x block pixels, copied over
/// the block. It does not touch any RenderState; when stopped, the blocks not reached stay black.
Image render_coarse(const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, int block,
                    const std::atomic<bool>* stop = nullptr);

/// Pixel (x, y) of render_samples(state, scene, plan, settings, spp) on a fresh state: the mean
/// of its spp samples, summed as the render sums them (the same bits). Throws
/// std::invalid_argument for a pixel outside the image.
Vec3 render_pixel_value(const RenderScene& scene, const RenderPlan& plan,
                        const RenderSettings& settings, int x, int y, int spp);

/// Number of threads render_samples() uses for a settings value (0 = all cores), at most
/// kMaxThreads.
int resolve_thread_count(int threads);

}  // namespace rt
