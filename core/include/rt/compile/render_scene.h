// The render representation: flat arrays with resolved indices and cached matrices, built from a
// SceneDesc by compile_scene() (rt/compile/compile.h). Each .ray file that is instanced is compiled
// once into a GeometrySet (its groups flattened into the file's frame) with its own BVH; instances
// place a set in the world. The renderer never sees text.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rt/accel/bvh.h"
#include "rt/accel/triangle4.h"
#include "rt/image/image.h"
#include "rt/shapes/shapes.h"
#include "rt/util/error.h"
#include "rt/util/light_kind.h"

namespace rt {

struct Material {
    Vec3 emissive{0.0}, ambient{0.0}, diffuse{0.0}, specular{0.0};
    double specular_exponent = 0.0;
    Vec3 transparent{0.0};
    double refractive_index = 1.0;
    int texture = -1;  // index into RenderScene::textures
};

/// A light (spec §7.2, §13.3). A V0/V1 light's one colour is its diffuse and specular colour.
struct Light {
    LightKind kind = LightKind::Point;
    Vec3 ambient{0.0};   // A_l: V3, attenuated and spot-limited, never shadowed (spec §13.9)
    Vec3 diffuse{1.0};   // D_l
    Vec3 specular{1.0};  // S'_l
    Vec3 position{0.0};
    Vec3 direction{0.0, -1.0, 0.0};  // unit; directional: direction of travel; spot: axis
    double constant_atten = 1.0, linear_atten = 0.0, quadratic_atten = 0.0;
    double cutoff_rad = kPi;
    double spot_exponent = 0.0;
    double radius = 0.0;  // sphere lights: the shadow factor is averaged over this sphere
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

/// The camera of the file (spec §6.1) as the renderer uses it; make_camera() builds the frame.
struct CameraPose {
    Vec3 position{0.0};
    Vec3 direction{0.0, 0.0, -1.0};
    Vec3 up{0.0, 1.0, 0.0};
    double half_height_angle_rad = kPi / 6;
};

struct RenderScene {
    std::optional<CameraPose> camera;  // absent: default camera (spec §6.3, at the render's size)
    Vec3 background{0.0};
    Vec3 ambient{0.0};
    /// V3 (spec §13.9): the texel multiplies K_E, K_A, K_D and K_S; V0/V1: K_A and K_D only.
    bool texture_all_terms = false;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<std::shared_ptr<const TextureImage>> textures;
    std::vector<GeometrySet> sets;
    std::vector<Instance> instances;
    Bvh top;               // over instances' world bounds
    Bounds3 world_bounds;  // tight when the scene has no camera (the default camera frames it)
};

}  // namespace rt
