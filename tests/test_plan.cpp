// The render plan: the features are read from values, not syntax, the plan leaves out what the
// scene does not need, and the specialized renderer gives the generic renderer's image, bit for
// bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "render/variants.h"
#include "test_util.h"

namespace rt {
namespace {

const char* kDiffuse = "#material 0 0 0  .1 .1 .1  .7 .7 .7  0 0 0  1  0 0 0  1  -1 !d!\n";

SceneFeatures features_of(const std::string& text, int depth = 5, bool shadows = true) {
    RenderSettings s;
    s.max_depth = depth;
    s.shadows = shadows;
    return scene_features(test::compile(text), s);
}

bool has_line(const std::vector<std::string>& lines, const std::string& text) {
    return std::find(lines.begin(), lines.end(), text) != lines.end();
}

// The --explain lines of a scene's features.
std::vector<std::string> explain_lines(const SceneFeatures& f) {
    std::vector<std::string> out;
    for (const PlanReason& r : explain_features(f)) out.push_back(reason_line(r));
    return out;
}

TEST(Features, ReadFromValuesNotSyntax) {
    // A specular colour of zero reflects nothing; a transparent colour of zero lets nothing
    // through; a light of colour zero lights nothing.
    const SceneFeatures f =
        features_of(std::string("#light_point 0 0 0  0 5 0  1 0 0\n#light_dir 1 1 1  0 -1 0\n") +
                    kDiffuse + "#shape_sphere 0 0 0 0 1\n");
    EXPECT_EQ(f.lights[static_cast<int>(LightKind::Directional)], 1);
    EXPECT_EQ(f.lights[static_cast<int>(LightKind::Point)], 0);
    EXPECT_EQ(f.dark_lights, 1);
    EXPECT_FALSE(f.reflection);
    EXPECT_FALSE(f.refraction);
    EXPECT_FALSE(f.highlights);
    EXPECT_FALSE(f.textures);
    EXPECT_TRUE(f.shadows);
    EXPECT_FALSE(f.transmissive_shadows);
    EXPECT_FALSE(f.geometry.instancing);
    EXPECT_EQ(f.geometry.prims[static_cast<int>(ShapeKind::Sphere)], 1u);
    EXPECT_EQ(f.shade_variant(), static_cast<uint32_t>(kShadeShadows));
    const auto lines = explain_lines(f);
    EXPECT_TRUE(has_line(lines, "left out: refraction: no transparent material"));
    EXPECT_TRUE(has_line(lines, "left out: reflection: no material with a specular colour"));
    EXPECT_TRUE(
        has_line(lines, "left out: 1 light(s): colour zero or all attenuation coefficients zero"));
    EXPECT_TRUE(has_line(lines, "left out: spot cut-off and drop-off: no spot light"));
    // The geometry variant: one sphere, no transform.
    EXPECT_TRUE(
        has_line(lines, "left out: top-level BVH: one instance: rays walk its BVH directly"));
    EXPECT_TRUE(has_line(lines,
                         "left out: transforms: no group or instance transform: rays are "
                         "never transformed"));
    EXPECT_TRUE(
        has_line(lines, "left out: triangle tests: no triangles: no triangle set-up per ray"));
    EXPECT_TRUE(has_line(lines, "left out: torus test: no torus: no quartic is solved"));
    EXPECT_TRUE(
        has_line(explain_lines(features_of(std::string("#light_dir 0 0 0  1 1 1  1 1 1  0 -1 0\n") +
                                           kDiffuse + "#shape_torus 0 0 0 0 0.25 1\n")),
                 "kept: torus test: 1 torus primitive(s): quartics solved (spec §13.7)"));
    EXPECT_TRUE(has_line(
        lines, "left out: shape dispatch: spheres only: leaves call the sphere test directly"));
    EXPECT_TRUE(has_line(explain_lines(features_of("#light_dir 1 1 1  0 -1 0\n")),
                         "left out: ray queries: the scene has no shapes, every ray sees the "
                         "background"));
    for (const std::string& l : lines)
        EXPECT_TRUE(l.rfind("left out: ", 0) == 0 || l.rfind("kept: ", 0) == 0) << l;
}

TEST(Features, OnlyMaterialsThatArePlacedCount) {
    // A glass material that no shape uses does not switch refraction on; a used one does.
    const std::string glass =
        "#material 0 0 0  0 0 0  0 0 0  .5 .5 .5  50  .9 .9 .9  1.5  -1 !g!\n";
    const std::string light = "#light_point 1 1 1  0 5 0  1 0 0\n";
    SceneFeatures f = features_of(light + kDiffuse + glass + "#shape_sphere 0 0 0 0 1\n");
    EXPECT_FALSE(f.refraction);
    EXPECT_FALSE(f.reflection);
    f = features_of(light + kDiffuse + glass + "#shape_sphere 1 0 0 0 1\n");
    EXPECT_TRUE(f.refraction);
    EXPECT_TRUE(f.reflection);
    EXPECT_TRUE(f.transmissive_shadows);
    EXPECT_TRUE(f.highlights);
    // Depth 1: no child rays at all.
    f = features_of(light + kDiffuse + glass + "#shape_sphere 1 0 0 0 1\n", 1);
    EXPECT_FALSE(f.refraction);
    EXPECT_FALSE(f.reflection);
    EXPECT_TRUE(has_line(explain_lines(f), "left out: refraction: recursion depth 1"));
    // Shadows switched off: no shadow rays, hence no transparent shadows either.
    f = features_of(light + kDiffuse + glass + "#shape_sphere 1 0 0 0 1\n", 5, false);
    EXPECT_FALSE(f.shadows);
    EXPECT_FALSE(f.transmissive_shadows);
    // All attenuation coefficients zero: the point light lights nothing.
    f = features_of(std::string("#light_point 1 1 1  0 5 0  0 0 0\n") + kDiffuse +
                    "#shape_sphere 0 0 0 0 1\n");
    EXPECT_EQ(f.dark_lights, 1);
    EXPECT_FALSE(f.shadows);
    EXPECT_TRUE(has_line(explain_lines(f), "left out: shadow rays: no light lights anything"));
}

TEST(Features, TransformsAndScale) {
    const std::string head = std::string("#light_dir 1 1 1  0 -1 0\n") + kDiffuse;
    SceneFeatures f = features_of(head +
                                  "#group_begin 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1\n"
                                  "#shape_sphere 0 0 0 0 1\n#group_end\n");
    EXPECT_TRUE(f.geometry.transforms);
    EXPECT_FALSE(f.geometry.nonuniform_scale);
    f = features_of(head +
                    "#group_begin 1 0 0 0  0 3 0 0  0 0 1 0  0 0 0 1\n"
                    "#shape_sphere 0 0 0 0 1\n#group_end\n");
    EXPECT_TRUE(f.geometry.nonuniform_scale);
}

TEST(Plan, ChoosesTheVariantAndTheLightsThatLight) {
    const RenderScene scene = test::compile(
        std::string("#light_point 0 0 0  0 5 0  1 0 0\n#light_dir 1 1 1  0 -1 0\n") +
        "#light_point 1 1 1  0 5 0  1 0 0\n" + kDiffuse + "#shape_sphere 0 0 0 0 1\n");
    RenderSettings s;
    const RenderPlan special = make_render_plan(scene, s);
    EXPECT_TRUE(special.specialized);
    ASSERT_EQ(special.lights.size(), 2u);  // the dark point light is left out
    EXPECT_EQ(special.lights[0].kind, LightKind::Directional);
    EXPECT_EQ(special.lights[1].diffuse, Vec3(1.0));
    EXPECT_EQ(special.shading, &shading_variant(kShadeShadows | kShadeAttenuation));
    EXPECT_EQ(special.geometry, &geometry_queries(read_geometry(scene).variant));
    EXPECT_NE(special.geometry, &geometry_queries(kGeomGeneric));
    // Soft shadows draw random samples per light: every light stays, the generic shading runs.
    s.light_radius = 0.2;
    const RenderPlan soft = make_render_plan(scene, s);
    EXPECT_EQ(soft.lights.size(), 3u);
    EXPECT_EQ(soft.shading->trace, shading_variant(kShadeAll).trace);  // compiled once
    // --no-specialize: every light, the generic shading and walk; the same reasons.
    s.light_radius = 0;
    s.specialize = false;
    const RenderPlan generic = make_render_plan(scene, s);
    EXPECT_FALSE(generic.specialized);
    EXPECT_EQ(generic.lights.size(), 3u);
    EXPECT_EQ(generic.shading, &shading_variant(kShadeAll));
    EXPECT_EQ(generic.geometry, &geometry_queries(kGeomGeneric));
    ASSERT_EQ(generic.reasons.size(), special.reasons.size());
    for (size_t i = 0; i < generic.reasons.size(); ++i)
        EXPECT_EQ(reason_line(generic.reasons[i]), reason_line(special.reasons[i]));
}

TEST(Plan, UsesSayWhatThePreviewCompilesFor) {
    // A dark spot light lights nothing: its kind is not used; a textured material is not used
    // when nothing placed has it; shadows need a light that lights.
    const std::string lights =
        "#light_spot 0 0 0  0 5 0  0 -1 0  1 0 0  0.5 1\n#light_point 1 1 1  0 5 0  1 0 0\n";
    const std::string unused =
        "#texture " + std::string(RT_SOURCE_DIR) + "/scenes/textures/checker.bmp\n" + kDiffuse +
        "#material 0 0 0  .1 .1 .1  .7 .7 .7  .5 .5 .5  9  0 0 0  1  0 !t!\n";
    RenderSettings s;
    const RenderPlan p =
        make_render_plan(test::compile(lights + unused + "#shape_sphere 0 0 0 0 1\n"), s);
    EXPECT_TRUE(p.uses.light_kinds[static_cast<int>(LightKind::Point)]);
    EXPECT_FALSE(p.uses.light_kinds[static_cast<int>(LightKind::Spot)]);
    EXPECT_FALSE(p.uses.light_kinds[static_cast<int>(LightKind::Directional)]);
    EXPECT_FALSE(p.uses.textures);
    EXPECT_FALSE(p.uses.highlights);
    EXPECT_TRUE(p.uses.shadows);
    s.shadows = false;
    EXPECT_FALSE(make_render_plan(test::compile(lights + unused + "#shape_sphere 0 0 0 0 1\n"), s)
                     .uses.shadows);
}

TEST(Plan, ReasonsAreDataThatFormatAsExplainLines) {
    EXPECT_EQ(reason_line({"shadow rays", true, "1 light(s) that light something"}),
              "kept: shadow rays: 1 light(s) that light something");
    EXPECT_EQ(reason_line({"reflection", false, "recursion depth 1"}),
              "left out: reflection: recursion depth 1");
    const RenderScene scene = test::compile(std::string("#light_dir 1 1 1  0 -1 0\n") + kDiffuse +
                                            "#shape_sphere 0 0 0 0 1\n");
    RenderSettings s;
    s.max_depth = 1;
    const RenderPlan plan = make_render_plan(scene, s);
    const auto refl = std::find_if(plan.reasons.begin(), plan.reasons.end(),
                                   [](const PlanReason& r) { return r.feature == "reflection"; });
    ASSERT_NE(refl, plan.reasons.end());
    EXPECT_FALSE(refl->kept);
    EXPECT_EQ(refl->why, "recursion depth 1");
    EXPECT_EQ(explain_lines(scene_features(scene, s)).size(), plan.reasons.size());
}

TEST(Plan, ResolvesTheCameraAndTheFocusDistance) {
    // No camera in the file: the default camera of spec §6.3 at the settings' aspect ratio.
    const RenderScene scene = test::compile(std::string("#light_dir 1 1 1  0 -1 0\n") + kDiffuse +
                                            "#shape_sphere 0 0 0 -5 1\n");
    ASSERT_FALSE(scene.camera);
    RenderSettings s;
    s.width = 100;
    s.height = 400;
    const RenderPlan tall = make_render_plan(scene, s);
    EXPECT_VEC_NEAR(tall.camera.position, default_camera(scene.world_bounds, 100, 400).position,
                    1e-12);
    EXPECT_EQ(tall.camera.width, 100);
    s.width = 640;
    s.height = 480;
    const RenderPlan wide = make_render_plan(scene, s);
    EXPECT_GT(tall.camera.position.z, wide.camera.position.z + 0.5);  // further back when narrow
    // The focus plane: the scene's centre unless the settings name one.
    EXPECT_NEAR(wide.focus_distance, wide.camera.position.z + 5.0, 1e-9);
    s.focus_distance = 3.5;
    EXPECT_EQ(make_render_plan(scene, s).focus_distance, 3.5);
    // A camera in the file is compiled once into a pose the plan frames.
    const RenderScene placed = test::compile(std::string("#camera 1 2 3  0 0 -1  0 1 0  0.5\n") +
                                             kDiffuse + "#shape_sphere 0 0 0 0 1\n");
    ASSERT_TRUE(placed.camera);
    EXPECT_EQ(make_render_plan(placed, s).camera.position, Vec3(1, 2, 3));
}

// Scenes that switch features on one at a time and all at once: the specialized and the generic
// renderer give identical images.
TEST(Plan, SpecializedImagesEqualGenericImages) {
    const std::string shapes =
        "#vertex -2 -0.5 1  0 0 0  0 0\n#vertex 2 -0.5 1  0 0 0  1 0\n"
        "#vertex 0 1 1.5  0 0 0  .5 1\n"
        "#shape_box 0  0 -1 0  8 0.2 8\n#shape_sphere 1  -1 0 0  0.8\n"
        "#shape_cylinder 0  1 0 0  0.5 1\n#shape_cone 1  0 0 -1.5  0.5 1\n"
        "#shape_triangle 1  0 1 2\n";
    const std::string cam = "#camera 0 2 7  0 -0.3 -1  0 1 0  0.5\n#ambient .2 .2 .2\n";
    const std::string point = "#light_point 1 1 1  2 4 3  1 0 0.01\n";
    const std::string spot = "#light_spot 1 .9 .8  -2 4 2  0.4 -1 -0.4  1 0 0  0.6 3\n";
    const std::string dir = "#light_dir .5 .5 .5  -1 -1 -1\n";
    const std::string dark = "#light_point 0 0 0  0 3 0  1 0 0\n";
    const std::string diffuse = "#material 0 0 0  .1 .1 .1  .7 .6 .5  0 0 0  1  0 0 0  1  -1 !a!\n";
    const std::string shiny =
        "#material 0 0 0  .1 .1 .1  .5 .5 .5  .5 .5 .5  40  0 0 0  1  -1 !b!\n";
    const std::string glass =
        "#material 0 0 0  0 0 0  .1 .1 .1  .2 .2 .2  80  .8 .8 .8  1.4  -1 !c!\n";
    const std::string textured = "#texture " + std::string(RT_SOURCE_DIR) +
                                 "/scenes/textures/checker.bmp\n"
                                 "#material 0 0 0  .2 .2 .2  .8 .8 .8  0 0 0  1  0 0 0  1  0 !t!\n";
    // The geometry variants: one kind (spheres), packed triangles, a transformed include placed
    // once (top-level box test) and three times beside the top file's own shapes (the layout
    // picked per set), no shapes at all.
    const std::string balls =
        "#shape_sphere 0  -1 0 0  0.8\n#shape_sphere 1  1 0.2 0  0.6\n"
        "#shape_sphere 0  0 -101 0  100\n";
    const std::string pyramid =
        "#vertex -3 -1 -3  0 0 0  0 0\n#vertex 3 -1 -3  0 0 0  1 0\n#vertex 3 -1 3  0 0 0  1 1\n"
        "#vertex -3 -1 3  0 0 0  0 1\n#vertex 0 1.5 0  0 0 0  .5 .5\n";
    const std::string faces =
        "#shape_triangle 0  0 2 1\n#shape_triangle 0  0 3 2\n#shape_triangle 1  0 1 4\n"
        "#shape_triangle 1  1 2 4\n#shape_triangle 0  2 3 4\n#shape_triangle 1  3 0 4\n";
    const std::string mesh = pyramid + faces;
    // The same pyramid again, 1e-7 higher, in the other material: z-fighting triangles.
    const std::string zfight =
        pyramid +
        "#vertex -3 -0.9999999 -3  0 0 0  0 0\n#vertex 3 -0.9999999 -3  0 0 0  1 0\n"
        "#vertex 3 -0.9999999 3  0 0 0  1 1\n#vertex -3 -0.9999999 3  0 0 0  0 1\n"
        "#vertex 0 1.5000001 0  0 0 0  .5 .5\n" +
        faces +
        "#shape_triangle 1  5 7 6\n#shape_triangle 1  5 8 7\n#shape_triangle 0  5 6 9\n"
        "#shape_triangle 0  6 7 9\n#shape_triangle 1  7 8 9\n#shape_triangle 0  8 5 9\n";
    const std::string part =
        (std::filesystem::path(::testing::TempDir()) / "rt_features_part.ray").string();
    { std::ofstream(part) << diffuse << shiny << balls; }
    auto placed = [](double x, double s) {
        return "#group_begin " + std::to_string(s) + " 0 0 " + std::to_string(x) + "  0 " +
               std::to_string(s) + " 0 0  0 0 " + std::to_string(s) +
               " 0  0 0 0 1\n#ray_file_instance 0\n#group_end\n";
    };
    const std::string include = "#ray_file " + part + "\n";
    constexpr uint32_t kAnyWalk = ~0u;
    const struct {
        std::string name, text;
        uint32_t geom = kAnyWalk;  // the geometry variant expected
    } scenes[] = {
        {"spheres only", cam + dir + diffuse + shiny + balls, geom_layout_bits(SetLayout::Spheres)},
        {"triangles only", cam + point + diffuse + glass + mesh,
         geom_layout_bits(SetLayout::Triangles)},
        {"z-fighting triangles", cam + point + diffuse + shiny + zfight,
         geom_layout_bits(SetLayout::Triangles)},
        {"one transformed instance", cam + point + include + placed(0.5, 0.7),
         kGeomInstancing | kGeomTransforms | geom_layout_bits(SetLayout::Spheres)},
        {"instances beside shapes",
         cam + spot + dir + include + diffuse + glass + mesh + placed(-2, 0.5) + placed(0, 0.6) +
             placed(2, 0.5),
         kGeomInstancing | kGeomTransforms | kGeomPerSet},
        {"no shapes", cam + point, kGeomEmpty},
        {"diffuse, one point light", cam + point + diffuse + diffuse + shapes},
        {"dark light only", cam + dark + diffuse + diffuse + shapes},
        {"directional", cam + dir + diffuse + diffuse + shapes},
        {"spot", cam + spot + diffuse + diffuse + shapes},
        {"highlights and mirrors", cam + point + dir + diffuse + shiny + shapes},
        {"glass", cam + point + diffuse + glass + shapes},
        {"textures", cam + spot + textured + diffuse + shapes},
        {"everything", cam + point + spot + dir + dark + textured + glass + shapes},
    };
    for (const auto& sc : scenes) {
        SCOPED_TRACE(sc.name);
        RenderScene scene;
        ASSERT_NO_THROW(scene = test::compile(sc.text)) << sc.text;
        // The walk each of the geometry scenes is there for.
        if (sc.geom != kAnyWalk) {
            EXPECT_EQ(read_geometry(scene).variant, sc.geom);
        }
        for (int variant = 0; variant < 3; ++variant) {
            RenderSettings s;
            s.width = 48;
            s.height = 36;
            s.threads = 2;
            s.shadows = variant != 1;
            s.max_depth = variant == 2 ? 1 : 5;
            RenderState a, b;
            s.specialize = false;
            test::render_samples(a, scene, s, 1);
            s.specialize = true;
            test::render_samples(b, scene, s, 1);
            EXPECT_EQ(a.image().rgb, b.image().rgb) << sc.name << ", settings " << variant;
            // Not a blank image (equal blanks would prove nothing), except without shapes.
            const auto [lo, hi] = std::minmax_element(b.sum.begin(), b.sum.end());
            EXPECT_EQ(*lo < *hi, sc.name != "no shapes");
        }
        // The stochastic features take the generic path: still equal, shadows on and off (sphere
        // lights move the light point either way).
        for (const bool shadows : {true, false}) {
            RenderSettings s;
            s.width = 24;
            s.height = 18;
            s.light_radius = 0.3;
            s.shadows = shadows;
            s.centre_first_sample = false;
            RenderState a, b;
            s.specialize = false;
            test::render_samples(a, scene, s, 2);
            s.specialize = true;
            test::render_samples(b, scene, s, 2);
            EXPECT_EQ(a.image().rgb, b.image().rgb) << sc.name << ", soft, shadows " << shadows;
        }
        RenderSettings s;
        s.width = 24;
        s.height = 18;
        s.light_radius = 0.3;
        s.roughness = 0.2;
        s.centre_first_sample = false;
        RenderState a, b;
        s.specialize = false;
        test::render_samples(a, scene, s, 2);
        s.specialize = true;
        test::render_samples(b, scene, s, 2);
        EXPECT_EQ(a.image().rgb, b.image().rgb) << sc.name << ", stochastic";
    }
}

// ---- V3 lights (spec §13.9), given to compiled V1 geometry as compile_scene gives a V3 file's.

Light v3_light(LightKind kind, const Vec3& ambient, const Vec3& diffuse, const Vec3& specular,
               const Vec3& position, double radius = 0.0) {
    Light l;
    l.kind = kind;
    l.ambient = ambient;
    l.diffuse = diffuse;
    l.specular = specular;
    l.position = position;
    l.direction = glm::normalize(Vec3(-1, -2, -1));
    l.radius = radius;
    return l;
}

RenderScene with_lights(RenderScene scene, std::vector<Light> lights) {
    scene.lights = std::move(lights);
    scene.texture_all_terms = true;
    scene.ambient = Vec3(0.0);
    return scene;
}

TEST(Features, V3LightsSwitchTheirCodeOnlyWhenTheyAddSomething) {
    const std::string no_ka = "#material 0 0 0  0 0 0  .7 .7 .7  0 0 0  1  0 0 0  1  -1 !d!\n";
    const RenderScene plain = test::compile(no_ka + "#shape_sphere 0 0 0 0 1\n");
    const RenderScene with_ka = test::compile(std::string(kDiffuse) + "#shape_sphere 0 0 0 0 1\n");
    RenderSettings s;
    // A V1 scene: none of it.
    SceneFeatures f = features_of(std::string("#light_point 1 1 1  0 5 0  1 0 0\n") + kDiffuse +
                                  "#shape_sphere 0 0 0 0 1\n");
    EXPECT_EQ(f.shade_variant() & kShadeV3Lights, 0u);
    auto lines = explain_lines(f);
    EXPECT_TRUE(has_line(lines, "left out: sphere light sampling: no sphere light"));
    EXPECT_TRUE(has_line(lines, "left out: light ambient terms: no light has an ambient colour"));
    EXPECT_TRUE(has_line(lines,
                         "left out: light specular colours: every light's specular colour is "
                         "its diffuse colour"));
    // A light's ambient colour that meets no ambient material colour adds nothing.
    const Light ambient = v3_light(LightKind::Point, Vec3(0.2), Vec3(1), Vec3(1), Vec3(0, 5, 0));
    f = scene_features(with_lights(plain, {ambient}), s);
    EXPECT_EQ(f.shade_variant() & kShadeV3Lights, 0u);
    EXPECT_TRUE(has_line(explain_lines(f),
                         "left out: light ambient terms: no material with an ambient colour"));
    f = scene_features(with_lights(with_ka, {ambient}), s);
    EXPECT_NE(f.shade_variant() & kShadeV3Lights, 0u);
    EXPECT_TRUE(
        has_line(explain_lines(f), "kept: light ambient terms: 1 light(s) with an ambient colour"));
    // A specular colour of its own.
    f = scene_features(with_lights(plain, {v3_light(LightKind::Directional, Vec3(0.0), Vec3(1),
                                                    Vec3(0.5), Vec3(0.0))}),
                       s);
    EXPECT_EQ(f.specular_colour_lights, 1);
    EXPECT_NE(f.shade_variant() & kShadeV3Lights, 0u);
    EXPECT_EQ(f.shade_variant() & kShadeAttenuation, 0u);
    // A sphere light: attenuated, sampled while there are shadow rays.
    const Light sphere = v3_light(LightKind::Sphere, Vec3(0.0), Vec3(1), Vec3(1), Vec3(0, 5, 0), 1);
    f = scene_features(with_lights(plain, {sphere}), s);
    EXPECT_EQ(f.lights[static_cast<int>(LightKind::Sphere)], 1);
    EXPECT_NE(f.shade_variant() & kShadeV3Lights, 0u);
    EXPECT_NE(f.shade_variant() & kShadeAttenuation, 0u);
    lines = explain_lines(f);
    EXPECT_TRUE(has_line(lines,
                         "kept: sphere light sampling: 1 sphere light(s): shadow rays to 64 "
                         "point(s) on each (--light-samples; progressive: one random point a "
                         "sample)"));
    EXPECT_TRUE(has_line(lines, "kept: light attenuation: 1 point, spot or sphere light(s)"));
    s.shadows = false;
    EXPECT_TRUE(has_line(explain_lines(scene_features(with_lights(plain, {sphere}), s)),
                         "left out: sphere light sampling: no shadow rays"));
}

TEST(Plan, SphereLightsGetTheStrataCentresOfTheSinglePass) {
    const RenderScene plain = test::compile(std::string(kDiffuse) + "#shape_sphere 0 0 0 0 1\n");
    RenderSettings s;
    s.light_samples = 5;  // m = 3: the first 5 of 9 strata, row-major
    const Light sphere = v3_light(LightKind::Sphere, Vec3(0.0), Vec3(1), Vec3(1), Vec3(0, 5, 0), 1);
    const RenderPlan plan = make_render_plan(with_lights(plain, {sphere}), s);
    EXPECT_TRUE(plan.uses.light_kinds[static_cast<int>(LightKind::Sphere)]);
    ASSERT_EQ(plan.sphere_points.size(), 5u);
    EXPECT_EQ(plan.light_samples, 5);
    auto w = [](double x1, double x2) {
        const double z = 1 - 2 * x1, r = std::sqrt(1 - z * z);
        return Vec3(r * std::cos(2 * kPi * x2), z, r * std::sin(2 * kPi * x2));
    };
    EXPECT_VEC_NEAR(plan.sphere_points[0], w(1.0 / 6, 1.0 / 6), 1e-15);
    EXPECT_VEC_NEAR(plan.sphere_points[1], w(3.0 / 6, 1.0 / 6), 1e-15);
    EXPECT_VEC_NEAR(plan.sphere_points[3], w(1.0 / 6, 3.0 / 6), 1e-15);
    for (const Vec3& p : plan.sphere_points) EXPECT_NEAR(glm::length(p), 1.0, 1e-15);
    // No sphere light (or one of radius 0): no points.
    EXPECT_TRUE(make_render_plan(plain, s).sphere_points.empty());
    Light point_like = sphere;
    point_like.radius = 0;
    EXPECT_TRUE(make_render_plan(with_lights(plain, {point_like}), s).sphere_points.empty());
    // V3 lights keep textures, highlights and every light kind: one instance for all of them.
    const uint32_t v = kShadeShadows | kShadeV3Lights;
    EXPECT_EQ(shading_variant(v).trace,
              shading_variant(v | kShadeTextures | kShadeHighlights | kShadeSpot).trace);
}

// V3 lights and the V3 texel rule on the feature scenes: the specialized and the generic renderer
// give identical images, in a single pass, supersampled, progressive and with the stochastic
// features.
TEST(Plan, SpecializedImagesEqualGenericImagesWithV3Lights) {
    const std::string text =
        "#camera 0 2 7  0 -0.3 -1  0 1 0  0.5\n"
        "#texture " +
        std::string(RT_SOURCE_DIR) +
        "/scenes/textures/checker.bmp\n"
        "#material .05 0 0  .1 .1 .1  .7 .6 .5  0 0 0  1  0 0 0  1  -1 !a!\n"
        "#material 0 0 0  .1 .1 .1  .5 .5 .5  .5 .5 .5  40  0 0 0  1  -1 !b!\n"
        "#material 0 0 0  0 0 0  .1 .1 .1  .2 .2 .2  80  .8 .8 .8  1.4  -1 !c!\n"
        "#material .1 .1 .1  .2 .2 .2  .8 .8 .8  .3 .3 .3  9  0 0 0  1  0 !t!\n"
        "#shape_box 3  0 -1 0  8 0.2 8\n#shape_sphere 1  -1 0 0  0.8\n"
        "#shape_cylinder 2  1 0 0  0.5 1\n#shape_cone 0  0 0 -1.5  0.5 1\n";
    const RenderScene base = test::compile(text);
    Light spot = v3_light(LightKind::Spot, Vec3(0.1), Vec3(1, .9, .8), Vec3(.3), Vec3(-2, 4, 2));
    spot.direction = glm::normalize(Vec3(0.4, -1, -0.4));
    spot.cutoff_rad = 0.6;
    spot.spot_exponent = 3;
    const struct {
        const char* name;
        std::vector<Light> lights;
    } cases[] = {
        {"sphere light", {v3_light(LightKind::Sphere, Vec3(0.0), Vec3(1), Vec3(1), {2, 4, 3}, 1)}},
        {"ambient and specular colours",
         {v3_light(LightKind::Point, Vec3(0.2), Vec3(1, .5, .2), Vec3(.2, .5, 1), {2, 4, 3}),
          v3_light(LightKind::Directional, Vec3(0.1), Vec3(.5), Vec3(.5), {0, 0, 0})}},
        {"every kind",
         {v3_light(LightKind::Sphere, Vec3(0.1), Vec3(1), Vec3(.5), {2, 4, 3}, 0.5), spot,
          v3_light(LightKind::Point, Vec3(0.0), Vec3(.5), Vec3(.5), {-2, 3, 3}),
          v3_light(LightKind::Sphere, Vec3(0.0), Vec3(0.0), Vec3(0.0), {0, 3, 0}, 1)}},
    };
    for (const auto& c : cases) {
        const RenderScene scene = with_lights(base, c.lights);
        for (int mode = 0; mode < 5; ++mode) {
            SCOPED_TRACE(std::string(c.name) + ", mode " + std::to_string(mode));
            RenderSettings s;
            s.width = 24;
            s.height = 18;
            s.threads = 2;
            s.light_samples = 9;
            s.shadows = mode != 1;
            int spp = 1;
            if (mode == 2) spp = 3;                                           // supersampled
            if (mode == 3) spp = 2, s.centre_first_sample = false;            // progressive
            if (mode == 4) spp = 2, s.light_radius = 0.3, s.roughness = 0.1;  // stochastic
            RenderState a, b;
            s.specialize = false;
            test::render_samples(a, scene, s, spp);
            s.specialize = true;
            test::render_samples(b, scene, s, spp);
            EXPECT_EQ(a.image().rgb, b.image().rgb);
            const auto [lo, hi] = std::minmax_element(b.sum.begin(), b.sum.end());
            EXPECT_LT(*lo, *hi);
        }
    }
}

}  // namespace
}  // namespace rt
