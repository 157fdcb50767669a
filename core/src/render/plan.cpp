// make_render_plan(): what the scene uses, the variant that leaves the rest out, and why.
#include "rt/render/plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "rt/render/render.h"
#include "rt/render/sampler.h"
#include "variants.h"

namespace rt {

namespace {

bool lights_something(const Light& l) {
    if (l.ambient == Vec3(0.0) && l.diffuse == Vec3(0.0) && l.specular == Vec3(0.0)) return false;
    if (l.kind == LightKind::Directional) return true;
    // All three coefficients zero: the denominator is never positive (spec §7.2).
    return l.constant_atten != 0.0 || l.linear_atten != 0.0 || l.quadratic_atten != 0.0;
}

bool scales_unevenly(const Mat4& m) {
    const double x = glm::length(Vec3(m[0])), y = glm::length(Vec3(m[1])),
                 z = glm::length(Vec3(m[2]));
    const double lo = std::min(x, std::min(y, z)), hi = std::max(x, std::max(y, z));
    // Also a shear: the columns of a uniform scale times a rotation are orthogonal.
    const double shear = std::abs(glm::dot(Vec3(m[0]), Vec3(m[1]))) +
                         std::abs(glm::dot(Vec3(m[1]), Vec3(m[2]))) +
                         std::abs(glm::dot(Vec3(m[0]), Vec3(m[2])));
    return hi - lo > 1e-12 * hi || shear > 1e-12 * hi * hi;
}

// The geometry variant: what the walk does.
void explain_geometry(const GeometryFeatures& g, std::vector<PlanReason>& out) {
    auto line = [&](bool used, const char* feature, const std::string& why_kept,
                    const std::string& why_left) {
        out.push_back({feature, used, used ? why_kept : why_left});
    };
    if (g.variant == kGeomEmpty) {
        line(false, "ray queries", "", "the scene has no shapes, every ray sees the background");
        return;
    }
    line((g.variant & kGeomInstancing) != 0, "top-level BVH",
         g.instancing ? "the scene places several instances"
                      : "the one instance has a transform: its box culls rays before they are "
                        "transformed",
         "one instance: rays walk its BVH directly");
    line((g.variant & kGeomTransforms) != 0, "transforms", "a group or instance transform",
         "no group or instance transform: rays are never transformed");
    line((g.variant & kGeomCsg) != 0, "CSG test",
         std::to_string(g.csg_nodes) +
             " CSG node(s): a hit counts where every node above it keeps it (spec §13.8)",
         "no CSG node: every hit counts, no inside tests");
    // A kind with a test of its own per ray says so (kPlanNote, shapes.h).
    [&]<size_t... I>(std::index_sequence<I...>) {
        const auto note = [&](auto tag) {
            using T = typename decltype(tag)::type;
            if constexpr (requires { T::kPlanNote; }) {
                const size_t n = g.prims[static_cast<int>(T::kKind)];
                line(n > 0, (std::string(T::kName) + " test").c_str(),
                     std::to_string(n) + " " + T::kName + " primitive(s): " + T::kPlanNote[0],
                     std::string("no ") + T::kName + ": " + T::kPlanNote[1]);
            }
        };
        (note(std::type_identity<std::variant_alternative_t<I, Shape>>{}), ...);
    }
    (std::make_index_sequence<kShapeKinds>{});
    const size_t n_triangles = g.prims[static_cast<int>(ShapeKind::Triangle)];
    line(n_triangles > 0, "triangle tests", std::to_string(n_triangles) + " triangle(s)",
         "no triangles: no triangle set-up per ray");
    const uint32_t layout = (g.variant & kGeomPerSet) >> kGeomLayoutShift;
    static const char* const kOneKind[][2] = {
        {"spheres", "sphere"}, {"boxes", "box"}, {"cylinders", "cylinder"}, {"cones", "cone"}};
    const uint32_t first_one_kind = static_cast<uint32_t>(SetLayout::Spheres);
    const uint32_t triangles = static_cast<uint32_t>(SetLayout::Triangles);
    if (layout == triangles) {
        line(false, "shape dispatch", "",
             "triangles only: leaves hold packed triangles, four tested at once");
    } else if (layout >= first_one_kind && layout < triangles) {
        const auto& kind = kOneKind[layout - first_one_kind];
        line(false, "shape dispatch", "",
             std::string(kind[0]) + " only: leaves call the " + kind[1] + " test directly");
    } else if (layout == kSetLayouts) {
        line(true, "shape dispatch",
             "the instanced files differ: each is walked by its own layout (one switch per file "
             "a ray enters)",
             "");
    } else {
        const int tri = static_cast<int>(ShapeKind::Triangle);
        size_t analytic = 0;
        int kinds = 0;
        for (int k = 0; k < kShapeKinds; ++k) {
            if (k == tri) continue;
            analytic += g.prims[k];
            kinds += g.prims[k] > 0;
        }
        line(true, "shape dispatch",
             std::to_string(analytic) + " analytic shape(s) of " + std::to_string(kinds) +
                 " kind(s)" + (g.prims[tri] > 0 ? " and triangles" : "") + " in one file",
             "");
    }
}

// One shape primitive (or CSG leaf) of a set: its kind, material and transform.
void count_primitive(const GeometrySet& set, const Primitive& p, GeometryFeatures& g,
                     std::array<size_t, kShapeKinds>& kinds) {
    g.material_used[static_cast<size_t>(p.material)] = 1;
    ++kinds[static_cast<size_t>(p.kind)];
    if (p.transform >= 0) {
        g.transforms = true;
        g.nonuniform_scale |= scales_unevenly(set.transforms[static_cast<size_t>(p.transform)].m);
    }
}

}  // namespace

GeometryFeatures read_geometry(const RenderScene& scene) {
    GeometryFeatures g;
    std::vector<char> set_used(scene.sets.size(), 0);
    g.material_used.assign(scene.materials.size(), 0);
    std::vector<std::array<size_t, kShapeKinds>> set_prims(scene.sets.size());
    std::vector<size_t> set_csg(scene.sets.size(), 0);
    for (const Instance& inst : scene.instances) {
        const size_t si = static_cast<size_t>(inst.set);
        const GeometrySet& set = scene.sets[si];
        if (!set_used[si]) {  // each set once, however often it is instanced
            set_used[si] = 1;
            set_prims[si] = {};
            for (const Primitive& p : set.prims) {
                if (p.csg < 0) {
                    count_primitive(set, p, g, set_prims[si]);
                    continue;
                }
                const CsgRoot& r = set.csg.roots[static_cast<size_t>(p.csg)];
                for (uint32_t l = r.first_leaf; l < r.first_leaf + r.leaf_count; ++l)
                    count_primitive(set, set.csg.leaves[l].prim, g, set_prims[si]);
            }
            set_csg[si] = set.csg.operations();
        }
        for (size_t k = 0; k < kShapeKinds; ++k) g.prims[k] += set_prims[si][k];
        g.csg_nodes += set_csg[si];
        if (!inst.identity) {
            g.transforms = true;
            g.nonuniform_scale |= scales_unevenly(inst.world_from_set.m);
        }
    }
    g.instancing = scene.instances.size() > 1;
    // The layout every placed set shares, or a walk picked per set.
    uint32_t layout = 0;
    bool first = true;
    for (size_t i = 0; i < scene.sets.size(); ++i) {
        if (!set_used[i]) continue;
        const uint32_t l = geom_layout_bits(scene.sets[i].layout);
        layout = first || l == layout ? l : kGeomPerSet;
        first = false;
    }
    // One instance is walked directly, unless it has a transform: then the top-level box test
    // culls the rays that miss it before they are transformed.
    g.top_level = g.instancing || (scene.instances.size() == 1 && !scene.instances[0].identity);
    g.variant = (g.top_level ? kGeomInstancing : 0u) | (g.transforms ? kGeomTransforms : 0u) |
                (g.csg_nodes > 0 ? kGeomCsg : 0u) | layout;
    if (scene.instances.empty()) g.variant = kGeomEmpty;
    return g;
}

SceneFeatures scene_features(const RenderScene& scene, const RenderSettings& settings) {
    SceneFeatures f;
    f.max_depth = settings.max_depth;
    f.light_samples = settings.light_samples;
    for (const Light& l : scene.lights) {
        if (!lights_something(l)) {
            ++f.dark_lights;
            continue;
        }
        ++f.lights[static_cast<int>(l.kind)];
        f.direct_lights += l.diffuse != Vec3(0.0) || l.specular != Vec3(0.0);
        f.ambient_lights += l.ambient != Vec3(0.0);
        f.specular_colour_lights += l.diffuse != l.specular;
    }
    // Shadow rays and highlights serve the lights with a diffuse or specular colour.
    const bool lit = f.direct_lights > 0;
    f.geometry = read_geometry(scene);
    const GeometryFeatures& g = f.geometry;
    auto material_used = [&](size_t i) { return g.material_used[i] != 0; };

    std::vector<char> texture_used(scene.textures.size(), 0);
    bool any_ambient = false;
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        if (!material_used(i)) continue;
        const Material& m = scene.materials[i];
        f.highlights |= m.specular != Vec3(0.0);
        f.transmissive_shadows |= m.transparent != Vec3(0.0);
        f.refraction |= m.transparent != Vec3(0.0);
        f.reflection |= m.specular != Vec3(0.0);
        f.emissive |= m.emissive != Vec3(0.0);
        any_ambient |= m.ambient != Vec3(0.0);
        if (m.texture >= 0) {
            f.textures = true;
            texture_used[static_cast<size_t>(m.texture)] = 1;
        }
    }
    for (char used : texture_used) f.unused_textures += !used;
    f.ambient = any_ambient && scene.ambient != Vec3(0.0);
    f.light_ambient = any_ambient && f.ambient_lights > 0;
    // A camera ray has depth max_depth; children are traced while depth - 1 >= 1 (spec §8).
    f.reflection &= settings.max_depth > 1;
    f.refraction &= settings.max_depth > 1;
    f.shadows = settings.shadows && lit;
    f.transmissive_shadows &= f.shadows;
    f.highlights &= lit;
    // Sphere lights move the light point (direction and attenuation too), shadows on or off.
    f.soft_shadows = settings.light_radius > 0 && f.lights[1] + f.lights[2] > 0;
    f.glossy = settings.roughness > 0 && f.reflection;
    f.depth_of_field = settings.aperture > 0;
    return f;
}

