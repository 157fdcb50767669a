#include "rt/render/aov.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <iterator>
#include <stdexcept>

#include "camera_sample.h"
#include "parallel.h"
#include "rt/accel/intersect.h"
#include "rt/render/sampler.h"
#include "rt/render/shading.h"

namespace rt {

namespace {

constexpr const char* kNames[] = {"albedo", "normal", "depth", "samples", "variance"};

bool* member(AovSet* set, size_t k) {
    bool* m[] = {&set->albedo, &set->normal, &set->depth, &set->samples, &set->variance};
    return m[k];
}

constexpr int kAovTile = 16;

// The camera ray of sample `index` of a pixel with `n` samples, as render_samples() traced it
// (camera_sample.h: the same positions from the same random numbers): one call of n samples
// with centre_first_sample, the progressive sequence without.
struct PixelSampler {
    const RenderPlan& plan;
    const RenderSettings& settings;
    bool stochastic;

    Ray ray(int x, int y, uint32_t index, uint32_t n) const {
        const size_t pixel = static_cast<size_t>(y) * settings.width + x;
        Rng rng(settings.seed, pixel, index);
        const int stratum = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
        const Vec2 sample =
            sample_position(settings, stochastic, static_cast<int>(index), static_cast<int>(n), 0,
                            stratum, progressive_shifts(settings, pixel), rng);
        return camera_ray(plan, settings, x, y, sample, rng);
    }
};

// The first hit's values along one ray (false: it hits nothing).
bool first_hit(const RenderScene& scene, const RenderPlan& plan, const Ray& ray, Vec3* albedo,
               Vec3* normal, double* depth) {
    Hit hit;
    if (!intersect(scene, plan, ray, {0.0, kInf}, &hit)) return false;
    const SurfaceInteraction si = interaction(scene, plan, ray, hit, plan.uses.textures);
    const Material& m = scene.materials[static_cast<size_t>(si.material)];
    // As trace() in shading.cpp: K_D times the texel, the normal facing the ray (spec §5).
    Vec3 t(1.0);
    if (m.texture >= 0) t = eval_texture(*scene.textures[static_cast<size_t>(m.texture)], si.uv);
    *albedo = m.diffuse * t;
    const Vec3 d = glm::normalize(ray.d);
    const double side = glm::dot(d, si.n_geometric) > 0 ? -1.0 : 1.0;
    *normal = side * si.n_shading;
    *depth = hit.t * glm::length(ray.d);
    return true;
}

}  // namespace

bool add_aov(const std::string& name, AovSet* set) {
    for (size_t k = 0; k < std::size(kNames); ++k)
        if (name == kNames[k]) return *member(set, k) = true;
    return false;
}

std::string aov_names() { return "albedo, normal, depth, samples, variance"; }

std::string aov_list(const AovSet& set) {
    AovSet s = set;
    std::string out;
    for (size_t k = 0; k < std::size(kNames); ++k)
        if (*member(&s, k)) {
            if (!out.empty()) out += ',';
            out += kNames[k];
        }
    return out;
}

FirstHitAovs render_first_hit_aovs(const RenderScene& scene, const RenderPlan& plan,
                                   const RenderSettings& settings,
                                   const std::vector<uint32_t>& samples,
                                   const std::atomic<bool>* stop) {
    const size_t pixels = static_cast<size_t>(settings.width) * settings.height;
    if (plan.camera.width != settings.width || plan.camera.height != settings.height)
        throw std::invalid_argument("render plan made for another image size");
    if (samples.size() != pixels)
        throw std::invalid_argument("the sample counts are not one per pixel of the image");
    FirstHitAovs out;
    out.width = settings.width;
    out.height = settings.height;
    out.albedo.assign(3 * pixels, 0.0);
    out.normal.assign(3 * pixels, 0.0);
    out.depth.assign(pixels, kInf);
    const PixelSampler sampler{plan, settings, settings.stochastic()};
    const int tiles_x = (settings.width + kAovTile - 1) / kAovTile;
    const int tiles = tiles_x * ((settings.height + kAovTile - 1) / kAovTile);
    RayCounters rays;
    const bool done = parallel_tiles(
        resolve_thread_count(settings.threads), tiles, stop, rays, [&](int tile, RayCounters&) {
            const int x0 = (tile % tiles_x) * kAovTile, y0 = (tile / tiles_x) * kAovTile;
            for (int y = y0; y < std::min(y0 + kAovTile, settings.height); ++y) {
                if (stop && stop->load(std::memory_order_relaxed)) return false;
                for (int x = x0; x < std::min(x0 + kAovTile, settings.width); ++x) {
                    const size_t p = static_cast<size_t>(y) * settings.width + x;
                    const uint32_t n = std::max(samples[p], 1u);
                    Vec3 albedo(0.0), normal(0.0);
                    double depth = 0.0;
                    uint32_t hits = 0;
                    for (uint32_t k = 0; k < n; ++k) {
                        Vec3 a, nrm;
                        double d;
                        if (!first_hit(scene, plan, sampler.ray(x, y, k, n), &a, &nrm, &d))
                            continue;
                        albedo += a, normal += nrm, depth += d, ++hits;
                    }
                    for (int c = 0; c < 3; ++c) {
                        out.albedo[p * 3 + static_cast<size_t>(c)] = albedo[c] / n;
                        out.normal[p * 3 + static_cast<size_t>(c)] = normal[c] / n;
                    }
                    if (hits > 0) out.depth[p] = depth / hits;
                }
            }
            return true;
        });
    if (!done) return {};
    return out;
}

std::vector<double> sample_variance(const RenderState& state) {
    std::vector<double> v(state.sum.size(), 0.0);
    for (size_t p = 0; p < state.samples.size(); ++p) {
        const double n = state.samples[p];
        if (n < 2) continue;
        for (size_t c = 0; c < 3; ++c) {
            const double s = state.sum[p * 3 + c], sq = state.sum_sq[p * 3 + c];
            v[p * 3 + c] = std::max(0.0, (sq - s * s / n) / (n - 1));
        }
    }
    return v;
}

std::vector<ExrChannel> aov_channels(const AovSet& set, const RenderState& state,
                                     const RenderScene& scene, const RenderPlan& plan,
                                     const RenderSettings& settings) {
    const size_t pixels = state.samples.size();
    std::vector<ExrChannel> out;
    // The channels of `names` from `values` (names.size() values per pixel).
    auto add = [&](std::initializer_list<const char*> names, ExrPixel type,
                   const std::vector<double>& values) {
        size_t k = 0;
        for (const char* name : names) {
            ExrChannel c{name, type, std::vector<double>(pixels)};
            for (size_t p = 0; p < pixels; ++p) c.values[p] = values[p * names.size() + k];
            out.push_back(std::move(c));
            ++k;
        }
    };
    if (set.first_hit()) {
        const FirstHitAovs h = render_first_hit_aovs(scene, plan, settings, state.samples);
        if (set.albedo) add({"Albedo.R", "Albedo.G", "Albedo.B"}, ExrPixel::Half, h.albedo);
        if (set.normal) add({"Ns.X", "Ns.Y", "Ns.Z"}, ExrPixel::Half, h.normal);
        if (set.depth) add({"depth.Z"}, ExrPixel::Float, h.depth);
    }
    if (set.samples)
        add({"Samples.N"}, ExrPixel::Uint,
            std::vector<double>(state.samples.begin(), state.samples.end()));
    if (set.variance)
        add({"Variance.R", "Variance.G", "Variance.B"}, ExrPixel::Half, sample_variance(state));
    return out;
}

}  // namespace rt
