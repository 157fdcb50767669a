// The ray tree of one pixel sample: every ray the renderer traces for it (camera, reflected,
// refracted and shadow rays), each hit and every term of the shading equation with its inputs
// (spec §7, §8, §13.9; docs/format.md). The tree is written down by the renderer's own shading
// code (render/shading_impl.h), compiled once more with a recorder, so it explains the very
// value the renderer computes: its colour is the sample's colour bit for bit.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "rt/accel/intersect.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/render_scene.h"
#include "rt/scene/scene_desc.h"
#include "rt/util/limits.h"

namespace rt {

/// A primitive met by a ray: its instance, its index in the instance's set, its kind and, for a
/// CSG node's hit, the leaf hit.
struct InspectPrim {
    int instance = -1;
    int set = -1;
    uint32_t prim = 0;
    ShapeKind kind = ShapeKind::Sphere;
    bool csg = false;
};

/// A surface a shadow ray crosses: where, and the transparency T it lets through.
struct InspectOccluder {
    InspectPrim prim;
    double t = 0.0;         // along the shadow ray (its direction is not unit toward a point)
    double distance = 0.0;  // from the ray's origin
    int material = -1;
    Vec3 transparent{0.0};  // the material's T (0: opaque)
};

/// One shadow ray: from the offset point toward a point (t in (0, 1)) or a direction.
struct InspectShadowRay {
    Ray ray;             // ray.o: the origin, the hit point moved off the surface (spec §7.5)
    Vec3 hit{0.0};       // the hit point the origin was moved off
    Vec3 offset{0.0};    // ray.o - hit: the origin offset offset_origin() gave (along +-n_g)
    double t_max = 1.0;  // 1: toward ray.o + ray.d (a point); infinite: a direction
    Vec3 transmittance{1.0};
    std::vector<InspectOccluder> occluders;  // in order along the ray
};

/// One light's terms at a hit (spec §7.1, §7.2, §13.9): the light as this sample saw it (soft
/// shadows move its position; Light::one_colour() picks §7.1's terms or §13.9's), then its terms.
struct InspectLight : Light {
    int light = -1;  // index into RenderScene::lights
    // Attenuation: points and spots.
    bool attenuated = false;
    double distance = 0.0, denominator = 1.0;  // d and c0 + c1 d + c2 d^2
    // Spot limit.
    bool spot = false;
    double cos_angle = 1.0, spot_factor = 1.0;
    double factor = 0.0;  // f_l = spot / denominator (1 for directional lights)
    bool facing_known = false;
    Vec3 to_light{0.0};  // L
    double n_dot_l = 0.0;
    double r_dot_l = 0.0;       // R.L, R the mirror direction of the view ray
    double highlight = 0.0;     // spec_l = max(R.L, 0)^n
    Vec3 ambient_term{0.0};     // V3: K_A A_l f_l
    bool terms_known = false;   // the diffuse and specular terms were computed (also in shadow)
    Vec3 diffuse_term{0.0};     // I_l K_D (N.L), before the shadow factor
    Vec3 specular_term{0.0};    // I_l K_S spec_l, before the shadow factor
    std::string no_shadow_ray;  // why no shadow ray was traced, when none was
    bool shadow_tested = false;
    Vec3 shadow{1.0};                           // S_l
    size_t shadow_ray_count = 0;                // shadow rays traced (a sphere light's points)
    std::vector<InspectShadowRay> shadow_rays;  // the first kMaxShadowRays of them
    Vec3 value{0.0};                            // what the light adds to the colour
    std::string note;                           // why it adds nothing, when it does not
    static constexpr size_t kMaxShadowRays = kMaxInspectShadowRays;
};

/// Why a reflected or refracted ray was not traced.
struct InspectStop {
    std::string kind;  // "reflected" or "refracted"
    std::string why;   // "depth limit", "cutoff", "total internal reflection", ...
    Vec3 weight{0.0};  // the path weight it would have had
};

/// One ray of the tree and what it met.
struct InspectRay {
    enum class Kind { Camera, Reflected, Refracted };
    Kind kind = Kind::Camera;
    int depth = 0;  // the depth it was traced with (the camera ray: the settings' max_depth)
    Ray ray;        // as traced (reflected and refracted rays start at the offset point)
    Vec3 weight{1.0};
    int parent = -1;
    // Refraction: the ratio of indices and cos of the incident angle.
    double eta = 1.0, cos_incident = 1.0;
    bool hit = false;
    // The hit.
    double t = 0.0, distance = 0.0;  // along ray.d, and from the origin
    Vec3 point{0.0};
    InspectPrim prim;
    int material = -1;
    Vec3 n_geometric{0.0}, n_shading{0.0}, n{0.0};  // n: the normal shaded with (spec §5)
    bool entering = true;                           // the ray met the outward side
    Vec2 uv{0.0};
    bool textured = false;
    Vec3 texel{1.0};
    // The terms (spec §7.1): emissive, ambient, every light, reflected and refracted.
    Vec3 emissive{0.0};
    Vec3 k_a{0.0}, k_d{0.0}, k_s{0.0};  // with the texel applied
    double exponent = 0.0;
    Vec3 scene_ambient{0.0}, ambient{0.0};
    std::vector<InspectLight> lights;
    Vec3 k_reflect{0.0}, reflected{0.0};  // K_S and K_S x the reflected ray's colour
    Vec3 k_transmit{0.0}, refracted{0.0};
    std::vector<int> children;  // indices into PixelTree::rays
    /// A reflected or refracted ray traced past the tree's limits (PixelTree::kMaxRays,
    /// kMaxRecords): its colour counts, but neither it nor the rays below it are recorded.
    struct NotRecorded {
        Kind kind = Kind::Reflected;
        int depth = 0;
        Vec3 weight{0.0};
        Vec3 color{0.0};  // the colour it brought back (what K_S or T multiplies)
        size_t rays = 1;  // it and every ray below it
    };
    std::vector<NotRecorded> not_recorded;
    /// Rays below it that a filter (filter_tree(), --inspect-depth) leaves out of what is shown:
    /// traced and recorded, their colours counted in `reflected` and `refracted`.
    std::vector<NotRecorded> left_out;
    size_t lights_left_out = 0;  // light terms a filter (--inspect-light) leaves out
    std::vector<InspectStop> stops;
    Vec3 color{0.0};  // the sum (the background on a miss)
};

/// The camera's inputs for the pixel's sample (spec §6.1, §6.2), as the renderer's camera
/// (rt/render/camera.h) holds and computes them.
struct InspectCamera {
    bool from_file = true;               // the scene's camera, else the default camera of §6.3
    double half_height_angle_rad = 0.0;  // ha, as the file gives it (or §6.3's pi/6)
    double tan_h = 0.0, tan_w = 0.0;     // tan(ha), tan(ha) x width / height
    int width = 1, height = 1;
    Vec3 position{0.0};
    Vec3 forward{0.0}, right{0.0}, up{0.0};  // f, r = f x up / |f x up|, up' = r x f
    Vec2 image_point{0.0};  // (x, y) of §6.2: the direction is normalize(f + x r + y up')
};

/// The 8-bit output of the pixel (spec §9), as the image writer computes it (rt::to_byte).
struct InspectOutput {
    uint8_t bytes[3] = {0, 0, 0};  // floor(255 clamp(c, 0, 1) + 0.5) of the pixel's value
};

/// The tree of one sample of a pixel.
struct PixelTree {
    int x = 0, y = 0;     // column, row from the top
    uint32_t sample = 0;  // of `samples` per pixel
    uint32_t samples = 1;
    Vec2 position{0.5};            // where in the pixel, [0,1)^2 from its top left corner
    bool random = false;           // the sample drew random numbers (jitter, lens, light points)
    Vec3 lens{0.0};                // the camera ray's origin (moved over the lens with an aperture)
    std::vector<InspectRay> rays;  // rays[0] is the camera ray; each ray before its children
    size_t rays_not_recorded = 0;  // traced past the limits below (their colours still count)
    size_t records = 0;            // light terms, shadow rays and occluders recorded
    Vec3 color{0.0};               // the sample's colour (rays[0].color)
    Vec3 pixel{0.0};               // the pixel's value over all its samples (what the image holds)
    InspectCamera camera;          // the camera's inputs for this sample
    InspectOutput output;          // the 8-bit value written for the pixel (PNG, BMP, PPM)
    // What filter_tree() left out of what is shown (0, -1: nothing).
    int filter_depth = 0;      // --inspect-depth N: rays deeper than N levels left out
    int filter_light = -1;     // --inspect-light K: only light K's terms
    size_t rays_left_out = 0;  // rays left out by filter_depth

