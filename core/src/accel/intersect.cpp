// The ray queries' entry points: the table of walks of the active instruction set (the walks
// themselves: walks.h), and the offset of a spawned ray's origin.
#include "rt/accel/intersect.h"

#include <cmath>

#include "accel/queries.h"
#include "rt/util/isa.h"

namespace rt {

const GeometryQueries& geometry_queries(uint32_t variant) {
#if defined(__x86_64__) && !defined(__wasm__) && !defined(RT_SSE2_ONLY)
    switch (active_isa()) {
        case Isa::Avx512:
            return avx512::geometry_queries(variant);
        case Isa::Avx2:
            return avx2::geometry_queries(variant);
        case Isa::Sse2:
            break;
    }
#endif
    return sse2::geometry_queries(variant);
}

bool intersect(const RenderScene& scene, const Ray& ray, Interval t, Hit* hit) {
    return geometry_queries(kGeomGeneric).intersect(scene, ray, t, hit);
}

bool occluded(const RenderScene& scene, const Ray& ray, double t_max) {
    return geometry_queries(kGeomGeneric).occluded(scene, ray, t_max);
}

Vec3 transmittance(const RenderScene& scene, const Ray& ray, double t_max) {
    return geometry_queries(kGeomGeneric).transmittance(scene, ray, t_max);
}

SurfaceInteraction interaction(const RenderScene& scene, const Ray& ray, const Hit& hit, bool uv) {
    return geometry_queries(kGeomGeneric).interaction(scene, ray, hit, uv);
}

Vec3 offset_origin(const SurfaceInteraction& si, const Vec3& dir) {
    const Vec3 n = si.n_geometric;
    // Spec §7.5: the origin moves along n_g by a bound on the point's floating-point error, not by
    // a fixed epsilon: pbrt-v4's OffsetRayOrigin (Pharr, Jakob, Humphreys, "Physically Based
    // Rendering", 4th ed., §6.8.6), the error-bound form of the offset that Wächter and Binder
    // ("A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6) derive
    // from the float grid. Distance along n that moves the point outside its error box:
    const double d = glm::dot(glm::abs(n), si.p_error);
    Vec3 offset = d * n;
    if (glm::dot(dir, n) < 0) offset = -offset;
    Vec3 po = si.p + offset;
    // Round away from the surface so the offset point is not rounded back onto it.
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0)
            po[i] = std::nextafter(po[i], kInf);
        else if (offset[i] < 0)
            po[i] = std::nextafter(po[i], -kInf);
    }
    return po;
}

Ray spawn_ray(const SurfaceInteraction& si, const Vec3& dir) {
    return {offset_origin(si, dir), dir};
}

}  // namespace rt
