// Lighting against the closed-form equations of spec §7, §8 and §13.9: the three worked examples,
// lights, shadows through transparent occluders, mirror, glass, total internal reflection,
// depth and cutoff, textures, V3 three-colour and sphere lights.
#include <memory>

#include "rt/render/shading.h"
#include "test_util.h"

namespace rt {
namespace {

using test::compile;
using test::shade;

// The plane y = 0 as two large triangles.
const char* kPlane =
    "#vertex -100 0 -100 0 0 0 0 0\n#vertex -100 0 100 0 0 0 0 0\n#vertex 100 0 100 0 0 0 0 0\n"
    "#vertex 100 0 -100 0 0 0 0 0\n#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n";

TEST(Shading, WorkedExample1PointLightV1) {
    const RenderScene s = compile(
        "#ambient 0.5 0.5 0.5\n#background 0.2 0.2 0.2\n#light_point 1 1 1  5 5 5  0.01 0.02 0.03\n"
        "#material 0 0 0  .3 .3 .3  .1 .1 .5  1 1 1  100  0 0 0  1  -1 !!\n" +
        std::string(kPlane));
    const Vec3 c = shade(s, {{0, 10, 10}, glm::normalize(Vec3(3, -10, -4))});
    EXPECT_VEC_NEAR(c, Vec3(0.566933, 0.566933, 0.925082), 1e-6);
    EXPECT_EQ(to_byte(c.x), 145);
    EXPECT_EQ(to_byte(c.z), 236);
}

TEST(Shading, WorkedExample2SpotLightV0) {
    const RenderScene s = compile(
        "#ambient 0.5 0.5 0.5\n#light_spot 1 1 1  5 5 5  -2 -5 1  0.3 0.02 0  0.5 0.5\n"
        "#material 0.3 0.3 0.3  0.1 0.1 0.5  1 1 1  0 0 0  0.78125 0 1.05 -1 !!\n" +
        std::string(kPlane));
    const Vec3 inside = shade(s, {{0, 10, 10}, glm::normalize(Vec3(3, -10, -3))});
    EXPECT_VEC_NEAR(inside, Vec3(0.718841, 0.718841, 1.042928), 1e-6);
    EXPECT_EQ(to_byte(inside.x), 183);
    EXPECT_EQ(to_byte(inside.z), 255);
    const Vec3 outside = shade(s, {{0, 10, 10}, glm::normalize(Vec3(0, -10, -10))});
    EXPECT_VEC_NEAR(outside, Vec3(0.15), 1e-9);
    EXPECT_EQ(to_byte(outside.x), 38);
}

TEST(Shading, PointLightAttenuationOnAxis) {
    // Light on the view axis above a diffuse plane: kd * I / (ca + la d + qa d^2).
    const RenderScene s = compile(
        "#light_point 1 0.5 0.25  0 4 0  0.5 0.25 0.125\n"
        "#material 0 0 0  0 0 0  .8 .6 .4  0 0 0  1  0 0 0  1  -1 !!\n" +
        std::string(kPlane));
    const Vec3 c = shade(s, {{0, 10, 0}, {0, -1, 0}});
    const double att = 1.0 / (0.5 + 0.25 * 4 + 0.125 * 16);
    EXPECT_VEC_NEAR(c, Vec3(0.8 * 1, 0.6 * 0.5, 0.4 * 0.25) * att, 1e-12);
}

TEST(Shading, SpotLightJustInsideAndOutsideCutoffAndExponent) {
    const RenderScene s = compile(
        "#light_spot 1 1 1  0 1 0  0 -1 0  1 0 0  0.3 2\n"
        "#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0 0 0  1  -1 !!\n" +
        std::string(kPlane));
    auto at = [&](double angle) {
        const double x = std::tan(angle);
        return shade(s, {{x, 5, 0}, {0, -1, 0}}).x;
    };
    const double a = 0.29;
    const double dist = 1.0 / std::cos(a);
    // I = cos^p(a) / 1; N.L = cos(a); (V1: p = dor = 2). The light is at height 1.
    EXPECT_NEAR(at(a), std::pow(std::cos(a), 2) * std::cos(a), 1e-9);
    (void)dist;
    EXPECT_EQ(at(0.31), 0.0);
}

TEST(Shading, DirectionalAmbientAndEmissive) {
    const RenderScene s = compile(
        "#ambient 0.5 0.25 1\n#light_dir 1 1 1  -1 -1 0\n"
        "#material .1 .2 .3  .4 .4 .4  .5 .5 .5  0 0 0  1  0 0 0  1  -1 !!\n" +
        std::string(kPlane));
    const Vec3 c = shade(s, {{0, 10, 0}, {0, -1, 0}});
    const double ndl = 1 / std::sqrt(2.0);
    EXPECT_VEC_NEAR(c, Vec3(.1, .2, .3) + Vec3(.4) * Vec3(.5, .25, 1) + Vec3(.5) * ndl, 1e-12);
}

TEST(Shading, SpecularHighlightUsesMirrorDirection) {
    // Eye and light mirror each other about the normal: R_v . L = 1, spec = 1 for any exponent.
    const RenderScene s = compile(
        "#light_dir 1 1 1  -1 -1 0\n"
        "#material 0 0 0  0 0 0  0 0 0  .25 .5 .75  1000  0 0 0  1  -1 !!\n" +
        std::string(kPlane));
    const Vec3 c = shade(s, {{-5, 5, 0}, glm::normalize(Vec3(1, -1, 0))}, 1);
    EXPECT_VEC_NEAR(c, Vec3(.25, .5, .75), 1e-9);
}

// Plane lit from above by a point light with a sphere occluder of transparency T between.
std::string shadow_scene(const std::string& t) {
    return "#light_point 1 1 1  0 10 0  1 0 0\n"
           "#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0 0 0  1  -1 !!\n"
           "#material 0 0 0  0 0 0  0 0 0  0 0 0  1  " +
           t + "  1  -1 !!\n" + std::string(kPlane) + "#shape_sphere 1  0 5 0  1\n";
}

TEST(Shading, OpaqueAndTransparentShadows) {
    const Ray eye{{0, 1, 5}, glm::normalize(Vec3(0, -1, -5))};
    EXPECT_VEC_NEAR(shade(compile(shadow_scene("0 0 0")), eye), Vec3(0.0), 1e-12);
    // A closed transparent object counts twice: entry and exit.
    EXPECT_VEC_NEAR(shade(compile(shadow_scene("0.5 0.8 1")), eye), Vec3(0.25, 0.64, 1.0), 1e-12);
    // Shadows off: the light is always visible.
    EXPECT_VEC_NEAR(shade(compile(shadow_scene("0 0 0")), eye, 5, 0.001, false), Vec3(1.0), 1e-12);
}

TEST(Shading, MirrorReflectsBackgroundAndDepthStopsIt) {
    const RenderScene s = compile(
        "#background 0.3 0.6 0.9\n#material 0 0 0  0 0 0  0 0 0  1 1 1  1  0 0 0  1  -1 !!\n" +
        std::string(kPlane));
    const Ray r{{0, 5, 5}, glm::normalize(Vec3(0, -1, -1))};
    EXPECT_VEC_NEAR(shade(s, r, 2), Vec3(0.3, 0.6, 0.9), 1e-12);
    EXPECT_VEC_NEAR(shade(s, r, 1), Vec3(0.0), 1e-12);  // depth 1: no reflection
    // Cutoff: a weight of 0.5 is below a cutoff of 0.6; the skipped child adds nothing.
    const RenderScene half =
        compile("#background 1 1 1\n#material 0 0 0  0 0 0  0 0 0  .5 .5 .5  1  0 0 0  1  -1 !!\n" +
                std::string(kPlane));
    EXPECT_VEC_NEAR(shade(half, r, 5, 0.6), Vec3(0.0), 1e-12);
    EXPECT_VEC_NEAR(shade(half, r, 5, 0.5), Vec3(0.5), 1e-12);
}

TEST(Shading, MirrorBoxRecursionCountsBounces) {
    // Two parallel mirrors of weight 0.5 facing each other, emissive 1: each bounce adds 0.5^k.
    const RenderScene s = compile(
        "#material 1 1 1  0 0 0  0 0 0  .5 .5 .5  1  0 0 0  1  -1 !!\n"
        "#shape_box 0  0 0 -1  10 10 0.1\n#shape_box 0  0 0 1  10 10 0.1\n");
    const Ray r{{0, 0, 0}, {0, 0, -1}};
    for (int depth = 1; depth <= 6; ++depth) {
        double expected = 0;
        for (int k = 0; k < depth; ++k) expected += std::pow(0.5, k);
        EXPECT_NEAR(shade(s, r, depth, 0).x, expected, 1e-12) << depth;
    }
}

TEST(Shading, GlassSlabOfIndexOneIsInvisible) {
    const RenderScene s = compile(
        "#material 0 0 0  0 0 0  0 0 0  0 0 0  1  1 1 1  1  -1 !!\n"
        "#material .2 .4 .6  0 0 0  0 0 0  0 0 0  1  0 0 0  1  -1 !!\n"
        "#shape_box 0  0 0 0  4 4 0.5\n#shape_box 1  0 0 -5  10 10 0.1\n");
    const Ray r{{0.3, 0.2, 5}, glm::normalize(Vec3(-0.1, 0.05, -1))};
    EXPECT_VEC_NEAR(shade(s, r), Vec3(.2, .4, .6), 1e-12);
    EXPECT_VEC_NEAR(shade(s, r, 2), Vec3(0.0), 1e-12);  // depth 2 stops inside the slab
}

TEST(Shading, SnellRefractionAndTotalInternalReflection) {
    // A ray inside a box of index 1.5 meets its +y face from inside.
    const RenderScene s = compile(
        "#background 1 1 1\n#material 0 0 0  0 0 0  0 0 0  0 0 0  1  1 1 1  1.5  -1 !!\n"
        "#shape_box 0  0 0 0  100 2 100\n");
    auto from_inside = [&](double incidence) {
        return shade(s, {{0, 0, 0}, {std::sin(incidence), std::cos(incidence), 0}}).x;
    };
    EXPECT_NEAR(from_inside(kPi / 6), 1.0, 1e-12);  // 30 deg < critical 41.8 deg: escapes
    EXPECT_NEAR(from_inside(kPi / 3), 0.0, 1e-12);  // 60 deg: total internal reflection

    // Entering a slab (y in [-0.5, 0.5]) at 45 degrees: inside, sin(t) = sin(45)/1.5, so the
    // ray shifts along z by 1 - tan(t) against a straight line. Aim at a strip (half width 0.3)
    // at y = -3 through the refracted path; index 1 would miss it by 0.47.
    auto slab_scene = [](const char* index) {
        return compile(std::string("#material 0 0 0  0 0 0  0 0 0  0 0 0  1  1 1 1  ") + index +
                       "  -1 !!\n#material 1 1 1  0 0 0  0 0 0  0 0 0  1  0 0 0  1  -1 !!\n"
                       "#shape_box 0  0 0 0  100 1 100\n#shape_box 1  0 -3 -3  100 0.01 0.6\n");
    };
    const double tan_t = std::tan(std::asin(std::sin(kPi / 4) / 1.5));
    const Ray aimed{{0, 2.5, -3 + 4.5 + tan_t}, glm::normalize(Vec3(0, -1, -1))};
    EXPECT_NEAR(shade(slab_scene("1.5"), aimed).x, 1.0, 1e-12);
    EXPECT_NEAR(shade(slab_scene("1"), aimed).x, 0.0, 1e-12);
}

TEST(Textures, BilinearLookupOrientationAndWrap) {
    TextureImage t;
    t.width = 2;
    t.height = 2;
    // Row 0 (top): red, green; row 1 (bottom): blue, white.
    t.rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    EXPECT_VEC_NEAR(eval_texture(t, {0.25, 0.75}), Vec3(1, 0, 0), 1e-12);  // top-left texel
    EXPECT_VEC_NEAR(eval_texture(t, {0.75, 0.75}), Vec3(0, 1, 0), 1e-12);
    EXPECT_VEC_NEAR(eval_texture(t, {0.25, 0.25}), Vec3(0, 0, 1), 1e-12);  // v = 0 is the bottom
    EXPECT_VEC_NEAR(eval_texture(t, {0.5, 0.75}), Vec3(0.5, 0.5, 0), 1e-12);
    // Wrap: u = 1.25 equals 0.25; u = 0 blends the left and right columns.
    EXPECT_VEC_NEAR(eval_texture(t, {1.25, 0.75}), eval_texture(t, {0.25, 0.75}), 1e-12);
    EXPECT_VEC_NEAR(eval_texture(t, {-0.75, -0.25}), eval_texture(t, {0.25, 0.75}), 1e-12);
    EXPECT_VEC_NEAR(eval_texture(t, {0.0, 0.75}), Vec3(0.5, 0.5, 0), 1e-12);
}

TEST(Lights, DegenerateAttenuationContributesNothing) {
    Light l;
    l.kind = LightKind::Point;
    l.position = Vec3(0, 1, 0);
    l.constant_atten = l.linear_atten = l.quadratic_atten = 0;
    Vec3 i, dir;
    double dist = 0;
    EXPECT_FALSE(eval_light(l, Vec3(0), &i, &dir, &dist));
    l.constant_atten = 1;
    EXPECT_FALSE(eval_light(l, Vec3(0, 1, 0), &i, &dir, &dist));  // dist = 0
    l.constant_atten = -1;
    EXPECT_FALSE(eval_light(l, Vec3(0), &i, &dir, &dist));
}

// ---- V3 (spec §13.9). The V3 parser is not needed: V1 geometry is compiled and then given V3
// lights and the V3 texel rule, as compile_scene does for a V3 file.

Light v3_light(LightKind kind, const Vec3& a, const Vec3& d, const Vec3& sp, const Vec3& pos,
               const Vec3& atten = Vec3(1, 0, 0), double radius = 0.0) {
    Light l;
    l.kind = kind;
    l.ambient = a;
    l.diffuse = d;
    l.specular = sp;
    l.position = pos;
    l.constant_atten = atten.x;
    l.linear_atten = atten.y;
    l.quadratic_atten = atten.z;
    l.radius = radius;
    return l;
}

// A compiled V1 scene made V3: these lights, the texel on every term, no background or #ambient.
RenderScene as_v3(RenderScene scene, std::vector<Light> lights) {
    scene.lights = std::move(lights);
    scene.texture_all_terms = true;
    scene.background = Vec3(0.0);
    scene.ambient = Vec3(0.0);
    return scene;
}

// Worked example 3 (spec §13.10): the plane y = 0 (texture coordinates (0.5, 0.5) everywhere),
// the material and the light's colours given; textured: a 2x2 texture whose bilinear mean at
// (0.5, 0.5) is exactly t = (0.5, 1, 0.25).
RenderScene example3(const Vec3& a, const Vec3& d, const Vec3& sp, bool textured) {
    RenderScene s = as_v3(
        compile("#material 0.1 0.1 0.1  0.3 0.3 0.3  0.1 0.1 0.5  1 1 1  100  0 0 0  1  -1 !!\n"
                "#vertex -100 0 -100 0 0 0 .5 .5\n#vertex -100 0 100 0 0 0 .5 .5\n"
                "#vertex 100 0 100 0 0 0 .5 .5\n#vertex 100 0 -100 0 0 0 .5 .5\n"
                "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n"),
        {v3_light(LightKind::Point, a, d, sp, Vec3(5), Vec3(0.01, 0.02, 0.03))});
    if (a == Vec3(0.0) && d == Vec3(0.0) && sp == Vec3(0.0)) s.lights.clear();
    if (textured) {
        auto tex = std::make_shared<TextureImage>();
        tex->width = tex->height = 2;
        tex->rgb = {255, 255, 255, 255, 255, 0, 0, 255, 0, 0, 255, 0};
        s.textures.push_back(tex);
        s.materials[0].texture = 0;
    }
    return s;
}

const Ray kExample3Ray{{0, 10, 10}, glm::normalize(Vec3(3, -10, -4))};

TEST(V3Shading, WorkedExample3TermsAndPixelBytes) {
    const Vec3 a(0.5), d(1, 0.5, 1), sp(0.2, 0.4, 0.6), none(0.0);
    for (const bool textured : {false, true}) {
        SCOPED_TRACE(textured ? "textured" : "untextured");
        auto c = [&](const Vec3& la, const Vec3& ld, const Vec3& ls) {
            return shade(example3(la, ld, ls, textured), kExample3Ray);
        };
        const Vec3 emissive = textured ? Vec3(0.05, 0.1, 0.025) : Vec3(0.1);
        const Vec3 ambient = textured ? Vec3(0.073562, 0.147125, 0.036781) : Vec3(0.147125);
        const Vec3 diffuse =
            textured ? Vec3(0.044769, 0.044769, 0.111921) : Vec3(0.089537, 0.044769, 0.447686);
        const Vec3 specular =
            textured ? Vec3(0.012740, 0.050958, 0.019109) : Vec3(0.025479, 0.050958, 0.076438);
        EXPECT_VEC_NEAR(c(none, none, none), emissive, 1e-6);
        EXPECT_VEC_NEAR(c(a, none, none) - emissive, ambient, 1e-6);
        EXPECT_VEC_NEAR(c(none, d, none) - emissive, diffuse, 1e-6);
        EXPECT_VEC_NEAR(c(none, none, sp) - emissive, specular, 1e-6);
        const Vec3 total = c(a, d, sp);
        EXPECT_VEC_NEAR(
            total,
            textured ? Vec3(0.181070, 0.342851, 0.192812) : Vec3(0.362141, 0.342851, 0.771248),
            1e-6);
        // The pixel through P of a one-pixel render, as bytes (spec §9).
        RenderScene scene = example3(a, d, sp, textured);
        scene.camera = CameraPose{kExample3Ray.o, kExample3Ray.d, {0, 1, 0}, 0.1};
        const std::vector<uint8_t> bytes = to_bytes(test::render(scene, 1, 1));
        const std::vector<uint8_t> expected =
            textured ? std::vector<uint8_t>{46, 87, 49} : std::vector<uint8_t>{92, 87, 197};
        EXPECT_EQ(bytes, expected);
    }
}

TEST(V3Shading, V1TexelRuleLeavesEmissiveAndSpecularUntextured) {
    // The same scene under the V0/V1 rule: the texel multiplies K_A and K_D only.
    RenderScene s = example3(Vec3(0.0), Vec3(0.0), Vec3(0.2, 0.4, 0.6), true);
    s.texture_all_terms = false;
    EXPECT_VEC_NEAR(shade(s, kExample3Ray), Vec3(0.1) + Vec3(0.025479, 0.050958, 0.076438), 1e-6);
}

TEST(V3Shading, AmbientIsAttenuatedSpotLimitedAndNeverShadowed) {
    // A light below the plane (N.L < 0 for the eye's side) and behind an opaque box still adds
    // its attenuated ambient term; a spot light adds none outside its cut-off.
    RenderScene s = as_v3(compile("#material 0 0 0  .5 .5 .5  1 1 1  0 0 0  1  0 0 0  1  -1 !!\n" +
                                  std::string(kPlane) + "#shape_box 0  0 -2 0  1 1 1\n"),
                          {v3_light(LightKind::Point, Vec3(1, 0.5, 0.25), Vec3(1), Vec3(1),
                                    Vec3(0, -4, 0), Vec3(0.5, 0.25, 0))});
    const Ray down{{0, 5, 0}, {0, -1, 0}};
    EXPECT_VEC_NEAR(shade(s, down), Vec3(0.5, 0.25, 0.125) / (0.5 + 0.25 * 4), 1e-12);
    Light spot = v3_light(LightKind::Spot, Vec3(1), Vec3(0.0), Vec3(0.0), Vec3(0, 4, 0));
    spot.direction = Vec3(0, -1, 0);
    spot.cutoff_rad = 0.3;
    spot.spot_exponent = 2;
    s.lights = {spot};
    const double inside = std::pow(std::cos(0.2), 2) / 1.0;  // f = cos^p, attenuation 1
    EXPECT_NEAR(shade(s, {{4 * std::tan(0.2), 5, 0}, {0, -1, 0}}).x, 0.5 * inside, 1e-12);
    EXPECT_EQ(shade(s, {{4 * std::tan(0.4), 5, 0}, {0, -1, 0}}).x, 0.0);
    // f = 0 (all coefficients zero): no ambient either.
    s.lights = {v3_light(LightKind::Point, Vec3(1), Vec3(1), Vec3(1), Vec3(0, 4, 0), Vec3(0.0))};
    EXPECT_EQ(shade(s, down), Vec3(0.0));
}

// The floor y = 0 (white, diffuse only) under a sphere light at (0, 5, 0) of radius 1 (diffuse
// colour 1, no attenuation) and, when `wall` is given, the plane x = 0 of transparency `wall`.
RenderScene sphere_light_scene(const std::string& wall, double radius = 1.0) {
    std::string text = "#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0 0 0  1  -1 !!\n";
    if (!wall.empty()) text += "#material 0 0 0  0 0 0  0 0 0  0 0 0  1  " + wall + "  1  -1 !!\n";
    text +=
        "#vertex -100 0 -100 0 0 0 0 0\n#vertex -100 0 100 0 0 0 0 0\n"
        "#vertex 100 0 100 0 0 0 0 0\n#vertex 100 0 -100 0 0 0 0 0\n"
        "#vertex 0 -100 -100 0 0 0 0 0\n#vertex 0 -100 100 0 0 0 0 0\n"
        "#vertex 0 100 100 0 0 0 0 0\n#vertex 0 100 -100 0 0 0 0 0\n"
        "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n";
    if (!wall.empty()) text += "#shape_triangle 1 4 5 6\n#shape_triangle 1 4 6 7\n";
    return as_v3(compile(text), {v3_light(LightKind::Sphere, Vec3(0.0), Vec3(1), Vec3(0.0),
                                          Vec3(0, 5, 0), Vec3(1, 0, 0), radius)});
}

const Ray kFloorRay{{3, 1, 1}, glm::normalize(Vec3(0, -1, -1))};  // hits (3, 0, 0)

TEST(SphereLights, UnobstructedGivesOneAndAPlaneThroughTheCentreOneHalf) {
    // L, f and N.L from the centre: N.L = 5 / sqrt(34).
    const double free = 5 / std::sqrt(34.0);
    EXPECT_NEAR(shade(sphere_light_scene(""), kFloorRay).x, free, 1e-12);
    EXPECT_NEAR(shade(sphere_light_scene("0 0 0"), kFloorRay).x, 0.5 * free, 1e-12);
    // A wall of transparency 0.5: half the points seen through it.
    EXPECT_NEAR(shade(sphere_light_scene("0.5 0.5 0.5"), kFloorRay).x, 0.75 * free, 1e-12);
    // Shadows off: S_l = 1.
    EXPECT_NEAR(shade(sphere_light_scene("0 0 0"), kFloorRay, 5, 0.001, false).x, free, 1e-12);
}

TEST(SphereLights, UnobstructedEqualsThePointLightAtTheCentre) {
    RenderScene s = sphere_light_scene("");
    s.lights[0].ambient = Vec3(0.1);
    s.lights[0].specular = Vec3(0.3, 0.2, 0.1);
    s.materials[0].ambient = Vec3(0.5);
    s.materials[0].specular = Vec3(1);
    s.materials[0].specular_exponent = 3;
    const Vec3 sphere = shade(s, kFloorRay, 1);
    s.lights[0].kind = LightKind::Point;
    EXPECT_EQ(sphere, shade(s, kFloorRay, 1));
    EXPECT_GT(sphere.x, sphere.z);  // the highlight's colour, red over blue
}

// The plane lit by a sphere light at (0, 10, 0) of radius `radius` past an opaque ball at
// (0, 5, 0) of radius 1 (shadow_scene's geometry); the light's colours are V3 ones.
RenderScene penumbra_scene(double radius, LightKind kind = LightKind::Sphere) {
    RenderScene s = as_v3(
        compile(shadow_scene("0 0 0")),
        {v3_light(kind, Vec3(0.1), Vec3(1), Vec3(0.5), Vec3(0, 10, 0), Vec3(1, 0, 0), radius)});
    s.camera = CameraPose{{0, 8, 8}, {0, -1, -1}, {0, 1, 0}, 0.4};
    return s;
}

TEST(SphereLights, RadiusZeroActsAsAPointLight) {
    const RenderScene sphere = penumbra_scene(0.0);
    const RenderScene point = penumbra_scene(0.0, LightKind::Point);
    const Image a = test::render(sphere, 24, 18), b = test::render(point, 24, 18);
    EXPECT_EQ(a.rgb, b.rgb);
    // A radius softens the shadow's edge: some pixel changes.
    EXPECT_NE(test::render(penumbra_scene(1.0), 24, 18).rgb, b.rgb);
}

// The diffuse shade at a floor point of penumbra_scene(2) seen from straight above.
Vec3 penumbra_shade(const RenderSettings& s, Rng* rng, double x = 1.2) {
    const RenderScene scene = penumbra_scene(2.0);
    RayCounters c;
    return trace_ray(scene, make_render_plan(scene, s), s, {{x, 1, 0}, {0, -1, 0}}, 1, Vec3(1.0), c,
                     rng);
}

TEST(SphereLights, SinglePassUsesTheSameStrataCentresEverywhere) {
    RenderSettings s;
    const Vec3 a = penumbra_shade(s, nullptr);
    EXPECT_EQ(a, penumbra_shade(s, nullptr));  // deterministic
    // In the penumbra: neither the unshadowed value nor zero.
    const double free = penumbra_shade(s, nullptr, 4.0).x;
    EXPECT_GT(a.x, 0.05);
    EXPECT_LT(a.x, 0.95 * free);
    // The count of points changes the estimate. One point: the centre of the one stratum,
    // xi = (0.5, 0.5): z = 0, angle pi, w = (-1, 0, 0).
    s.light_samples = 16;
    EXPECT_NE(penumbra_shade(s, nullptr), a);
    s.light_samples = 1;
    const RenderPlan plan = make_render_plan(penumbra_scene(2.0), s);
    ASSERT_EQ(plan.sphere_points.size(), 1u);
    EXPECT_VEC_NEAR(plan.sphere_points[0], Vec3(-1, 0, 0), 1e-15);
}

TEST(SphereLights, RandomEstimatesConvergeToTheSinglePassValue) {
    RenderSettings s;
    s.light_samples = 4096;  // 64 x 64 strata centres: the reference
    const double reference = penumbra_shade(s, nullptr).x;
    // Progressive passes (no centre-first sampling): one uniform point per sample; supersampled
    // renders: the 16 strata jittered.
    for (const bool progressive : {true, false}) {
        SCOPED_TRACE(progressive ? "progressive" : "supersampled");
        RenderSettings r;
        r.centre_first_sample = !progressive;
        r.light_samples = 16;
        const int n = progressive ? 20000 : 2000;
        double sum = 0, sum_sq = 0;
        for (int i = 0; i < n; ++i) {
            Rng rng(7, 0, static_cast<uint64_t>(i));
            const double v = penumbra_shade(r, &rng).x;
            sum += v;
            sum_sq += v * v;
        }
        const double mean = sum / n;
        const double se = std::sqrt(std::max(0.0, sum_sq / n - mean * mean) / n);
        EXPECT_GT(se, 0.0);  // random indeed
        EXPECT_NEAR(mean, reference, 4 * se + 2e-4);
    }
}

}  // namespace
}  // namespace rt
