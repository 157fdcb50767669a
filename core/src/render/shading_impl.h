// The shading code (private to the core): the templates of spec §7, §8 and §13.9, which
// shading.cpp compiles once per ShadeFeature combination to render, and inspect.cpp once more,
// the generic combination, with a recorder that writes down every ray and term
// (rt/render/inspect.h). The recorder is the template parameter Rec: NoRecord, which renders, has
// empty inline methods, so the render instances hold no trace of it. Every call passes values
// the shading computes anyway; a call whose arguments would cost work of their own belongs
// behind `if constexpr (Rec::kOn)`. The recorder never computes a term of its own.
#pragma once

#include <algorithm>
#include <cmath>

#include "rt/render/render.h"
#include "rt/render/shading.h"
#include "variants.h"

namespace rt::shading {

/// Why a ray of a hit was not traced (TreeRecorder::stop).
enum class StopReason { DepthLimit, Cutoff, Zero, TotalInternalReflection, LeftOut };

/// The kind of a secondary ray (TreeRecorder::secondary).
enum class SecondaryKind { Reflected, Refracted };

// The scalar light factor f_l of spec §13.9 (I_l of §7.2 divided by the colour) for the light
// kinds a variant has: without kAttenuation only directional lights (no distance or
// attenuation), without kSpot no cut-off or drop-off code. A sphere light is a point light at its
// centre. 0: the light contributes nothing at p. light_factor is the version with every kind.
template <bool kAttenuation, bool kSpot, class Rec = NoRecord>
[[gnu::always_inline]] inline double light_kinds(const Light& light, const Vec3& p, Vec3* to_light,
                                                 double* distance, Rec rec = {}) {
    if (!kAttenuation || light.kind == LightKind::Directional) {
        // light-dir-reversed: the direction of travel taken as L.
        *to_light = mistake(rec, Mistake::LightDirReversed) ? light.direction : -light.direction;
        *distance = kInf;
        return 1.0;
    }
    const Vec3 delta = light.position - p;
    const double dist = glm::length(delta);
    if (!(dist > 0.0) || !std::isfinite(dist)) return 0.0;
    const Vec3 l = delta / dist;
    const double denom =
        light.constant_atten + light.linear_atten * dist + light.quadratic_atten * dist * dist;
    rec.attenuation(dist, denom, l);
    const bool attenuated = !mistake(rec, Mistake::NoAttenuation);  // else the colour undivided
    if (attenuated && (!(denom > 0.0) || !std::isfinite(denom))) return 0.0;
    double factor = attenuated ? 1.0 / denom : 1.0;
    if (kSpot && light.kind == LightKind::Spot) {
        const double cos_a = glm::dot(light.direction, -l);
        // spot-cutoff-full-angle: the cut-off read as the cone's full angle, half of it compared.
        if (std::acos(std::clamp(cos_a, -1.0, 1.0)) >
            (mistake(rec, Mistake::SpotCutoffFullAngle) ? 0.5 : 1.0) * light.cutoff_rad) {
            rec.spot(cos_a, 0.0);
            return 0.0;
        }
        // The factor is 1 when p = 0, whatever the angle (spec §7.2).
        if (light.spot_exponent != 0.0 && !mistake(rec, Mistake::SpotNoDropoff)) {
            const double spot = std::pow(std::max(0.0, cos_a), light.spot_exponent);
            rec.spot(cos_a, spot);
            factor *= spot;
        } else {
            rec.spot(cos_a, 1.0);
        }
    }
    *to_light = l;
    *distance = dist;
    return factor;
}

template <uint32_t F, class Rec>
double light_at(const Light& light, const Vec3& p, Vec3* to_light, double* distance, Rec rec) {
    return light_kinds<(F & kShadeAttenuation) != 0, (F & kShadeSpot) != 0>(light, p, to_light,
                                                                            distance, rec);
}

// The light as one sample sees it: with soft shadows (F stochastic, a radius set), a point or
// spot light is a sphere of radius light_radius, sampled uniformly over the disc it shows the
// point p (the moved light is written to *moved); its emission rules stay. Sphere lights have a
// radius of their own.
template <uint32_t F>
[[gnu::always_inline]] inline const Light& sampled_light(const Light& light, const Vec3& p,
                                                         const RenderSettings& settings, Rng* rng,
                                                         Light* moved) {
    if constexpr ((F & kShadeStochastic) != 0) {
        if (rng && settings.light_radius > 0.0 &&
            (light.kind == LightKind::Point || light.kind == LightKind::Spot)) {
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

// A shadow ray from si: toward the point *target (the open segment to it), or without one along
// the unit direction `side` to infinity; `side` also picks the side of the surface it leaves
// from. False when it is blocked, else true with *s the transmittance of the surfaces it crosses
// (1 when F has no transparent shadows: then the first hit decides). Inlined: as a call it costs
// 1% of a render.
template <uint32_t F, class Rec>
[[gnu::always_inline]] inline bool segment_passes(const RenderScene& scene,
                                                  const GeometryQueries& geometry,
                                                  const SurfaceInteraction& si, const Vec3& side,
                                                  const Vec3* target, Vec3* s,
                                                  RayCounters& counters, Rec rec) {
    ++counters.shadow;
    const Vec3 o = mistake(rec, Mistake::NoOffset) ? si.p : offset_origin(si, side);
    // Toward a point the segment from the offset point to the point itself, t in (0, 1)
    // (shadow-past-light: the whole ray beyond it).
    const Ray shadow_ray{o, target ? *target - o : side};
    const double t_max = target && !mistake(rec, Mistake::ShadowPastLight) ? 1.0 : kInf;
    if constexpr ((F & kShadeTransmissiveShadows) != 0) {
        *s = mistake(rec, Mistake::OpaqueShadows)  // any hit blocks
                 ? Vec3(!geometry.occluded(scene, shadow_ray, t_max))
                 : geometry.transmittance(scene, shadow_ray, t_max);
        rec.shadow_ray(scene, geometry, si, shadow_ray, t_max, *s);
        return *s != Vec3(0.0);
    }
    const bool passes = !geometry.occluded(scene, shadow_ray, t_max);
    rec.shadow_ray(scene, geometry, si, shadow_ray, t_max, Vec3(passes));
    return passes;
}

// The shadow ray from si toward the light (unit direction l; spec §7.2).
template <uint32_t F, class Rec>
[[gnu::always_inline]] inline bool shadow_ray_passes(const RenderScene& scene,
                                                     const GeometryQueries& geometry,
                                                     const SurfaceInteraction& si,
                                                     const Light& light, const Vec3& l, Vec3* s,
                                                     RayCounters& counters, Rec rec) {
    const bool directional = light.kind == LightKind::Directional;
    return segment_passes<F>(scene, geometry, si, l, directional ? nullptr : &light.position, s,
                             counters, rec);
}

// The shadow factor of a sphere light (spec §13.9): the mean transmittance of the segments from
// si to points c + radius * w(xi) spread by area over the whole sphere. Without rng (one sample
// per pixel) the plan's strata centres, the same for every point; with one, a progressive pass
// (no centre-first sampling) takes one uniform point, a supersampled render the strata jittered.
template <uint32_t F, class Rec>
Vec3 sphere_shadow(const RenderScene& scene, const RenderPlan& plan, const RenderSettings& settings,
                   const SurfaceInteraction& si, const Light& light, Rng* rng,
                   RayCounters& counters, Rec rec) {
    auto through = [&](const Vec3& w) {
        const Vec3 y = light.position + light.radius * w;
        Vec3 s(1.0);
        return segment_passes<F>(scene, *plan.geometry, si, y - si.p, &y, &s, counters, rec)
                   ? s
                   : Vec3(0.0);
    };
    Vec3 sum(0.0);
    if (!rng) {
        for (const Vec3& w : plan.sphere_points) sum += through(w);
        return sum / static_cast<double>(plan.sphere_points.size());
    }
    auto jitter = [&] {
        const double a = rng->uniform();
        return Vec2(a, rng->uniform());
    };
    if (!settings.centre_first_sample) return through(uniform_sphere(jitter()));
    const int n = plan.light_samples;
    const int m = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
    for (int k = 0; k < n; ++k) sum += through(uniform_sphere(stratum_point(k, m, jitter())));
    return sum / static_cast<double>(n);
}

// What the light terms of one hit share: the point, the normal facing the ray, the mirror
// direction (also for highlights) and the material's colours with the texel applied (spec §7.3,
// §13.9: t multiplies K_A and K_D, in V3 K_S too).
struct ShadePoint {
    const SurfaceInteraction& si;
    Vec3 n, r_v;
    Vec3 ka, kd, ks;
    double exponent;
};

// spec_l of spec §7.1 toward the unit direction l.
[[gnu::always_inline]] inline double highlight(const ShadePoint& sp, const Vec3& l) {
    // At most 1 (both unit; rounding can exceed it, and x^huge would overflow).
    const double r_dot_l = std::min(glm::dot(sp.r_v, l), 1.0);
    return r_dot_l > 0.0 ? std::pow(r_dot_l, sp.exponent) : 0.0;
}

// spec_l as the render computes it: highlight(), or with a mistake 0 (no-specular) or Blinn's
// (N·H)^e, H = normalize(L + V), V = -d = 2 (R_v·N) N - R_v (blinn).
template <class Rec>
[[gnu::always_inline]] inline double highlight(const ShadePoint& sp, const Vec3& l, Rec rec) {
    if (mistake(rec, Mistake::NoSpecular)) return 0.0;
    if (mistake(rec, Mistake::Blinn)) {
        const Vec3 v = 2.0 * glm::dot(sp.r_v, sp.n) * sp.n - sp.r_v;
        const double n_dot_h = std::min(glm::dot(sp.n, glm::normalize(l + v)), 1.0);
        return n_dot_h > 0.0 ? std::pow(n_dot_h, sp.exponent) : 0.0;
    }
    return highlight(sp, l);
}

// A secondary ray from si along dir (spec §7.5; no-offset: from P itself).
template <class Rec>
[[gnu::always_inline]] inline Ray spawn_ray(const SurfaceInteraction& si, const Vec3& dir,
                                            Rec rec) {
    return mistake(rec, Mistake::NoOffset) ? Ray{si.p, dir} : rt::spawn_ray(si, dir);
}

// A light with one colour, its diffuse and specular (V0, V1; V3 lights without ambient whose
// colours agree): S_l ⊙ I_l ⊙ (K_D (N.L) + K_S spec_l) of spec §7.1, added to c.
template <uint32_t F, class Rec>
[[gnu::always_inline]] inline void one_colour_light(const RenderScene& scene,
                                                    const RenderPlan& plan,
                                                    const RenderSettings& settings,
                                                    const ShadePoint& sp, const Light& light,
                                                    RayCounters& counters, Vec3& c, Rec rec) {
    if (light.diffuse == Vec3(0.0)) {  // lights nothing (not 0 * inf = NaN either)
        rec.skip("the light's colour is 0");
        return;
    }
    Vec3 l;
    double dist = 0.0;
    const double factor = light_at<F>(light, sp.si.p, &l, &dist, rec);
    rec.factor(factor);
    if (!(factor > 0.0)) return;
    const Vec3 intensity = light.diffuse * factor;
    const double n_dot_l = glm::dot(sp.n, l);
    rec.facing(l, n_dot_l);
    if (!(n_dot_l > 0.0) && !mistake(rec, Mistake::NoDiffuseClamp)) return;
    Vec3 s(1.0);
    if constexpr ((F & kShadeShadows) != 0)
        if (settings.shadows && !mistake(rec, Mistake::NoShadows) &&
            !shadow_ray_passes<F>(scene, *plan.geometry, sp.si, light, l, &s, counters, rec)) {
            rec.shadow(Vec3(0.0));
            if constexpr (Rec::kOn)  // the terms S_l = 0 removes, as the lit case records them
                rec.direct(
                    sp, l, intensity * sp.kd * n_dot_l,
                    (F & kShadeHighlights) != 0 ? intensity * sp.ks * highlight(sp, l) : Vec3(0.0),
                    Vec3(0.0));
            return;
        }
    rec.shadow(s);
    if constexpr ((F & kShadeHighlights) != 0) {
        const double h = highlight(sp, l, rec);
        const Vec3 lit = s * intensity * (sp.kd * n_dot_l + sp.ks * h);
        rec.direct(sp, l, intensity * sp.kd * n_dot_l, intensity * sp.ks * h, lit);
        c += lit;
    } else {
        const Vec3 lit = s * intensity * (sp.kd * n_dot_l);
        rec.direct(sp, l, intensity * sp.kd * n_dot_l, Vec3(0.0), lit);
        c += lit;
    }
}

// The ShadeFeature bits the light terms read: the V3 light code is compiled once per combination
// of these (not once per variant of trace) and called, which keeps the build time down.
constexpr uint32_t kLightBits = kShadeShadows | kShadeTransmissiveShadows | kShadeHighlights |
                                kShadeSpot | kShadeAttenuation | kShadeV3Lights;

// For the recorder only: the diffuse and specular terms of a V3 light in shadow (S_l = 0), as
// three_colour_light() computes them when lit.
template <uint32_t F, class Rec>
void in_shadow(Rec rec, const ShadePoint& sp, const Light& light, const Vec3& l, double f,
               double n_dot_l) {
    const bool highlit = (F & kShadeHighlights) != 0 && sp.ks != Vec3(0.0);
    rec.direct(sp, l, f * (sp.kd * light.diffuse * n_dot_l),
               highlit ? f * (sp.ks * light.specular * highlight(sp, l)) : Vec3(0.0), Vec3(0.0));
}

// A V3 light (spec §13.9), added to c: the ambient term (attenuated and spot-limited, never
// shadowed, whatever N.L) and, facing the light, S_l f_l (K_D ⊙ D_l (N.L) + K_S ⊙ S'_l spec_l).
template <uint32_t F, class Rec>
[[gnu::noinline]] void three_colour_light(const RenderScene& scene, const RenderPlan& plan,
                                          const RenderSettings& settings, const ShadePoint& sp,
                                          const Light& light, Rng* rng, RayCounters& counters,
                                          Vec3& c, Rec rec) {
    Vec3 l;
    double dist = 0.0;
    const double f = light_at<F>(light, sp.si.p, &l, &dist, rec);
    rec.factor(f);
    if (!(f > 0.0)) return;  // nothing here, the ambient term included
    if (light.ambient != Vec3(0.0) && !mistake(rec, Mistake::NoAmbient)) {
        const Vec3 ambient = sp.ka * light.ambient * f;
        rec.light_ambient(ambient);
        c += ambient;
    }
    const double n_dot_l = glm::dot(sp.n, l);
    rec.facing(l, n_dot_l);
    if ((!(n_dot_l > 0.0) && !mistake(rec, Mistake::NoDiffuseClamp)) ||
        (light.diffuse == Vec3(0.0) && light.specular == Vec3(0.0))) {
        if (n_dot_l > 0.0) rec.skip("diffuse and specular colours are 0");
        return;
    }
    Vec3 s(1.0);
    if constexpr ((F & kShadeShadows) != 0) {
        if (settings.shadows && !mistake(rec, Mistake::NoShadows)) {
            if (light.kind == LightKind::Sphere && light.radius > 0.0 &&
                (rng || !plan.sphere_points.empty()))
                s = sphere_shadow<F & kShadeTransmissiveShadows>(scene, plan, settings, sp.si,
                                                                 light, rng, counters, rec);
            else if (!shadow_ray_passes<F>(scene, *plan.geometry, sp.si, light, l, &s, counters,
                                           rec)) {
                rec.shadow(Vec3(0.0));
                if constexpr (Rec::kOn) in_shadow<F>(rec, sp, light, l, f, n_dot_l);
                return;
            }
            rec.shadow(s);
            if constexpr (Rec::kOn)
                if (s == Vec3(0.0)) in_shadow<F>(rec, sp, light, l, f, n_dot_l);
            if (s == Vec3(0.0)) return;
        }
    }
    const Vec3 diffuse = sp.kd * light.diffuse * n_dot_l;
    Vec3 lit = diffuse, specular(0.0);
    if constexpr ((F & kShadeHighlights) != 0)
        if (sp.ks != Vec3(0.0)) {
            specular = sp.ks * light.specular * highlight(sp, l, rec);
            lit += specular;
        }
    const Vec3 value = s * f * lit;
    rec.direct(sp, l, f * diffuse, f * specular, value);
    c += value;
}

template <uint32_t F, class Rec>
Vec3 trace(const RenderScene& scene, const RenderPlan& plan, const RenderSettings& settings,
           const Ray& ray, int depth, const Vec3& weight, RayCounters& counters, Rng* rng, Rec rec);

// The reflected and refracted rays of a hit (spec §7.4, §8), added to c.
template <uint32_t F, class Rec>
void secondary_rays(const RenderScene& scene, const RenderPlan& plan,
                    const RenderSettings& settings, const ShadePoint& sp, const Material& m,
                    const Vec3& d, int depth, const Vec3& weight, RayCounters& counters, Rng* rng,
                    Vec3& c, Rec rec) {
    constexpr bool kStochastic = (F & kShadeStochastic) != 0;
    const SurfaceInteraction& si = sp.si;
    const Vec3& n = sp.n;
    auto traced = [&](const Vec3& w, SecondaryKind kind) {
        if (w != Vec3(0.0) && (settings.cutoff == 0.0 || mistake(rec, Mistake::NoCutoff) ||
                               max_component(w) >= settings.cutoff))
            return true;
        rec.stop(kind, w == Vec3(0.0) ? StopReason::Zero : StopReason::Cutoff, w);
        return false;
    };
    if constexpr ((F & kShadeReflection) != 0) {
        // Reflection, weighted by K_S (not textured).
        const Vec3 w_refl = weight * m.specular;
        if (!mistake(rec, Mistake::NoReflection) && traced(w_refl, SecondaryKind::Reflected)) {
            // Glossy reflection: the mirror direction spread by `roughness` (kept above the
            // surface).
            Vec3 dir = sp.r_v;
            if constexpr (kStochastic) {
                if (rng && settings.roughness > 0.0) {
                    const Vec3 g = glm::normalize(sp.r_v + settings.roughness * rng->ball());
                    if (glm::dot(g, n) > 0.0) dir = g;
                }
            }
            ++counters.reflected;
            const Ray r = spawn_ray(si, dir, rec);
            const Rec child = rec.secondary(SecondaryKind::Reflected, r, depth - 1, w_refl);
            const Vec3 v = m.specular * trace<F>(scene, plan, settings, r, depth - 1, w_refl,
                                                 counters, rng, child);
            rec.secondary_value(SecondaryKind::Reflected, m.specular, v);
            c += v;
        }
    } else {
        rec.stop(SecondaryKind::Reflected, StopReason::LeftOut, weight * m.specular);
    }
    if constexpr ((F & kShadeRefraction) != 0) {
        // Refraction (Snell), weighted by T; none past the critical angle.
        const Vec3 w_refr = weight * m.transparent;
        if (!mistake(rec, Mistake::NoRefraction) && traced(w_refr, SecondaryKind::Refracted)) {
            const bool entering = glm::dot(d, si.n_geometric) < 0;
            const bool inverted = mistake(rec, Mistake::IorInverted);
            const double eta = entering != inverted ? 1.0 / m.refractive_index : m.refractive_index;
            const double cos_i = std::clamp(-glm::dot(d, n), 0.0, 1.0);
            const double k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
            if (k >= 0.0) {
                const Vec3 dir = eta * d + (eta * cos_i - std::sqrt(k)) * n;
                ++counters.refracted;
                const Ray r = spawn_ray(si, dir, rec);
                const Rec child =
                    rec.secondary(SecondaryKind::Refracted, r, depth - 1, w_refr, eta, cos_i);
                const Vec3 v = m.transparent * trace<F>(scene, plan, settings, r, depth - 1, w_refr,
                                                        counters, rng, child);
                rec.secondary_value(SecondaryKind::Refracted, m.transparent, v);
                c += v;
            } else {
                rec.stop(SecondaryKind::Refracted, StopReason::TotalInternalReflection, w_refr, eta,
                         cos_i);
            }
        }
    } else {
        rec.stop(SecondaryKind::Refracted, StopReason::LeftOut, weight * m.transparent);
    }
}

// The Whitted colour along a ray (spec §7, §8, §13.9), compiled once per variant F (ShadeFeature
// bits): `if constexpr` removes the code of every feature F lacks. With F = kShadeAll it is the
// generic renderer, which tests each feature per ray.
template <uint32_t F, class Rec>
Vec3 trace(const RenderScene& scene, const RenderPlan& plan, const RenderSettings& settings,
           const Ray& ray, int depth, const Vec3& weight, RayCounters& counters, Rng* rng,
           Rec rec) {
    const GeometryQueries& geometry = *plan.geometry;
    Hit hit;
    if (!geometry.intersect(scene, ray, {0.0, kInf}, &hit)) {
        rec.miss(scene.background);
        return scene.background;
    }
    // Texture coordinates only where a texture reads them.
    const SurfaceInteraction si = geometry.interaction(scene, ray, hit, (F & kShadeTextures) != 0);
    const Material& m = scene.materials[static_cast<size_t>(si.material)];
    const Vec3 d = glm::normalize(ray.d);

    // Two-sided rule (spec §5): shade with the normal facing the incoming ray.
    const double side =
        glm::dot(d, si.n_geometric) > 0 && !mistake(rec, Mistake::OneSided) ? -1.0 : 1.0;
    const Vec3 n = side * si.n_shading;
    Vec3 t(1.0), ke = m.emissive, ks = m.specular;
    if constexpr ((F & kShadeTextures) != 0) {
        if (m.texture >= 0) {
            t = eval_texture(*scene.textures[static_cast<size_t>(m.texture)], si.uv);
            // texture-v-flipped: y = v' H_t - 0.5, the lookup at 1 - v (the same, as it wraps).
            if (mistake(rec, Mistake::TextureVFlipped))
                t = eval_texture(*scene.textures[static_cast<size_t>(m.texture)],
                                 Vec2(si.uv.x, 1.0 - si.uv.y));
            if (scene.texture_all_terms && !mistake(rec, Mistake::TextureDiffuseOnly))
                ke *= t, ks *= t;  // V3 (spec §13.9)
        }
    }
    if (mistake(rec, Mistake::NoEmissive)) ke = Vec3(0.0);
    ShadePoint sp{
        si, n, d - 2.0 * glm::dot(d, n) * n, m.ambient * t, m.diffuse * t, ks, m.specular_exponent};
    if (mistake(rec, Mistake::TextureDiffuseOnly)) sp.ka = m.ambient;

    Vec3 c = ke + sp.ka * scene.ambient;
    if (mistake(rec, Mistake::NoAmbient)) c = ke;
    rec.hit(scene, ray, hit, sp, side < 0, t, ke, sp.ka * scene.ambient);
    for (const Light& scene_light : plan.lights) {
        Light moved;
        const Light& light = sampled_light<F>(scene_light, si.p, settings, rng, &moved);
        const Rec lrec = rec.light(static_cast<int>(&scene_light - plan.lights.data()), light);
        if constexpr ((F & kShadeV3Lights) != 0) {
            if (!light.one_colour()) {
                three_colour_light<F & kLightBits>(scene, plan, settings, sp, light, rng, counters,
                                                   c, lrec);
                continue;
            }
        }
        one_colour_light<F>(scene, plan, settings, sp, light, counters, c, lrec);
    }
    if constexpr ((F & (kShadeReflection | kShadeRefraction)) != 0) {
        if (depth - 1 >= (mistake(rec, Mistake::DepthOffByOne) ? 0 : 1))
            secondary_rays<F>(scene, plan, settings, sp, m, d, depth, weight, counters, rng, c,
                              rec);
        else
            rec.depth_limit(weight * m.specular, weight * m.transparent);
    } else {
        rec.stop(SecondaryKind::Reflected, StopReason::LeftOut, weight * m.specular);
        rec.stop(SecondaryKind::Refracted, StopReason::LeftOut, weight * m.transparent);
    }
    rec.result(c);
    return c;
}

// The variants compiled: a combination that cannot occur maps to one that can (transparent
// shadows need shadows; spot lights are attenuated), and the rarely used stochastic features run
// the generic renderer, which keeps the number of instances (and the build time) down. V3 lights
// keep textures, highlights and every light kind (runtime tests, cheap beside their shadow
// rays): 12 more instances instead of 145 (shading.cpp: 7.1 s of compile time instead of 6.3 s
// without V3 lights; 16.5 s with every combination compiled).
constexpr uint32_t kShadeV3Forced =
    kShadeTextures | kShadeHighlights | kShadeSpot | kShadeAttenuation;
constexpr uint32_t canonical(uint32_t v) {
    if (v & kShadeStochastic) return kShadeAll;
    if (!(v & kShadeShadows)) v &= ~static_cast<uint32_t>(kShadeTransmissiveShadows);
    if (v & kShadeSpot) v |= kShadeAttenuation;
    if (v & kShadeV3Lights) v |= kShadeV3Forced;
    return v;
}

}  // namespace rt::shading
