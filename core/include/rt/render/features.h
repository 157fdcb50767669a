// What a compiled scene actually uses, read from its values and not only from its syntax (a
// material with zero specular colour reflects nothing; a light of colour zero lights nothing), and
// the renderer variant that leaves the rest out. render_samples() and render_coarse() pick the
// variant once per call; RenderSettings::specialize = false keeps the generic path (every feature
// tested per ray), which renders the same image.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rt/compile/render_scene.h"

namespace rt {

struct RenderSettings;

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
    kShadeAll = (1u << 9) - 1,
};

struct SceneFeatures {
    // Lights that can light something (colour not zero, some attenuation coefficient not zero),
    // by kind: directional, point, spot (the LightKind order).
    int lights[3] = {0, 0, 0};
    int dark_lights = 0;                // lights that light nothing, left out
    bool shadows = false;               // shadow rays: the setting on and a light that lights
    bool transmissive_shadows = false;  // a used material lets light through
    bool reflection = false;            // a used material reflects and the depth allows it
    bool refraction = false;            // a used material transmits and the depth allows it
    bool highlights = false;            // a used material has a specular colour
    bool textures = false;              // a used material is textured
    bool emissive = false;              // a used material emits
    bool ambient = false;               // ambient light and a used ambient colour
    size_t prims[5] = {0, 0, 0, 0, 0};  // primitives by ShapeKind, after instancing
    size_t sets = 0, unused_textures = 0;
    bool instancing = false;        // more than one instance
    bool top_level = false;         // the two-level walk: several instances or a transformed one
    bool transforms = false;        // an instance or shape transform that is not the identity
    bool nonuniform_scale = false;  // one that scales unevenly (normals need (A^-1)^T)
    bool soft_shadows = false, depth_of_field = false, glossy = false;  // progressive features
    int max_depth = 1;
    uint32_t geom_variant = kGeomGeneric;  // GeomFeature bits of the walk (RenderScene::geometry)

    /// The ShadeFeature bits of the variant that renders this scene.
    uint32_t shade_variant() const;
};

/// Reads what the scene's geometry holds and the walk that fits it (compile_scene stores it in
/// RenderScene::geometry; the viewer's light edits do not change it).
GeometryFeatures read_geometry(const RenderScene& scene);

/// Reads what the scene uses: RenderScene::geometry, the lights, the used materials and the
/// settings. Materials count only when some instanced primitive uses them.
SceneFeatures scene_features(const RenderScene& scene, const RenderSettings& settings);

/// The lights the specialized renderer iterates: those that can light something.
std::vector<Light> lighting_lights(const RenderScene& scene);

/// One line per feature left out, "left out: <feature>: <reason>", and one per feature kept,
/// "kept: <feature>: <why>" (raytrace --explain, the viewer's status).
std::vector<std::string> explain_features(const SceneFeatures& f);

}  // namespace rt
