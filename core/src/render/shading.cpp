#include "rt/render/shading.h"

#include <array>
#include <stdexcept>
#include <string>
#include <utility>

#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "shading_impl.h"
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

double light_factor(const Light& light, const Vec3& p, Vec3* to_light, double* distance) {
    return shading::light_kinds<true, true>(light, p, to_light, distance);
}

bool eval_light(const Light& light, const Vec3& p, Vec3* intensity, Vec3* to_light,
                double* distance) {
    if (light.diffuse == Vec3(0.0)) return false;  // lights nothing (not 0 * inf = NaN either)
    const double factor = light_factor(light, p, to_light, distance);
    *intensity = light.diffuse * factor;
    return factor > 0.0;
}

namespace {

using shading::canonical;

template <uint32_t... I>
constexpr std::array<ShadingVariant, sizeof...(I)> trace_table(
    std::integer_sequence<uint32_t, I...>) {
    return {ShadingVariant{&shading::trace<canonical(I), shading::NoRecord>}...};
}

// Every variant, indexed by its ShadeFeature bits.
constexpr auto kTraceVariants = trace_table(std::make_integer_sequence<uint32_t, kShadeAll + 1>{});

}  // namespace

const ShadingVariant& shading_variant(uint32_t shade_variant) {
    return kTraceVariants[shade_variant & kShadeAll];
}

void check_depth(int depth) {
    if (depth > kMaxDepth)
        throw std::invalid_argument("ray depth " + std::to_string(depth) +
                                    " is more than the maximum, " + std::to_string(kMaxDepth));
}

Vec3 trace_ray(const RenderScene& scene, const RenderPlan& plan, const RenderSettings& settings,
               const Ray& ray, int depth, const Vec3& weight, RayCounters& counters, Rng* rng) {
    check_depth(depth);  // each level nests a call: bounded, so the stack is
    return plan.shading->trace(scene, plan, settings, ray, depth, weight, counters, rng, {});
}

}  // namespace rt
