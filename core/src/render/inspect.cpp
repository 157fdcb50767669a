// The ray tree of a pixel sample: the shading code of shading_impl.h compiled once more, with a
// recorder that writes down each ray, hit and term as the shading computes it.
#include "rt/render/inspect.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "camera_sample.h"
#include "rt/image/image.h"
#include "rt/util/enum_names.h"
#include "shading_impl.h"
#include "variants.h"

namespace rt {

namespace {

using shading::SecondaryKind;
using shading::StopReason;

// What the recorders of one tree share.
struct TreeContext {
    PixelTree tree;
    std::vector<int> light_ids;  // plan light -> index into RenderScene::lights
};

const char* stop_text(StopReason r) {
    static constexpr const char* kText[] = {"depth limit", "path weight below the cutoff",
                                            "weight 0", "total internal reflection",
                                            "left out by the plan"};  // StopReason's order
    return enum_name(r, kText);
}

const char* kind_text(SecondaryKind k) {
    return k == SecondaryKind::Reflected ? "reflected" : "refracted";
}

// The recorder: the shading code calls it with the values it computes (a render calls NoRecord's
// empty methods instead, variants.h). `node` is the ray being shaded, `light` the light term being
// evaluated (-1: none). A ray traced past the tree's limits has node -1: it records nothing but its
// count and, the first of its subtree (`top`), its colour, into the entry `entry` of the
// not_recorded list of the recorded ray `owner` above it.
struct TreeRecorder {
    static constexpr bool kOn = true;
    TreeContext* ctx = nullptr;
    int node = 0;
    int light_term = -1;
    int owner = -1;
    int entry = -1;
    bool top = false;

    bool on() const { return node >= 0; }
    InspectRay& ray() const { return ctx->tree.rays[static_cast<size_t>(node)]; }
    InspectLight& term() const { return ray().lights[static_cast<size_t>(light_term)]; }
    bool budget_left() const { return ctx->tree.records < ctx->tree.max_records; }
    InspectRay::NotRecorded& skipped() const {
        return ctx->tree.rays[static_cast<size_t>(owner)].not_recorded[static_cast<size_t>(entry)];
    }

    void miss(const Vec3& background) const {
        if (!on()) return;
        ray().hit = false;
        ray().color = background;
    }

    void hit(const RenderScene& scene, const Ray& r, const Hit& h, const shading::ShadePoint& sp,
             bool leaving, const Vec3& texel, const Vec3& emissive, const Vec3& ambient) const {
        if (!on()) return;
        InspectRay& x = ray();
        x.hit = true;
        x.t = h.t;
        x.distance = h.t * glm::length(r.d);
        x.point = sp.si.p;
        const Instance& inst = scene.instances[static_cast<size_t>(h.instance)];
        const Primitive& p = scene.sets[static_cast<size_t>(inst.set)].prims[h.prim];
        x.prim = {h.instance, inst.set, h.prim, p.kind, p.csg >= 0};
        x.material = sp.si.material;
        const Material& m = scene.materials[static_cast<size_t>(sp.si.material)];
        x.n_geometric = sp.si.n_geometric;
        x.n_shading = sp.si.n_shading;
        x.n = sp.n;
        x.entering = !leaving;
        x.uv = sp.si.uv;
        x.textured = m.texture >= 0;
        x.texel = texel;
        x.emissive = emissive;
        x.k_a = sp.ka;
        x.k_d = sp.kd;
        x.k_s = sp.ks;
        x.exponent = sp.exponent;
        x.scene_ambient = scene.ambient;
        x.ambient = ambient;
        x.k_reflect = m.specular;
        x.k_transmit = m.transparent;
    }

    TreeRecorder light(int plan_index, const Light& l) const {
        if (!on()) return *this;
        ++ctx->tree.records;  // a recorded ray keeps every light term (its sum must hold)
        InspectLight t;
        static_cast<Light&>(t) = l;
        t.light = ctx->light_ids[static_cast<size_t>(plan_index)];
        ray().lights.push_back(std::move(t));
        TreeRecorder r = *this;
        r.light_term = static_cast<int>(ray().lights.size()) - 1;
        return r;
    }

    void attenuation(double dist, double denom, const Vec3& l) const {
        if (!on()) return;
        InspectLight& t = term();
        t.attenuated = true;
        t.distance = dist;
        t.denominator = denom;
        t.to_light = l;
        if (!(denom > 0.0) || !std::isfinite(denom))
            t.note = "the attenuation's denominator is not positive and finite";
    }

