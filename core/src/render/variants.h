// The variants of "leave out what a scene does not need" (private to the core): the switches
// of the shading code (shading.cpp), those of the ray queries (accel/queries.h), and what a scene
// uses, read from its values. make_render_plan() (plan.cpp) is the one place that chooses a
// variant; everything else reads the choice from the RenderPlan.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "accel/queries.h"
#include "rt/accel/intersect.h"
#include "rt/render/mistakes.h"
#include "rt/render/plan.h"
#include "rt/render/shading.h"
#include "rt/render_scene.h"

namespace rt {

/// The shading variant's switches: one compiled instance of the shading code per combination
/// (shading.cpp), each with the code of the features it lacks removed at compile time.
enum ShadeFeature : uint32_t {
    kShadeShadows = 1u << 0,              // shadow rays at all
    kShadeTransmissiveShadows = 1u << 1,  // shadow rays multiply every crossing's T (else: any hit)
    kShadeReflection = 1u << 2,           // mirror rays (some K_S != 0, depth > 1)
    kShadeRefraction = 1u << 3,           // refracted rays (some T != 0, depth > 1)
    kShadeTextures = 1u << 4,             // texture lookups
    kShadeHighlights = 1u << 5,           // the Phong highlight term (some K_S != 0)
    kShadeSpot = 1u << 6,                 // spot cut-off and drop-off
    kShadeAttenuation = 1u << 7,          // point or spot lights (distance and attenuation)
    kShadeStochastic = 1u << 8,           // soft shadows or glossy reflection (random samples)
    kShadeV3Lights = 1u << 9,  // V3 lights (spec §13.9): ambient per light, a specular colour of
                               // their own, sphere lights (their shadow factor over the sphere)
    kShadeAll = (1u << 10) - 1,
};

namespace shading {
/// The recorder of a render (shading_impl.h): it records nothing. An empty type passed by value
/// takes no register, and its empty inline methods (the inspector's TreeRecorder's, inspect.cpp)
/// leave nothing in the render's code.
struct NoRecord {
    static constexpr bool kOn = false;
    template <class... A>
    NoRecord light(const A&...) const {
        return {};
    }
    template <class... A>
    NoRecord secondary(const A&...) const {
        return {};
    }
    template <class... A>
    void attenuation(const A&...) const {}
    template <class... A>
    void spot(const A&...) const {}
    template <class... A>
    void factor(const A&...) const {}
    template <class... A>
    void facing(const A&...) const {}
    template <class... A>
    void skip(const A&...) const {}
    template <class... A>
    void light_ambient(const A&...) const {}
    template <class... A>
    void shadow_ray(const A&...) const {}
    template <class... A>
    void shadow(const A&...) const {}
    template <class... A>
    void direct(const A&...) const {}
    template <class... A>
    void secondary_value(const A&...) const {}
    template <class... A>
    void stop(const A&...) const {}
    template <class... A>
    void miss(const A&...) const {}
    template <class... A>
    void hit(const A&...) const {}
    template <class... A>
    void depth_limit(const A&...) const {}
    template <class... A>
    void result(const A&...) const {}
};

/// The switches of a teaching render (rt/render/mistakes.h): a recorder that records nothing and
/// carries the mistakes switched on, which the formula sites of shading_impl.h read through
/// mistake(). Only render_with_mistakes() (mistakes.cpp) instantiates the shading with it; for
/// every other recorder mistake() is a constant false and the switch is compiled away.
struct WithMistakes : NoRecord {
    MistakeSet mistakes;
    template <class... A>
    WithMistakes light(const A&...) const {
        return *this;
    }
    template <class... A>
    WithMistakes secondary(const A&...) const {
        return *this;
    }
};

/// Whether mistake `m` is on in a render with recorder `rec`: false, at compile time, but in a
/// render with WithMistakes.
template <class Rec>
[[gnu::always_inline]] constexpr bool mistake(const Rec& rec, Mistake m) {
    if constexpr (std::is_same_v<Rec, WithMistakes>)
        return rec.mistakes.has(m);
    else
        return (static_cast<void>(rec), static_cast<void>(m), false);
}
}  // namespace shading

/// The shading code of one ShadeFeature combination (shading.cpp).
struct ShadingVariant {
    Vec3 (*trace)(const RenderScene&, const RenderPlan&, const RenderSettings&, const Ray&,
                  int depth, const Vec3& weight, RayCounters&, Rng*, shading::NoRecord);
};
const ShadingVariant& shading_variant(uint32_t shade_variant);

/// What the geometry holds and the walk that fits it.
struct GeometryFeatures {
    size_t prims[kShapeKinds] = {};   // by ShapeKind, after instancing (CSG leaves included)
    size_t csg_nodes = 0;             // CSG operations (union, intersection, difference), after
                                      // instancing
    bool instancing = false;          // more than one instance
    bool top_level = false;           // rays walk the top-level BVH (several instances or a
                                      // transformed one)
    bool transforms = false;          // an instance or shape transform that is not the identity
    bool nonuniform_scale = false;    // one that scales unevenly (normals need (A^-1)^T)
    std::vector<char> material_used;  // per material: some placed primitive uses it
    uint32_t variant = kGeomGeneric;  // GeomFeature bits of the walk that fits
};

/// What a scene uses with the given settings, read from its values and not only from its syntax
/// (a material with zero specular colour reflects nothing; a light of colour zero lights nothing).
struct SceneFeatures {
    GeometryFeatures geometry;
    // Lights that can light something (colour not zero, some attenuation coefficient not zero),
    // by kind: directional, point, spot, sphere (the LightKind order).
    int lights[kLightKinds] = {};
    int dark_lights = 0;                // lights that light nothing, left out
    int direct_lights = 0;              // of those, lights with a diffuse or specular colour
    int ambient_lights = 0;             // V3: lights with an ambient colour
    bool light_ambient = false;         // V3: a light's ambient colour meets a used K_A
    int specular_colour_lights = 0;     // V3: lights whose specular colour is not their diffuse
    int light_samples = 1;              // the settings' points per sphere light
    bool shadows = false;               // shadow rays: the setting on and a light that lights
    bool transmissive_shadows = false;  // a used material lets light through
    bool reflection = false;            // a used material reflects and the depth allows it
    bool refraction = false;            // a used material transmits and the depth allows it
    bool highlights = false;            // a used material has a specular colour
    bool textures = false;              // a used material is textured
    bool emissive = false;              // a used material emits
    bool ambient = false;               // ambient light and a used ambient colour
    size_t unused_textures = 0;
    bool soft_shadows = false, depth_of_field = false, glossy = false;  // progressive features
    int max_depth = 1;

    /// Whether the V3 light code runs (kShadeV3Lights): per-light ambient, separate specular
    /// colours or sphere lights.
    bool v3_lights() const {
        return light_ambient || specular_colour_lights > 0 ||
               lights[static_cast<int>(LightKind::Sphere)] > 0;
    }
    /// The ShadeFeature bits of the variant that renders this scene.
    uint32_t shade_variant() const;
};

/// Reads what the scene's geometry holds (one pass over the placed sets' primitives).
GeometryFeatures read_geometry(const RenderScene& scene);

/// Reads what the scene uses: its geometry, the lights, the used materials and the settings.
/// Materials count only when some instanced primitive uses them.
SceneFeatures scene_features(const RenderScene& scene, const RenderSettings& settings);

/// Why each feature is kept or left out (the RenderPlan's reasons).
std::vector<PlanReason> explain_features(const SceneFeatures& f);

}  // namespace rt
