// Where a pixel's samples fall and the camera rays through them: what render_samples() traces,
// and what the AOV pass (aov.cpp) traces again, so both see the very same rays.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/render/sampler.h"

namespace rt {

/// The pixel's random shifts of the progressive sequences (even samples, odd samples); zero
/// with settings.centre_first_sample, whose strata take none.
inline std::array<Vec2, 2> progressive_shifts(const RenderSettings& settings, size_t pixel) {
    std::array<Vec2, 2> shift{Vec2(0.0), Vec2(0.0)};
    if (!settings.centre_first_sample) {
        Rng pixel_rng(settings.seed, pixel, uint64_t{1} << 40);
        for (Vec2& sh : shift) sh = Vec2(pixel_rng.uniform(), pixel_rng.uniform());
    }
    return shift;
}

/// Where the s-th of a pixel's n samples of one render_samples() call falls in the pixel, in
/// [0,1)^2. The pixel has `base` samples from earlier calls; `stratum` is ceil(sqrt(n)),
/// `shift` progressive_shifts(); `stochastic` is settings.stochastic(). Draws from `rng` (the
/// sample's) in the order the render does.
inline Vec2 sample_position(const RenderSettings& settings, bool stochastic, int s, int n,
                            uint32_t base, int stratum, const std::array<Vec2, 2>& shift,
                            Rng& rng) {
    const uint32_t index = base + static_cast<uint32_t>(s);
    if (!settings.centre_first_sample) {
        // Progressive passes: the even and the odd samples each follow the R2 sequence (Roberts
        // 2018) under a random shift of their own per pixel, so any run of sample indices,
        // across passes too, is spread over the pixel without bias, and the means of the even
        // and the odd samples are independent estimates (their difference estimates the error).
        constexpr double a1 = 0.7548776662466927, a2 = 0.5698402909980532;
        const Vec2 sh = shift[index & 1];
        const uint32_t k = index >> 1;
        return {std::fmod(sh.x + k * a1, 1.0), std::fmod(sh.y + k * a2, 1.0)};
    }
    if (n > 1 || base > 0 || stochastic) {
        // Spec §6.2: one uniform sample in each of the first n strata of a ceil(sqrt(n))^2
        // grid, row-major.
        const double sx = (s % stratum + rng.uniform()) / stratum;
        const double sy = (s / stratum + rng.uniform()) / stratum;
        return {sx, sy};
    }
    return {0.5, 0.5};  // one sample: the pixel centre
}

/// The camera ray through pixel (x, y) at `sample`; with an aperture, from a point of the lens
/// (drawn from `rng` after the sample position).
inline Ray camera_ray(const RenderPlan& plan, const RenderSettings& settings, int x, int y,
                      Vec2 sample, Rng& rng) {
    const Camera& camera = plan.camera;
    Ray ray = camera.generate(x, y, sample.x, sample.y);
    if (settings.aperture > 0) {
        // Thin lens: from a point of the aperture toward the focused point.
        const Vec3 focused =
            ray.o + ray.d * (plan.focus_distance / glm::dot(ray.d, camera.forward));
        const Vec2 lens = settings.aperture * rng.disc();
        ray.o += lens.x * camera.right + lens.y * camera.up;
        ray.d = glm::normalize(focused - ray.o);
    }
    return ray;
}

}  // namespace rt
