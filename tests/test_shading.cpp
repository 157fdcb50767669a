// Lighting against the closed-form equations of spec §7 and §8: the two worked examples,
// lights, shadows through transparent occluders, mirror, glass, total internal reflection,
// depth and cutoff, textures.
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

}  // namespace
}  // namespace rt
