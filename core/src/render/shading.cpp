#include "rt/render/shading.h"

#include <array>
#include <utility>

#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "variants.h"

namespace rt {

Vec3 eval_texture(const TextureImage& tex, const Vec2& uv) {
    if (tex.width <= 0 || tex.height <= 0) return Vec3(1.0);
    const double u = uv.x - std::floor(uv.x), v = uv.y - std::floor(uv.y);
    const double x = u * tex.width - 0.5;
    const double y = (1.0 - v) * tex.height - 0.5;  // y counts rows from the top
    const double x0f = std::floor(x), y0f = std::floor(y);
    const double fx = x - x0f, fy = y - y0f;
    auto wrap = [](long long a, int n) { return static_cast<int>(((a % n) + n) % n); };
    auto texel = [&](long long c, long long r) {
        const size_t i = (static_cast<size_t>(wrap(r, tex.height)) * tex.width +
                          static_cast<size_t>(wrap(c, tex.width))) *
                         3;
        return Vec3(tex.rgb[i], tex.rgb[i + 1], tex.rgb[i + 2]) / 255.0;
    };
    const long long x0 = static_cast<long long>(x0f), y0 = static_cast<long long>(y0f);
    return (1 - fx) * (1 - fy) * texel(x0, y0) + fx * (1 - fy) * texel(x0 + 1, y0) +
           (1 - fx) * fy * texel(x0, y0 + 1) + fx * fy * texel(x0 + 1, y0 + 1);
}

namespace {

// Spec §7.2 for the light kinds a variant has: without kAttenuation only directional lights
// (no distance or attenuation), without kSpot no cut-off or drop-off code. eval_light is the
// version with every kind.
template <bool kAttenuation, bool kSpot>
bool light_kinds(const Light& light, const Vec3& p, Vec3* intensity, Vec3* to_light,
                 double* distance) {
    if (light.diffuse == Vec3(0.0)) return false;  // lights nothing (not 0 * inf = NaN either)
    if (!kAttenuation || light.kind == LightKind::Directional) {
        *to_light = -light.direction;
        *intensity = light.diffuse;
        *distance = kInf;
        return true;
    }
    const Vec3 delta = light.position - p;
    const double dist = glm::length(delta);
    if (!(dist > 0.0) || !std::isfinite(dist)) return false;
    const Vec3 l = delta / dist;
    const double denom =
        light.constant_atten + light.linear_atten * dist + light.quadratic_atten * dist * dist;
    if (!(denom > 0.0) || !std::isfinite(denom)) return false;
    double factor = 1.0 / denom;
    if (kSpot && light.kind == LightKind::Spot) {
        const double cos_a = glm::dot(light.direction, -l);
        if (std::acos(std::clamp(cos_a, -1.0, 1.0)) > light.cutoff_rad) return false;
        // The factor is 1 when p = 0, whatever the angle (spec §7.2).
        if (light.spot_exponent != 0.0)
            factor *= std::pow(std::max(0.0, cos_a), light.spot_exponent);
    }
    *intensity = light.diffuse * factor;
    *to_light = l;
    *distance = dist;
    return factor > 0.0;
}

template <uint32_t F>
bool light_at(const Light& light, const Vec3& p, Vec3* intensity, Vec3* to_light,
              double* distance) {
    return light_kinds<(F & kShadeAttenuation) != 0, (F & kShadeSpot) != 0>(light, p, intensity,
                                                                            to_light, distance);
}

}  // namespace

bool eval_light(const Light& light, const Vec3& p, Vec3* intensity, Vec3* to_light,
                double* distance) {
    return light_kinds<true, true>(light, p, intensity, to_light, distance);
}

namespace {

// The light as one sample sees it: with soft shadows (F stochastic, a radius set), a point or
// spot light is a sphere of radius light_radius, sampled uniformly over the disc it shows the
// point p (the moved light is written to *moved); its emission rules stay.
template <uint32_t F>
[[gnu::always_inline]] inline const Light& sampled_light(const Light& light, const Vec3& p,
                                                         const RenderSettings& settings, Rng* rng,
                                                         Light* moved) {
    if constexpr ((F & kShadeStochastic) != 0) {
        if (rng && settings.light_radius > 0.0 && light.kind != LightKind::Directional) {
            const Vec3 axis = light.position - p;
            if (glm::dot(axis, axis) > 0.0) {
                Vec3 a, b;
                orthonormal_basis(glm::normalize(axis), &a, &b);
                const Vec2 q = settings.light_radius * rng->disc();
                *moved = light;
                moved->position += q.x * a + q.y * b;
                return *moved;
            }
        }
    }
    return light;
}

// The shadow ray from si toward the light (unit direction l): false when it is blocked, else
// true with *s the transmittance of the surfaces it crosses (1 when F has no transparent
// shadows: then the first hit decides). Inlined: as a call it costs 1% of a render.
template <uint32_t F>
[[gnu::always_inline]] inline bool shadow_ray_passes(const RenderScene& scene,
                                                     const GeometryQueries& geometry,
                                                     const SurfaceInteraction& si,
                                                     const Light& light, const Vec3& l, Vec3* s,
                                                     RayCounters& counters) {
    ++counters.shadow;
    const Vec3 o = offset_origin(si, l);
    // Toward a point light the segment from the offset point to the light itself, t in (0, 1).
    const bool directional = light.kind == LightKind::Directional;
    const Ray shadow_ray{o, directional ? l : light.position - o};
    const double t_max = directional ? kInf : 1.0;
    if constexpr ((F & kShadeTransmissiveShadows) != 0) {
        *s = geometry.transmittance(scene, shadow_ray, t_max);
        return *s != Vec3(0.0);
    }
    return !geometry.occluded(scene, shadow_ray, t_max);
}

// The Whitted colour along a ray (spec §7, §8), compiled once per variant F (ShadeFeature bits):
// `if constexpr` removes the code of every feature F lacks. With F = kShadeAll it is the generic
// renderer, which tests each feature per ray.
template <uint32_t F>
Vec3 trace(const RenderScene& scene, const RenderPlan& plan, const RenderSettings& settings,
           const Ray& ray, int depth, const Vec3& weight, RayCounters& counters, Rng* rng) {
    constexpr bool kStochastic = (F & kShadeStochastic) != 0;
    const GeometryQueries& geometry = *plan.geometry;
    Hit hit;
    if (!geometry.intersect(scene, ray, {0.0, kInf}, &hit)) return scene.background;
    // Texture coordinates only where a texture reads them.
    const SurfaceInteraction si = geometry.interaction(scene, ray, hit, (F & kShadeTextures) != 0);
    const Material& m = scene.materials[static_cast<size_t>(si.material)];
    const Vec3 d = glm::normalize(ray.d);

    // Two-sided rule (spec §5): shade with the normal facing the incoming ray.
    const double side = glm::dot(d, si.n_geometric) > 0 ? -1.0 : 1.0;
    const Vec3 n = side * si.n_shading;
    Vec3 t(1.0);
    if constexpr ((F & kShadeTextures) != 0)
        if (m.texture >= 0)
            t = eval_texture(*scene.textures[static_cast<size_t>(m.texture)], si.uv);
    const Vec3 kd = m.diffuse * t;

    Vec3 c = m.emissive + m.ambient * t * scene.ambient;
    const Vec3 r_v = d - 2.0 * glm::dot(d, n) * n;  // mirror direction, also for highlights

    for (const Light& scene_light : plan.lights) {
        Light moved;
        const Light& light = sampled_light<F>(scene_light, si.p, settings, rng, &moved);
        Vec3 intensity, l;
        double dist = 0.0;
        if (!light_at<F>(light, si.p, &intensity, &l, &dist)) continue;
        const double n_dot_l = glm::dot(n, l);
        if (!(n_dot_l > 0.0)) continue;
        Vec3 s(1.0);
        if constexpr ((F & kShadeShadows) != 0)
            if (settings.shadows &&
                !shadow_ray_passes<F>(scene, geometry, si, light, l, &s, counters))
                continue;
        if constexpr ((F & kShadeHighlights) != 0) {
            // At most 1 (both unit; rounding can exceed it, and x^huge would overflow).
            const double r_dot_l = std::min(glm::dot(r_v, l), 1.0);
            const double spec = r_dot_l > 0.0 ? std::pow(r_dot_l, m.specular_exponent) : 0.0;
            c += s * intensity * (kd * n_dot_l + m.specular * spec);
        } else {
            c += s * intensity * (kd * n_dot_l);
        }
    }

    if constexpr ((F & (kShadeReflection | kShadeRefraction)) != 0) {
        if (depth - 1 < 1) return c;
        auto traced = [&](const Vec3& w) {
            return w != Vec3(0.0) &&
                   (settings.cutoff == 0.0 || max_component(w) >= settings.cutoff);
        };
        if constexpr ((F & kShadeReflection) != 0) {
            // Reflection, weighted by K_S.
            const Vec3 w_refl = weight * m.specular;
            if (traced(w_refl)) {
                // Glossy reflection: the mirror direction spread by `roughness` (kept above
                // the surface).
                Vec3 dir = r_v;
                if constexpr (kStochastic) {
                    if (rng && settings.roughness > 0.0) {
                        const Vec3 g = glm::normalize(r_v + settings.roughness * rng->ball());
                        if (glm::dot(g, n) > 0.0) dir = g;
                    }
                }
                ++counters.reflected;
                c += m.specular * trace<F>(scene, plan, settings, spawn_ray(si, dir), depth - 1,
                                           w_refl, counters, rng);
            }
        }
        if constexpr ((F & kShadeRefraction) != 0) {
            // Refraction (Snell), weighted by T; none past the critical angle.
            const Vec3 w_refr = weight * m.transparent;
            if (traced(w_refr)) {
                const bool entering = glm::dot(d, si.n_geometric) < 0;
                const double eta = entering ? 1.0 / m.refractive_index : m.refractive_index;
                const double cos_i = std::clamp(-glm::dot(d, n), 0.0, 1.0);
                const double k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
                if (k >= 0.0) {
                    const Vec3 dir = eta * d + (eta * cos_i - std::sqrt(k)) * n;
                    ++counters.refracted;
                    c += m.transparent * trace<F>(scene, plan, settings, spawn_ray(si, dir),
                                                  depth - 1, w_refr, counters, rng);
                }
            }
        }
    }
    return c;
}

// The variants compiled: a combination that cannot occur maps to one that can (transparent
// shadows need shadows; spot lights are attenuated), and the rarely used stochastic features run
// the generic renderer, which keeps the number of instances (and the build time) down.
constexpr uint32_t canonical(uint32_t v) {
    if (v & kShadeStochastic) return kShadeAll;
    if (!(v & kShadeShadows)) v &= ~static_cast<uint32_t>(kShadeTransmissiveShadows);
    if (v & kShadeSpot) v |= kShadeAttenuation;
    return v;
}

template <uint32_t... I>
constexpr std::array<ShadingVariant, sizeof...(I)> trace_table(
    std::integer_sequence<uint32_t, I...>) {
    return {ShadingVariant{&trace<canonical(I)>}...};
}

// Every variant, indexed by its ShadeFeature bits.
constexpr auto kTraceVariants = trace_table(std::make_integer_sequence<uint32_t, kShadeAll + 1>{});

}  // namespace

const ShadingVariant& shading_variant(uint32_t shade_variant) {
    return kTraceVariants[shade_variant & kShadeAll];
}

Vec3 trace_ray(const RenderScene& scene, const RenderPlan& plan, const RenderSettings& settings,
               const Ray& ray, int depth, const Vec3& weight, RayCounters& counters, Rng* rng) {
    return plan.shading->trace(scene, plan, settings, ray, depth, weight, counters, rng);
}

}  // namespace rt
