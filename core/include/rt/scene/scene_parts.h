// The parts of a scene that the description (rt/scene/scene_desc.h) and the render
// representation (rt/render_scene.h) share: a light, a material's terms, the camera's pose. The
// description's LightDesc, MaterialDesc and CameraDesc are these plus where the file wrote them;
// the compile takes them as they are (lights' directions made unit, textures renumbered).
#pragma once

#include "rt/util/light_kind.h"
#include "rt/util/math.h"

namespace rt {

/// A light (spec §7.2, §13.3). V0/V1 lights have one colour, which is their diffuse and their
/// specular colour (and no ambient); V3 lights have three.
struct Light {
    LightKind kind = LightKind::Point;
    Vec3 ambient{0.0};   // A_l: V3, attenuated and spot-limited, never shadowed (spec §13.9)
    Vec3 diffuse{1.0};   // D_l: the V0/V1 colour
    Vec3 specular{1.0};  // S'_l: the V0/V1 colour
    Vec3 position{0.0};  // point, spot; sphere: centre
    // Directional: direction of travel; spot: axis. Unit once compiled (other kinds: the default).
    Vec3 direction{0.0, -1.0, 0.0};
    double constant_atten = 1.0, linear_atten = 0.0, quadratic_atten = 0.0;
    double cutoff_rad = kPi;
    double spot_exponent = 0.0;  // p, already 128*dor in V0 (spec §7.2)
    double radius = 0.0;         // sphere lights: the shadow factor is averaged over this sphere
    bool operator==(const Light&) const = default;

    /// Spec §7.1's one intensity, the V0/V1 light (no ambient, diffuse = specular), which the
    /// renderer shades by §7.1's terms; a sphere light (V3 only) never is one.
    bool one_colour() const {
        return kind != LightKind::Sphere && ambient == Vec3(0.0) && diffuse == specular;
    }
    void set_colour(const Vec3& c) { ambient = Vec3(0.0), diffuse = specular = c; }
};

/// A number of a light that a user sets by name: the viewer's panel shows one control per row
/// and its script's `light I NAME X` sets it, from this table alone. So a new number is its field
/// in Light, its row here and its use in the renderers (shading and the preview).
struct LightNumber {
    const char* name;   // the script's word
    const char* label;  // the panel's
    double Light::*field;
    double lo, hi;          // the range a user sets it in
    float step;             // the panel drags it by this much a pixel; 0: a slider
    bool (*of)(LightKind);  // the kinds that have it
};

inline constexpr LightNumber kLightNumbers[] = {
    {"radius", "radius", &Light::radius, 0.0, 1e6, 0.01f,
     [](LightKind k) { return k == LightKind::Sphere; }},
    {"constant", "constant attenuation", &Light::constant_atten, 0.0, 100.0, 0.005f,
     [](LightKind k) { return k != LightKind::Directional; }},
    {"linear", "linear attenuation", &Light::linear_atten, 0.0, 100.0, 0.005f,
     [](LightKind k) { return k != LightKind::Directional; }},
    {"quadratic", "quadratic attenuation", &Light::quadratic_atten, 0.0, 100.0, 0.005f,
     [](LightKind k) { return k != LightKind::Directional; }},
    {"cutoff", "cut-off (rad)", &Light::cutoff_rad, 0.0, kPi, 0.0f,
     [](LightKind k) { return k == LightKind::Spot; }},
    {"dropoff", "drop-off exponent", &Light::spot_exponent, 0.0, 256.0, 0.0f,
     [](LightKind k) { return k == LightKind::Spot; }},
};

/// A material's terms with the dialect resolved (spec §3.2: V0's kspec and scalar ktran are
/// converted).
struct Material {
    Vec3 emissive{0.0}, ambient{0.0}, diffuse{0.0}, specular{0.0};
    double specular_exponent = 0.0;  // e
    Vec3 transparent{0.0};           // T
    double refractive_index = 1.0;
    /// -1: none. A MaterialDesc's is an index into its file's textures, a compiled material's
    /// into RenderScene::textures.
    int texture = -1;
    bool operator==(const Material&) const = default;
};

/// The camera (spec §6.1, §3.1); make_camera() (rt/render/camera.h) builds the frame.
struct CameraPose {
    Vec3 position{0.0};
    Vec3 direction{0.0, 0.0, -1.0};
    Vec3 up{0.0, 1.0, 0.0};
    double half_height_angle_rad = kPi / 6;  // spec §3.1: ha is the half-height angle
};

}  // namespace rt