    void spot(double cos_a, double factor) const {
        if (!on()) return;
        InspectLight& t = term();
        t.spot = true;
        t.cos_angle = cos_a;
        t.spot_factor = factor;
        if (factor == 0.0 && t.note.empty()) t.note = "outside the spot's cone";
    }

    void factor(double f) const {
        if (!on()) return;
        InspectLight& t = term();
        t.factor = f;
        if (!(f > 0.0) && t.note.empty())
            t.note = t.attenuated ? "the light factor is 0" : "the point is at the light";
    }

    void facing(const Vec3& l, double n_dot_l) const {
        if (!on()) return;
        InspectLight& t = term();
        t.facing_known = true;
        t.to_light = l;
        t.n_dot_l = n_dot_l;
        if (!(n_dot_l > 0.0) && t.note.empty()) t.note = "the surface faces away (N.L <= 0)";
    }

    void skip(const char* why) const {
        if (on()) term().note = why;
    }

    void light_ambient(const Vec3& a) const {
        if (on()) term().ambient_term = a;
    }

    void shadow_ray(const RenderScene& scene, const GeometryQueries& geometry,
                    const SurfaceInteraction& si, const Ray& r, double t_max, const Vec3& s) const {
        if (!on()) return;
        InspectLight& t = term();
        ++t.shadow_ray_count;
        if (t.shadow_rays.size() >= InspectLight::kMaxShadowRays || !budget_left()) return;
        ++ctx->tree.records;
        // The origin as offset_origin() moved it off the hit point (its difference from the
        // point: the offset, exact for points this close).
        InspectShadowRay sr{r, si.p, r.o - si.p, t_max, s, {}};
        // The surfaces on the segment, nearest first, by the renderer's own nearest-hit query
        // (what the transmittance query multiplied, or the first that blocked it).
        double lo = 0.0;
        for (int k = 0; k < 64 && budget_left(); ++k) {
            Hit h;
            if (!geometry.intersect(scene, r, {lo, t_max}, &h)) break;
            const SurfaceInteraction met = geometry.interaction(scene, r, h, false);
            const Instance& inst = scene.instances[static_cast<size_t>(h.instance)];
            const Primitive& p = scene.sets[static_cast<size_t>(inst.set)].prims[h.prim];
            InspectOccluder o;
            o.prim = {h.instance, inst.set, h.prim, p.kind, p.csg >= 0};
            o.t = h.t;
            o.distance = h.t * glm::length(r.d);
            o.material = met.material;
            o.transparent = scene.materials[static_cast<size_t>(met.material)].transparent;
            sr.occluders.push_back(o);
            ++ctx->tree.records;
            if (o.transparent == Vec3(0.0) || !(h.t > lo)) break;
            lo = h.t;
        }
        t.shadow_rays.push_back(std::move(sr));
    }

    void shadow(const Vec3& s) const {
        if (!on()) return;
        InspectLight& t = term();
        t.shadow_tested = true;
        t.shadow = s;
        if (s == Vec3(0.0) && t.note.empty()) t.note = "in shadow";
    }

    void direct(const shading::ShadePoint& sp, const Vec3& l, const Vec3& diffuse,
                const Vec3& specular, const Vec3& value) const {
        if (!on()) return;
        InspectLight& t = term();
        t.r_dot_l = std::min(glm::dot(sp.r_v, l), 1.0);
        t.highlight = shading::highlight(sp, l);
        t.terms_known = true;
        t.diffuse_term = diffuse;
        t.specular_term = specular;
        t.value = value;
    }

    TreeRecorder secondary(SecondaryKind kind, const Ray& r, int depth, const Vec3& weight,
                           double eta = 1.0, double cos_i = 1.0) const {
        const auto kind_of = [&] {
            return kind == SecondaryKind::Reflected ? InspectRay::Kind::Reflected
                                                    : InspectRay::Kind::Refracted;
        };
        PixelTree& tree = ctx->tree;
        if (!on()) {  // below a ray not recorded: counted with it
            ++tree.rays_not_recorded;
            ++skipped().rays;
            return {ctx, -1, -1, owner, entry, false};
        }
        if (tree.rays.size() >= tree.max_rays || !budget_left()) {
            ++tree.rays_not_recorded;
            ray().not_recorded.push_back({kind_of(), depth, weight, Vec3(0.0), 1});
            return {ctx, -1, -1, node, static_cast<int>(ray().not_recorded.size()) - 1, true};
        }
        InspectRay child;
        child.kind = kind_of();
        child.depth = depth;
        child.ray = r;
        child.weight = weight;
        child.parent = node;
        child.eta = eta;
        child.cos_incident = cos_i;
        tree.rays.push_back(std::move(child));
        const int index = static_cast<int>(tree.rays.size()) - 1;
        ray().children.push_back(index);
        return {ctx, index, -1, -1, -1, false};
    }