    // The limits that keep a tree's memory and its text bounded (rt/util/limits.h). Past
    // either, no further ray is recorded; the rays are still traced, so the colour is the
    // same. A recorded ray keeps all its light terms; its shadow rays and their surfaces are
    // recorded while the budget of records lasts.
    static constexpr size_t kMaxRays = kMaxInspectRays;
    static constexpr size_t kMaxRecords = kMaxInspectRecords;
    size_t max_rays = kMaxRays;  // the limits this tree was recorded with
    size_t max_records = kMaxRecords;
};

/// The limits inspect_pixel() records a tree within (PixelTree::kMaxRays, kMaxRecords unless a
/// test asks for less).
struct InspectLimits {
    size_t rays = PixelTree::kMaxRays;
    size_t records = PixelTree::kMaxRecords;
};

/// The tree of sample `sample` of pixel (x, y) of a render of `spp` samples per pixel with
/// `settings` (what render_samples(state, scene, plan, settings, spp) traces for it, on a fresh
/// state, with the plan's shading code), within `limits`. Throws std::invalid_argument when the
/// pixel lies outside the image or the sample is not below spp.
PixelTree inspect_pixel(const RenderScene& scene, const RenderPlan& plan,
                        const RenderSettings& settings, int x, int y, uint32_t sample = 0,
                        int spp = 1, const InspectLimits& limits = {});

/// What filter_tree() keeps of a tree: rays down to `depth` levels (the camera ray is level 1,
/// as --depth counts; 0: all), and only the terms and shadow rays of light `light` (-1: all).
struct InspectFilter {
    int depth = 0;
    int light = -1;
};

/// The tree with the rays deeper than filter.depth and the other lights' terms left out (each
/// ray keeps the colour of what was left out below it, and says how many rays it was). The
/// values are the tree's own: nothing is traced again.
PixelTree filter_tree(const PixelTree& tree, const InspectFilter& filter);

/// What the printed tree names things by: the primitives' directives and the groups above them,
/// the materials' names (empty when unknown).
struct InspectNames {
    const SceneDesc* desc = nullptr;
    const std::vector<std::vector<SourceLoc>>* prim_locs = nullptr;
    const std::vector<std::string>* material_names = nullptr;
};

/// "sphere 3 of instance 0 at scene.ray:12:1 (scene.ray > group at line 10)".
std::string inspect_prim_name(const InspectPrim& p, const InspectNames& names);

/// The tree as indented text, every term with its formula and inputs, ending with the pixel's
/// value. Names from the scene (files, groups, materials) holding control bytes or bytes that
/// are not UTF-8 are quoted and escaped as the parser's messages do. Each ray level indents by
/// four spaces up to kMaxTextIndent; deeper rays are indented no further (their depth says
/// where they are). Written to `out` as it is made.
void inspect_text(std::ostream& out, const PixelTree& tree, const RenderScene& scene,
                  const InspectNames& names);
std::string inspect_text(const PixelTree& tree, const RenderScene& scene,
                         const InspectNames& names);
/// Where ray lines stop moving right: 16 levels of rays.
inline constexpr int kMaxTextIndent = 64;

/// The tree as JSON (docs/inspect.md gives the schema): strict UTF-8 (a byte that is not UTF-8
/// is written as U+FFFD, a control character as its escape), the rays a flat array, so that its
/// nesting is the same at any depth. Written to `out` as it is made.
void inspect_json(std::ostream& out, const PixelTree& tree, const RenderScene& scene,
                  const InspectNames& names);
std::string inspect_json(const PixelTree& tree, const RenderScene& scene,
                         const InspectNames& names);

}  // namespace rt
