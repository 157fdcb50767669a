// The render plan: what a render of one scene with one set of settings needs beyond the scene,
// made once by make_render_plan() and read by every pass. It is the one place that leaves out
// what the scene does not need: it reads what the scene uses (from its values, not only its
// syntax: a material with zero specular colour reflects nothing; a light of colour zero lights
// nothing) and picks the shading code and the ray queries compiled without the rest.
// RenderSettings::specialize = false plans the generic renderer (every feature tested per ray),
// which renders the same image.
#pragma once

#include <string>
#include <vector>

#include "rt/accel/intersect.h"
#include "rt/render/camera.h"
#include "rt/render_scene.h"

namespace rt {

struct RenderSettings;
// The variants chosen, as entries of private tables (core/src/render/variants.h).
struct ShadingVariant;
struct GeometryQueries;

/// Why a feature of the renderer is kept or left out for a scene (raytrace --explain, the
/// viewer's status).
struct PlanReason {
    std::string feature;
    bool kept = false;
    std::string why;
};

/// "kept: <feature>: <why>" or "left out: <feature>: <why>".
std::string reason_line(const PlanReason& reason);

/// What the scene uses, as plain facts (the viewer's preview compiles its shaders for them).
struct PlanUses {
    bool light_kinds[kLightKinds] = {};  // among RenderPlan::lights, by LightKind
    bool textures = false;               // a placed primitive's material is textured
    bool highlights = false;             // a placed primitive's material has a specular colour
    bool shadows = false;                // shadows are on and some light lights something
};

struct RenderPlan {
    Camera camera;  // the scene's, or the default camera of spec §6.3 at the settings' size
    double focus_distance = 0.0;  // thin lens: the settings' or the distance to the scene's centre
    std::vector<Light> lights;    // the lights the shading iterates
    /// Sphere lights (spec §13.9): the unit directions w(xi_k) of the single-pass estimate, the
    /// centres of the first light_samples strata (empty without a sphere light of radius > 0),
    /// and that count, which supersampled renders jitter.
    std::vector<Vec3> sphere_points;
    int light_samples = 1;
    bool specialized = false;  // false: the generic renderer (RenderSettings::specialize)
    /// What the scene uses, one reason per feature, however the plan was made.
    std::vector<PlanReason> reasons;
    PlanUses uses;
    const ShadingVariant* shading = nullptr;
    const GeometryQueries* geometry = nullptr;
};

/// The plan for rendering `scene` with `settings` (their size, depth, shadows and progressive
/// features). It stays valid while the scene's geometry, lights and materials stay as they were.
RenderPlan make_render_plan(const RenderScene& scene, const RenderSettings& settings);

/// The ray queries of rt/accel/intersect.h with the plan's walk (the one that fits the scene).
bool intersect(const RenderScene& scene, const RenderPlan& plan, const Ray& ray, Interval t,
               Hit* hit);
bool occluded(const RenderScene& scene, const RenderPlan& plan, const Ray& ray, double t_max);
Vec3 transmittance(const RenderScene& scene, const RenderPlan& plan, const Ray& ray, double t_max);
SurfaceInteraction interaction(const RenderScene& scene, const RenderPlan& plan, const Ray& ray,
                               const Hit& hit, bool uv = true);

}  // namespace rt