uint32_t SceneFeatures::shade_variant() const {
    uint32_t v = 0;
    if (shadows) v |= kShadeShadows;
    if (transmissive_shadows) v |= kShadeTransmissiveShadows;
    if (reflection) v |= kShadeReflection;
    if (refraction) v |= kShadeRefraction;
    if (textures) v |= kShadeTextures;
    if (highlights) v |= kShadeHighlights;
    if (lights[static_cast<int>(LightKind::Spot)] > 0) v |= kShadeSpot;
    if (lights[static_cast<int>(LightKind::Point)] + lights[static_cast<int>(LightKind::Spot)] +
            lights[static_cast<int>(LightKind::Sphere)] >
        0)
        v |= kShadeAttenuation;
    if (soft_shadows || glossy) v |= kShadeStochastic;
    if (v3_lights()) v |= kShadeV3Lights;
    return v;
}

namespace {

// The light side of the shading variant: the kinds, and the terms of V3 lights (spec §13.9).
void explain_lights(const SceneFeatures& f, std::vector<PlanReason>& out) {
    auto line = [&](bool used, const char* feature, const std::string& why_kept,
                    const std::string& why_left) {
        out.push_back({feature, used, used ? why_kept : why_left});
    };
    auto count = [&](LightKind k) { return f.lights[static_cast<int>(k)]; };
    const int spot = count(LightKind::Spot), sphere = count(LightKind::Sphere);
    const int attenuated = count(LightKind::Point) + spot + sphere;
    if (f.dark_lights > 0)
        out.push_back({std::to_string(f.dark_lights) + " light(s)", false,
                       "colour zero or all attenuation coefficients zero"});
    line(attenuated > 0, "light attenuation",
         std::to_string(attenuated) +
             (sphere > 0 ? " point, spot or sphere light(s)" : " point or spot light(s)"),
         "no point, spot or sphere light");
    line(spot > 0, "spot cut-off and drop-off", std::to_string(spot) + " spot light(s)",
         "no spot light");
    line(sphere > 0 && f.shadows, "sphere light sampling",
         std::to_string(sphere) + " sphere light(s): shadow rays to " +
             std::to_string(f.light_samples) +
             " point(s) on each (--light-samples; progressive: one random point a sample)",
         sphere > 0 ? "no shadow rays" : "no sphere light");
    line(f.light_ambient, "light ambient terms",
         std::to_string(f.ambient_lights) + " light(s) with an ambient colour",
         f.ambient_lights > 0 ? "no material with an ambient colour"
                              : "no light has an ambient colour");
    line(f.specular_colour_lights > 0, "light specular colours",
         std::to_string(f.specular_colour_lights) +
             " light(s) whose specular colour is not their diffuse colour",
         "every light's specular colour is its diffuse colour");
}

}  // namespace

