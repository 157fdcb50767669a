// The geometry variants of "leave out what a scene does not need" (private to the core): one
// compiled set of ray queries per combination of what a scene's geometry holds. The render plan
// (render/plan.cpp) chooses one; the walks themselves are in intersect.cpp.
#pragma once

#include <cstdint>

#include "rt/accel/intersect.h"
#include "rt/render_scene.h"

namespace rt {

/// The geometry variant's switches (one compiled walk per combination, intersect.cpp): bit 0 the
/// top-level walk over instances, bit 1 shape and instance transforms, bits 2..4 the SetLayout
/// every set shares, or kGeomPerSet when the sets differ (each set's walk is then picked per set),
/// bit 5 the CSG test.
enum GeomFeature : uint32_t {
    kGeomInstancing = 1u << 0,
    kGeomTransforms = 1u << 1,
    kGeomLayoutShift = 2,
    kGeomPerSet = 7u << kGeomLayoutShift,
    /// CSG primitives (spec §13.8): only Mixed-layout sets hold them, so the bit goes with the
    /// Mixed and per-set layouts (geometry_queries drops it from the others).
    kGeomCsg = 1u << 5,
    /// The generic walk: the top-level BVH, transforms, CSG, and every primitive dispatched on
    /// its kind (Mixed), whatever the scene holds.
    kGeomGeneric = kGeomInstancing | kGeomTransforms | kGeomCsg,
    kGeomVariants = 64,
    /// A scene without shapes: every query answers at once (no walk at all).
    kGeomEmpty = kGeomVariants,
};
// The layout field holds every SetLayout and, above them, kGeomPerSet.
static_assert(kSetLayouts <= (kGeomPerSet >> kGeomLayoutShift), "widen the layout bits");
inline constexpr uint32_t geom_layout_bits(SetLayout l) {
    return static_cast<uint32_t>(l) << kGeomLayoutShift;
}

/// The ray queries of one geometry variant and the surface description at their hits, with the
/// code of what the variant lacks left out: the top-level walk, transforms, the dispatch on shape
/// kinds, the triangle set-up. kGeomGeneric serves any scene; a specialized variant only the
/// scenes it was read from.
struct GeometryQueries {
    bool (*intersect)(const RenderScene&, const Ray&, Interval, Hit*);
    bool (*occluded)(const RenderScene&, const Ray&, double);
    Vec3 (*transmittance)(const RenderScene&, const Ray&, double);
    SurfaceInteraction (*interaction)(const RenderScene&, const Ray&, const Hit&, bool uv);
};
/// The queries of a GeomFeature combination, with the kernels of the active instruction set
/// (rt/util/isa.h; intersect.cpp).
const GeometryQueries& geometry_queries(uint32_t geom_variant);
/// The same with one instruction set's kernels (walks.h, compiled once per instruction set).
namespace sse2 {
const GeometryQueries& geometry_queries(uint32_t geom_variant);
}
namespace avx2 {
const GeometryQueries& geometry_queries(uint32_t geom_variant);
}
namespace avx512 {
const GeometryQueries& geometry_queries(uint32_t geom_variant);
}

}  // namespace rt
