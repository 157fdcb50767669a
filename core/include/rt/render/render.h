// Rendering: an explicit state (per-pixel sums and sample counts) and one call that adds samples
// to it. The CLI, the viewer and the tests all call render_samples(). Every pixel's samples are
// derived from (seed, pixel, sample index), so the image is the same for any thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "rt/compile/render_scene.h"
#include "rt/image/image.h"
#include "rt/render/camera.h"
#include "rt/render/shading.h"

namespace rt {

struct RenderSettings {
    int width = 640;
    int height = 480;
    int max_depth = 5;
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
    /// True: spec §6.2's sampling (one sample at the pixel centre; N samples jittered in the first
    /// N strata of a ceil(sqrt(N))^2 grid). False (progressive rendering): the pixel's samples
    /// follow a randomly shifted R2 sequence indexed by its sample count, unbiased across passes.
    bool centre_first_sample = true;
    /// Render with the variant specialized to the scene's features (rt/render/features.h); false:
    /// the generic renderer (raytrace --no-specialize), for comparison. Both give the same image.
    bool specialize = true;

    bool stochastic() const { return light_radius > 0 || aperture > 0 || roughness > 0; }
    /// The generic shading settings (every feature tested per ray).
    ShadingSettings shading() const {
        return {max_depth, cutoff, shadows, light_radius, roughness};
    }
    /// The shading settings for `scene`: with `specialize`, its variant and the lights that can
    /// light something (stored in `lights`, which must outlive the result).
    ShadingSettings shading(const RenderScene& scene, std::vector<Light>* lights) const;
};

/// Accumulated samples. Sums are doubles so millions of samples stay exact enough; the sums of
/// squares give each pixel's variance, hence the error estimate without a reference.
struct RenderState {
    int width = 0, height = 0;
    std::vector<double> sum;        // 3 per pixel
    std::vector<double> sum_sq;     // 3 per pixel
    std::vector<uint32_t> samples;  // per pixel
    /// Adaptive sampling: how many times `spp` samples each pixel gets in the next
    /// render_samples() call (0: none). Empty: every pixel gets `spp`.
    std::vector<uint8_t> active;
    int passes = 0;  // 0: every sum is zero (reset() or a new state), so a pass may write in place
    RayCounters rays;
    /// A pass's new sums, then its sums of squares (3 + 3 per pixel), committed when it completes;
    /// kept between calls so later passes reuse it. The first pass of a fresh state needs none.
    std::vector<double> scratch;

    void reset(int w, int h);
    /// The mean of each pixel's samples (spec §9: linear, unclamped).
    Image image() const;
};

/// Progress report: pixels rows done so far out of the total.
using ProgressFn = std::function<void(int rows_done, int rows_total)>;

/// Adds `spp` samples to every pixel (or spp times state.active[p] to pixel p). Where the samples
/// fall is set by RenderSettings::centre_first_sample.
/// `stop`, when set, is polled between tiles; a stopped call leaves the state unchanged.
/// Returns false when stopped.
bool render_samples(RenderState& state, const RenderScene& scene, const RenderSettings& settings,
                    int spp, const ProgressFn& progress = {},
                    const std::atomic<bool>* stop = nullptr);

/// A cheap preview for a moving camera: one centre sample per block x block pixels, copied over
/// the block. It does not touch any RenderState.
Image render_coarse(const RenderScene& scene, const RenderSettings& settings, int block,
                    const std::atomic<bool>* stop = nullptr);

/// Number of threads render_samples() uses for a settings value (0 = all cores).
int resolve_thread_count(int threads);

}  // namespace rt
