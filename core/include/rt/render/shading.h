// Whitted shading (spec §7, §8, §13.9): emissive + ambient + Phong terms of every light with hard
// shadows through transparent occluders, mirror reflection and Snell refraction up to a depth
// and a path-weight cutoff. Textures modulate ambient and diffuse (spec §7.3; V3: emissive and
// specular too). V3 lights add an ambient term each and have a specular colour of their own;
// a sphere light's shadow factor is its mean over the sphere.
#pragma once

#include <cstdint>
#include <vector>

#include "rt/accel/intersect.h"
#include "rt/render/sampler.h"
#include "rt/render_scene.h"
#include "rt/util/limits.h"

namespace rt {

struct RenderPlan;
struct RenderSettings;

/// Rays traced, by kind (for the CLI's rays-per-second figures).
struct RayCounters {
    uint64_t camera = 0, shadow = 0, reflected = 0, refracted = 0;
    uint64_t total() const { return camera + shadow + reflected + refracted; }
    RayCounters& operator+=(const RayCounters& o) {
        camera += o.camera, shadow += o.shadow, reflected += o.reflected, refracted += o.refracted;
        return *this;
    }
};

/// Throws std::invalid_argument, naming kMaxDepth (the deepest a ray may be traced,
/// rt/util/limits.h), when `depth` exceeds it.
void check_depth(int depth);

/// Bilinear, wrapping texture lookup of spec §7.3 (row 0 at the top, v = 0 at the bottom).
Vec3 eval_texture(const TextureImage& tex, const Vec2& uv);

/// The scalar light factor f_l of spec §13.9 (attenuation and spot limit; 1 for directional
/// lights; a sphere light as a point light at its centre) and the unit direction L toward the
/// light at point p; `distance` is the shadow ray's length (infinite for directional lights).
/// Returns 0 when the light contributes nothing there (its ambient term included).
double light_factor(const Light& light, const Vec3& p, Vec3* to_light, double* distance);

/// Incoming light intensity I_l = diffuse colour * f_l and L (spec §7.2). Returns false when the
/// light contributes nothing there.
bool eval_light(const Light& light, const Vec3& p, Vec3* intensity, Vec3* to_light,
                double* distance);

/// The colour seen along a ray of the given depth and path weight, by the plan's shading code
/// and ray queries over the plan's lights; `settings` gives the cutoff, shadows and progressive
/// features (those the plan was made with). `rng` feeds the stochastic features and, for a
/// sample that is not a single pass's pixel centre, the points on sphere lights (spec §13.9: one
/// uniform point per progressive sample, settings.light_samples jittered strata per supersample);
/// without one the result is the deterministic colour (sphere lights: the plan's points).
/// `depth` is at most kMaxDepth (check_depth).
Vec3 trace_ray(const RenderScene& scene, const RenderPlan& plan, const RenderSettings& settings,
               const Ray& ray, int depth, const Vec3& weight, RayCounters& counters,
               Rng* rng = nullptr);

}  // namespace rt
