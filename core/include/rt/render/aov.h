// Arbitrary output variables (AOVs): per-pixel values beside the colour that denoisers and
// compositing read, written as extra channels of an EXR file (rt/image/exr.h). The first-hit
// values (albedo, shading normal, depth) come from a pass of their own over the camera rays the
// render traced, so the render loop stays as it is and costs nothing when none is asked for;
// the sample count and the variance come from the RenderState.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "rt/image/exr.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/render_scene.h"

namespace rt {

/// Which AOVs to write.
struct AovSet {
    bool albedo = false, normal = false, depth = false, samples = false, variance = false;

    bool any() const { return albedo || normal || depth || samples || variance; }
    bool first_hit() const { return albedo || normal || depth; }
    bool operator==(const AovSet&) const = default;
};

/// Adds the AOV named `name` (albedo, normal, depth, samples or variance) to *set; false for
/// any other name.
bool add_aov(const std::string& name, AovSet* set);
/// "albedo, normal, depth, samples, variance": the names add_aov() takes.
std::string aov_names();
/// The AOVs of the set by name, in that order, comma-separated ("albedo,depth").
std::string aov_list(const AovSet& set);

/// The first hit of every camera ray of each pixel, averaged over the pixel's samples.
struct FirstHitAovs {
    int width = 0, height = 0;
    /// The material's diffuse colour K_D times its texel (what the shading multiplies by the
    /// light), 3 per pixel; a ray that hits nothing adds 0.
    std::vector<double> albedo;
    /// The shading normal in world space, unit, facing the ray as the shading turns it (spec §5),
    /// 3 per pixel; a ray that hits nothing adds 0. The mean of unit normals, not renormalised
    /// (shorter than 1 where a pixel's samples see different normals).
    std::vector<double> normal;
    /// The distance from the ray's origin (the camera, or the lens point with an aperture) to the
    /// hit, averaged over the samples that hit something; +infinity where none does.
    std::vector<double> depth;
};

/// Traces the camera rays of samples 0 .. samples[p] - 1 of every pixel p, as render_samples()
/// placed them (the same jitter, lens points and random numbers): with
/// settings.centre_first_sample the n samples of one render_samples(..., n) call (spec §6.2: one
/// sample is the pixel centre, n > 1 the first n strata jittered; also a merge of parts of such
/// a render), else the progressive sequence (any number of calls). `samples` holds
/// width * height counts (RenderState::samples); a pixel without samples gets the pixel centre's
/// ray. Parallel over settings.threads; `plan` is make_render_plan(scene, settings). Returns an
/// empty result (width 0) when stopped.
FirstHitAovs render_first_hit_aovs(const RenderScene& scene, const RenderPlan& plan,
                                   const RenderSettings& settings,
                                   const std::vector<uint32_t>& samples,
                                   const std::atomic<bool>* stop = nullptr);

/// Each pixel's sample variance per channel, 3 per pixel: (sum_sq - sum^2 / n) / (n - 1) for
/// n >= 2 samples (unbiased; never negative), 0 for fewer. The variance of one sample, as
/// pbrt-v4's GBufferFilm writes it; the variance of the pixel's mean is this divided by n.
std::vector<double> sample_variance(const RenderState& state);

/// The AOVs of `set` as EXR channels for save_exr(), for the render in `state` (rendered with
/// scene, plan and settings). Names (layers as viewers show them; pbrt-v4's GBufferFilm names
/// where it has them): Albedo.R/G/B, Ns.X/Y/Z (the shading normal, in world space), depth.Z
/// (Nuke's depth layer; always 32-bit float), Samples.N (32-bit unsigned, exact for any count)
/// and Variance.R/G/B. The other channels are half unless the file is float.
std::vector<ExrChannel> aov_channels(const AovSet& set, const RenderState& state,
                                     const RenderScene& scene, const RenderPlan& plan,
                                     const RenderSettings& settings);

}  // namespace rt