std::vector<PlanReason> explain_features(const SceneFeatures& f) {
    std::vector<PlanReason> out;
    auto line = [&](bool used, const char* feature, const std::string& why_kept,
                    const std::string& why_left) {
        out.push_back({feature, used, used ? why_kept : why_left});
    };
    const GeometryFeatures& g = f.geometry;
    const int lit = f.direct_lights;
    const std::string n_lights = std::to_string(lit);
    explain_lights(f, out);
    line(f.shadows, "shadow rays", n_lights + " light(s) that light something",
         lit == 0 ? "no light lights anything" : "shadows are switched off");
    line(f.transmissive_shadows, "transparent shadows", "a material lets light through",
         f.shadows ? "no transparent material: shadow rays stop at the first hit"
                   : "no shadow rays");
    line(f.reflection, "reflection", "a material with a specular colour",
         f.max_depth <= 1 ? "recursion depth 1" : "no material with a specular colour");
    line(f.refraction, "refraction", "a transparent material",
         f.max_depth <= 1 ? "recursion depth 1" : "no transparent material");
    line(f.highlights, "specular highlights", "a material with a specular colour",
         lit == 0 ? "no light lights anything" : "no material with a specular colour");
    line(f.textures, "texture lookups", "a textured material", "no material uses a texture");
    if (f.unused_textures > 0)
        out.push_back(
            {std::to_string(f.unused_textures) + " texture(s)", false, "no material uses them"});
    line(f.soft_shadows || f.glossy, "random sampling in shading",
         f.soft_shadows ? "soft shadows are on" : "glossy reflection is on",
         "soft shadows and glossy reflection are off");
    explain_geometry(g, out);
    return out;
}