    void secondary_value(SecondaryKind kind, const Vec3& k, const Vec3& v) const {
        if (!on()) return;
        InspectRay& x = ray();
        (kind == SecondaryKind::Reflected ? x.k_reflect : x.k_transmit) = k;
        (kind == SecondaryKind::Reflected ? x.reflected : x.refracted) = v;
    }

    void stop(SecondaryKind kind, StopReason why, const Vec3& weight, double eta = 1.0,
              double cos_i = 1.0) const {
        if (!on() || weight == Vec3(0.0))
            return;  // the material has no such term: nothing to explain
        std::string text = stop_text(why);
        if (why == StopReason::TotalInternalReflection) {
            // Snell: sin t = eta sin i, past 1 here.
            const double sin_t = eta * std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
            char buf[96];
            std::snprintf(buf, sizeof buf, " (eta %.6g: sin of the refracted angle would be %.6g)",
                          eta, sin_t);
            text += buf;
        }
        ray().stops.push_back({kind_text(kind), text, weight});
    }

    void depth_limit(const Vec3& w_reflect, const Vec3& w_refract) const {
        stop(SecondaryKind::Reflected, StopReason::DepthLimit, w_reflect);
        stop(SecondaryKind::Refracted, StopReason::DepthLimit, w_refract);
    }

    void result(const Vec3& c) const {
        if (on())
            ray().color = c;
        else if (top)
            skipped().color = c;
    }
};

// The camera's inputs for pixel (x, y) at the sample's position, from the renderer's camera
// (plan.cpp: make_camera).
InspectCamera camera_inputs(const RenderScene& scene, const RenderPlan& plan,
                            const RenderSettings& settings, int x, int y, const Vec2& position) {
    const Camera& cam = plan.camera;
    InspectCamera ic;
    ic.from_file = scene.camera.has_value();
    ic.half_height_angle_rad =
        scene.camera ? scene.camera->half_height_angle_rad
                     : default_camera(scene.world_bounds, settings.width, settings.height)
                           .half_height_angle_rad;
    ic.tan_h = cam.tan_h;
    ic.tan_w = cam.tan_w;
    ic.width = cam.width;
    ic.height = cam.height;
    ic.position = cam.position;
    ic.forward = cam.forward;
    ic.right = cam.right;
    ic.up = cam.up;
    ic.image_point = cam.image_point(x, y, position.x, position.y);
    return ic;
}

// Why each light that traced no shadow ray traced none: what ended its term first, or the
// settings.
void explain_missing_shadow_rays(const RenderSettings& settings, PixelTree* tree) {
    for (InspectRay& r : tree->rays)
        for (InspectLight& l : r.lights) {
            if (l.shadow_ray_count > 0) continue;
            if (l.facing_known && !(l.n_dot_l > 0.0))
                l.no_shadow_ray =
                    "the surface faces away from the light (N.L <= 0): it gets no diffuse or "
                    "specular term, so there is nothing to shadow";
            else if (!l.note.empty())
                l.no_shadow_ray = l.note + ": nothing to shadow";
            else
                l.no_shadow_ray =
                    settings.shadows ? "no shadow ray traced" : "shadows are off (--no-shadows)";
        }
}

}  // namespace

PixelTree inspect_pixel(const RenderScene& scene, const RenderPlan& plan,
                        const RenderSettings& settings, int x, int y, uint32_t sample, int spp,
                        const InspectLimits& limits) {
    if (x < 0 || y < 0 || x >= settings.width || y >= settings.height)
        throw std::invalid_argument("pixel " + std::to_string(x) + "," + std::to_string(y) +
                                    " is outside the image (columns 0.." +
                                    std::to_string(settings.width - 1) + ", rows 0.." +
                                    std::to_string(settings.height - 1) + ")");
    if (spp < 1 || sample >= static_cast<uint32_t>(spp))
        throw std::invalid_argument("sample " + std::to_string(sample) + " is not one of the " +
                                    std::to_string(spp) + " samples per pixel (0.." +
                                    std::to_string(spp - 1) + ")");
    check_depth(settings.max_depth);
    TreeContext ctx;
    // The plan keeps the scene's lights in order, less the ones that light nothing: each plan
    // light is the next scene light equal to it (two equal lights keep their own numbers).
    size_t next = 0;
    for (const Light& l : plan.lights) {
        int id = -1;
        for (size_t k = next; k < scene.lights.size() && id < 0; ++k)
            if (scene.lights[k] == l) id = static_cast<int>(k), next = k + 1;
        ctx.light_ids.push_back(id);
    }
    PixelTree& tree = ctx.tree;
    tree.x = x;
    tree.y = y;
    tree.sample = sample;
    tree.samples = static_cast<uint32_t>(spp);
    tree.max_rays = std::max<size_t>(limits.rays, 1);  // the camera ray at least
    tree.max_records = limits.records;
    // The sample as render_samples() places it (render.cpp, render_pixel): the same random
    // numbers, drawn in the same order.
    const size_t pixel = static_cast<size_t>(y) * static_cast<size_t>(settings.width) + x;
    Rng rng(settings.seed, pixel, sample);
    const bool stochastic = settings.stochastic();
    const int stratum = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(spp))));
    tree.position = sample_position(settings, stochastic, static_cast<int>(sample), spp, 0, stratum,
                                    progressive_shifts(settings, pixel), rng);
    const Ray ray = camera_ray(plan, settings, x, y, tree.position, rng);
    tree.random = stochastic || spp > 1 || !settings.centre_first_sample;
    tree.lens = ray.o;
    InspectRay root;
    root.kind = InspectRay::Kind::Camera;
    root.depth = settings.max_depth;
    root.ray = ray;
    tree.rays.push_back(std::move(root));
    RayCounters counters;
    // The generic shading code (every feature tested per ray), which gives whatever plan's
    // image bit for bit: one recording instance instead of one per variant (test_inspect.cpp
    // compares the trees with both plans' images).
    tree.color = shading::trace<kShadeAll, TreeRecorder>(
        scene, plan, settings, ray, settings.max_depth, Vec3(1.0), counters,
        tree.random ? &rng : nullptr, {&ctx, 0, -1, -1, -1, false});
    tree.pixel = render_pixel_value(scene, plan, settings, x, y, spp);
    // The 8 bits the image writer stores for that value (spec §9).
    for (int k = 0; k < 3; ++k) tree.output.bytes[k] = to_byte(tree.pixel[k]);
    tree.camera = camera_inputs(scene, plan, settings, x, y, tree.position);
    explain_missing_shadow_rays(settings, &tree);
    return std::move(ctx.tree);
}

