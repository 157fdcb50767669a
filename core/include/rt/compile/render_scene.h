// The render representation: flat arrays with resolved indices and cached matrices, built from a
// SceneDesc by compile_scene(). Each .ray file that is instanced is compiled once into a
// GeometrySet (its groups flattened into the file's frame) with its own BVH; instances place a
// set in the world. The renderer never sees text.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rt/accel/bvh.h"
#include "rt/accel/triangle4.h"
#include "rt/image/image.h"
#include "rt/scene/scene_desc.h"
#include "rt/shapes/shapes.h"
#include "rt/util/error.h"

namespace rt {

struct Material {
    Vec3 emissive{0.0}, ambient{0.0}, diffuse{0.0}, specular{0.0};
    double specular_exponent = 0.0;
    Vec3 transparent{0.0};
    double refractive_index = 1.0;
    int texture = -1;  // index into RenderScene::textures
};

struct Light {
    LightKind kind = LightKind::Point;
    Vec3 color{1.0};
    Vec3 position{0.0};
    Vec3 direction{0.0, -1.0, 0.0};  // unit; directional: direction of travel; spot: axis
    double constant_atten = 1.0, linear_atten = 0.0, quadratic_atten = 0.0;
    double cutoff_rad = kPi;
    double spot_exponent = 0.0;
};

/// One primitive of a set: its kind, its index in the kind's array, its material and, for the
/// analytic shapes, the transform from the shape's frame to the set's frame (-1: identity).
struct Primitive {
    ShapeKind kind = ShapeKind::Sphere;
    uint32_t index = 0;
    int material = 0;
    int transform = -1;
};

/// How a set's leaves are walked (intersect.cpp): one shape kind tested without a dispatch, the
/// analytic kinds through a switch, packed triangles four at a time, or any mix of the five.
enum class SetLayout : uint8_t { Mixed, Analytic, Spheres, Boxes, Cylinders, Cones, Triangles };
inline constexpr int kSetLayouts = 7;

/// The compiled geometry of one .ray file, in that file's frame.
struct GeometrySet {
    std::string name;  // the file it came from
    std::vector<Primitive> prims;
    ShapeArrays shapes;               // the analytic shapes, one array per kind (shapes.h)
    std::vector<Triangle> triangles;  // flattened into the set's frame
    std::vector<Tri4> tri4;           // the same in float, four per block: what rays test,
    Vec3 tri_origin{0.0};             // relative to this point of the set's frame
    std::vector<TriangleAttribs> triangle_attribs;
    std::vector<Transform> transforms;    // set_from_shape for analytic shapes under groups
    std::vector<Bounds3> prim_bounds;     // in the set's frame
    Bvh bvh;                              // primitives are stored in its leaf order
    SetLayout layout = SetLayout::Mixed;  // the kinds of prims; Triangles: prims[i] is triangles[i]
};

/// A set placed in the world. Nested instancing is flattened into composed transforms.
struct Instance {
    int set = 0;
    Transform world_from_set;
    bool identity = true;
    Bounds3 world_bounds;
};

struct SceneStats {
    size_t files = 0;
    size_t prims_by_kind[5] = {0, 0, 0, 0, 0};  // after instancing
    size_t unique_prims = 0;                    // before instancing
    size_t instances = 0;
    size_t lights = 0, materials = 0, textures = 0;
    size_t skipped_shapes = 0;  // degenerate shapes the parser skipped
    double build_seconds = 0;   // BVH builds (included in compile_scene's time)
};

/// The geometry variant's switches (ShadeFeature's counterpart for the ray queries: one compiled
/// walk per combination, intersect.cpp): bit 0 the top-level walk over instances, bit 1 shape
/// and instance transforms, bits 2..4 the SetLayout every set shares, or kGeomPerSet when the
/// sets differ (each set's walk is then picked per set).
enum GeomFeature : uint32_t {
    kGeomInstancing = 1u << 0,
    kGeomTransforms = 1u << 1,
    kGeomLayoutShift = 2,
    kGeomPerSet = 7u << kGeomLayoutShift,
    /// The generic walk: the top-level BVH, transforms, and every primitive dispatched on its
    /// kind (Mixed), whatever the scene holds.
    kGeomGeneric = kGeomInstancing | kGeomTransforms,
    kGeomVariants = 32,
    /// A scene without shapes: every query answers at once (no walk at all).
    kGeomEmpty = kGeomVariants,
};
inline constexpr uint32_t geom_layout_bits(SetLayout l) {
    return static_cast<uint32_t>(l) << kGeomLayoutShift;
}

/// What the geometry holds, read once by compile_scene (rt/render/features.h adds lights, materials
/// and settings). A scene built by hand keeps the defaults: the generic walk. The specialized walks
/// trust it (one instance walked directly, a set's layout): code that changes the instances or
/// sets of a compiled scene sets it again with read_geometry() (lights, camera and materials may
/// change freely).
struct GeometryFeatures {
    size_t prims[5] = {0, 0, 0, 0, 0};  // by ShapeKind, after instancing
    bool instancing = false;            // more than one instance
    bool top_level = false;             // rays walk the top-level BVH (several instances or a
                                        // transformed one)
    bool transforms = false;            // an instance or shape transform that is not the identity
    bool nonuniform_scale = false;      // one that scales unevenly (normals need (A^-1)^T)
    std::vector<char> material_used;    // per material: some placed primitive uses it
    uint32_t variant = kGeomGeneric;    // GeomFeature bits of the walk that fits
};

struct RenderScene {
    Dialect dialect = Dialect::V1;
    std::optional<CameraDesc> camera;  // absent: default camera (spec §6.3)
    Vec3 background{0.0};
    Vec3 ambient{0.0};
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<std::shared_ptr<const TextureImage>> textures;
    std::vector<GeometrySet> sets;
    std::vector<Instance> instances;
    Bvh top;               // over instances' world bounds
    Bounds3 world_bounds;  // tight when the scene has no camera (the default camera frames it)
    GeometryFeatures geometry;
    SceneStats stats;
};

/// A light of the description as the renderer uses it (directions made unit) and back (the
/// viewer saves edited lights through the description).
Light compile_light(const LightDesc& desc);
LightDesc describe_light(const Light& light);

/// SceneDesc -> RenderScene: resolves indices, flattens groups, instances sets, builds BVHs.
RenderScene compile_scene(const SceneDesc& desc);

}  // namespace rt