std::string reason_line(const PlanReason& r) {
    return (r.kept ? "kept: " : "left out: ") + r.feature + ": " + r.why;
}

RenderPlan make_render_plan(const RenderScene& scene, const RenderSettings& settings) {
    RenderPlan plan;
    plan.camera = make_camera(scene, settings.width, settings.height);
    plan.focus_distance = settings.focus_distance > 0
                              ? settings.focus_distance
                              : glm::length(scene.world_bounds.centre() - plan.camera.position);
    const SceneFeatures f = scene_features(scene, settings);
    plan.reasons = explain_features(f);
    plan.specialized = settings.specialize;
    const uint32_t shade = settings.specialize ? f.shade_variant() : kShadeAll;
    plan.shading = &shading_variant(shade);
    plan.geometry = &geometry_queries(settings.specialize ? f.geometry.variant : kGeomGeneric);
    // Dark lights are skipped, except where random samples are drawn per light (soft shadows):
    // skipping one there would shift every later sample, and the images must stay the same.
    const bool skip_dark = settings.specialize && !(shade & kShadeStochastic);
    for (const Light& l : scene.lights)
        if (!skip_dark || lights_something(l)) plan.lights.push_back(l);
    for (const Light& l : plan.lights) plan.uses.light_kinds[static_cast<int>(l.kind)] = true;
    // The single-pass estimate of sphere lights: the same points for every shading point.
    plan.light_samples = std::max(1, settings.light_samples);
    const auto sphere = [](const Light& l) { return l.kind == LightKind::Sphere && l.radius > 0; };
    if (std::any_of(plan.lights.begin(), plan.lights.end(), sphere)) {
        const int m =
            static_cast<int>(std::ceil(std::sqrt(static_cast<double>(plan.light_samples))));
        for (int k = 0; k < plan.light_samples; ++k)
            plan.sphere_points.push_back(uniform_sphere(stratum_point(k, m, Vec2(0.5))));
    }
    plan.uses.textures = f.textures;
    plan.uses.highlights = f.highlights;
    plan.uses.shadows = f.shadows;
    return plan;
}

bool intersect(const RenderScene& scene, const RenderPlan& plan, const Ray& ray, Interval t,
               Hit* hit) {
    return plan.geometry->intersect(scene, ray, t, hit);
}

bool occluded(const RenderScene& scene, const RenderPlan& plan, const Ray& ray, double t_max) {
    return plan.geometry->occluded(scene, ray, t_max);
}

Vec3 transmittance(const RenderScene& scene, const RenderPlan& plan, const Ray& ray, double t_max) {
    return plan.geometry->transmittance(scene, ray, t_max);
}

SurfaceInteraction interaction(const RenderScene& scene, const RenderPlan& plan, const Ray& ray,
                               const Hit& hit, bool uv) {
    return plan.geometry->interaction(scene, ray, hit, uv);
}

}  // namespace rt