PixelTree filter_tree(const PixelTree& tree, const InspectFilter& filter) {
    PixelTree out = tree;
    out.filter_depth = std::max(filter.depth, 0);
    out.filter_light = std::max(filter.light, -1);
    if (out.filter_light >= 0)
        for (InspectRay& r : out.rays) {
            const auto other = [&](const InspectLight& l) { return l.light != out.filter_light; };
            const size_t before = r.lights.size();
            r.lights.erase(std::remove_if(r.lights.begin(), r.lights.end(), other), r.lights.end());
            r.lights_left_out += before - r.lights.size();
        }
    if (out.filter_depth == 0 || tree.rays.empty()) return out;
    // Each ray's level (the camera ray's is 1, as --depth counts) and the rays of its subtree,
    // traced past the limits included: rays come before their children.
    const size_t n = tree.rays.size();
    std::vector<int> level(n, 1);
    for (size_t i = 1; i < n; ++i) level[i] = level[static_cast<size_t>(tree.rays[i].parent)] + 1;
    std::vector<size_t> size(n, 1);
    for (size_t i = n; i-- > 0;) {
        for (const InspectRay::NotRecorded& nr : tree.rays[i].not_recorded) size[i] += nr.rays;
        for (int c : tree.rays[i].children) size[i] += size[static_cast<size_t>(c)];
    }
    std::vector<int> index(n, -1);
    std::vector<InspectRay> rays = std::move(out.rays);  // with the light filter applied
    out.rays.clear();
    for (size_t i = 0; i < n; ++i) {
        if (level[i] > out.filter_depth) continue;
        InspectRay r = std::move(rays[i]);
        index[i] = static_cast<int>(out.rays.size());
        if (r.parent >= 0) r.parent = index[static_cast<size_t>(r.parent)];
        std::vector<int> kept;
        for (int c : r.children) {
            const InspectRay& child = tree.rays[static_cast<size_t>(c)];
            if (level[i] < out.filter_depth) {
                kept.push_back(c);  // renumbered below, once its index is known
                continue;
            }
            r.left_out.push_back(
                {child.kind, child.depth, child.weight, child.color, size[static_cast<size_t>(c)]});
            out.rays_left_out += size[static_cast<size_t>(c)];
        }
        r.children = std::move(kept);
        out.rays.push_back(std::move(r));
    }
    for (InspectRay& r : out.rays)
        for (int& c : r.children) c = index[static_cast<size_t>(c)];
    return out;
}

}  // namespace rt
