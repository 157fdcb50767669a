// compile_scene(): resolved materials and textures, flattened groups, one set per included file,
// nested instancing composed, statistics after instancing; what compile_scene_releasing frees.
#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "rt/accel/intersect.h"
#include "test_util.h"

namespace rt {
namespace {

TEST(Compile, MaterialsAndV0Default) {
    CompileReport report;
    const RenderScene s = compile_scene(
        test::parse("#material .1 .1 .1  .5 .5 .5  .2 .2 .2  0 0 0  .5 .25 1.5 -1 !!\n"
                    "#shape_sphere -1 0 0 0 1\n#shape_sphere 0 3 0 0 1\n"),
        &report);
    ASSERT_EQ(s.sets.size(), 1u);
    const GeometrySet& set = s.sets[0];
    const Material& def = s.materials[static_cast<size_t>(set.prims[0].material)];
    EXPECT_EQ(def.diffuse, Vec3(.8));
    EXPECT_EQ(def.specular_exponent, 128);
    EXPECT_EQ(s.materials[static_cast<size_t>(set.prims[1].material)].diffuse, Vec3(.5));
    EXPECT_EQ(report.materials, 1u);
}

TEST(Compile, GroupsFlattenAndTrianglesMoveToTheSetFrame) {
    const RenderScene s = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#vertex 0 0 0 0 0 1 0 0\n#vertex 1 0 0 0 0 1 0 0\n#vertex 0 1 0 0 0 1 0 0\n"
        "#group_begin 1 0 0 10  0 1 0 0  0 0 1 0  0 0 0 1\n"
        "#group_begin 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1\n"
        "#shape_triangle 0 0 1 2\n#shape_sphere 0 0 0 0 1\n#shape_box 0 0 0 0 1 1 1\n"
        "#group_end\n#group_end\n");
    const GeometrySet& set = s.sets[0];
    EXPECT_EQ(set.triangle(0).p1, Vec3(12, 0, 0));
    EXPECT_EQ(set.transforms.size(), 1u);  // one cached transform shared by the group's shapes
    EXPECT_EQ(set.transforms[0].inv[3][0], -5.0);
    EXPECT_EQ(s.instances.size(), 1u);
    EXPECT_TRUE(s.instances[0].identity);
}

// Spec §5 and §4.1: n_s = normalize(sum w_i n_i) in the triangle's local frame, then mapped by
// (A^-1)^T and renormalised. Under a non-uniform scale, renormalising each corner's normal after
// the map (as the compile once did) changes the weights and the normal by about 2 degrees here.
TEST(Compile, ShadingNormalInterpolatedInTheLocalFrameUnderANonUniformScale) {
    // The file's normals; the parser normalises each when it reads it (spec §3).
    const Vec3 file_n[3] = {{1, 0, 1}, {0, 1, 1}, {-1, -1, 1}};
    const Vec3 n[3] = {glm::normalize(file_n[0]), glm::normalize(file_n[1]),
                       glm::normalize(file_n[2])};
    std::string text = "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n";
    const Vec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (int k = 0; k < 3; ++k)
        text += "#vertex " + std::to_string(p[k].x) + " " + std::to_string(p[k].y) + " 0 " +
                std::to_string(file_n[k].x) + " " + std::to_string(file_n[k].y) + " " +
                std::to_string(file_n[k].z) + " 0 0\n";
    // x scaled by 8, z by 0.5: the normal matrix scales x by 1/8 and z by 2.
    text +=
        "#group_begin 8 0 0 0  0 1 0 0  0 0 0.5 0  0 0 0 1\n#shape_triangle 0 0 1 2\n"
        "#group_end\n";
    const RenderScene s = test::compile(text);
    const double w1 = 0.25, w2 = 0.5, w0 = 1 - w1 - w2;  // the hit's barycentrics
    const Vec3 local = w0 * p[0] + w1 * p[1] + w2 * p[2];
    const Ray ray{Vec3(8 * local.x, local.y, 5), Vec3(0, 0, -1)};
    Hit hit;
    ASSERT_TRUE(intersect(s, ray, {0, kInf}, &hit));
    const SurfaceInteraction si = interaction(s, ray, hit, true);
    const Vec3 n_local = glm::normalize(w0 * n[0] + w1 * n[1] + w2 * n[2]);
    const Vec3 expected = glm::normalize(Vec3(n_local.x / 8, n_local.y, n_local.z * 2));
    EXPECT_NEAR(glm::length(si.n_shading - expected), 0.0, 1e-12)
        << si.n_shading.x << " " << si.n_shading.y << " " << si.n_shading.z;
    // The old rule's answer is far off: the test tells the two apart.
    Vec3 old(0.0);
    for (int k = 0; k < 3; ++k)
        old += (k == 0   ? w0
                : k == 1 ? w1
                         : w2) *
               glm::normalize(Vec3(n[k].x / 8, n[k].y, n[k].z * 2));
    EXPECT_GT(glm::length(glm::normalize(old) - expected), 1e-3);
}

TEST(Compile, IncludedFileCompiledOnceAndNestedInstancesCompose) {
    const auto dir = std::filesystem::temp_directory_path() / "rt_compile_nested";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "leaf.ray") << "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
                                       "#shape_sphere 0 0 0 0 1\n";
    std::ofstream(dir / "mid.ray") << "#ray_file leaf.ray\n"
                                      "#group_begin 1 0 0 5  0 1 0 0  0 0 1 0  0 0 0 1\n"
                                      "#ray_file_instance 0\n#group_end\n#ray_file_instance 0\n";
    std::ofstream(dir / "top.ray") << "#ray_file mid.ray\n#ray_file leaf.ray\n"
                                      "#group_begin 1 0 0 0  0 1 0 0  0 0 1 100  0 0 0 1\n"
                                      "#ray_file_instance 0\n#group_end\n#ray_file_instance 0\n"
                                      "#ray_file_instance 1\n";
    Diagnostics diag;
    CompileReport report;
    const RenderScene s =
        compile_scene(parse_scene_file((dir / "top.ray").string(), diag), &report);
    EXPECT_EQ(s.sets.size(), 1u);       // only leaf.ray has shapes
    EXPECT_EQ(s.instances.size(), 5u);  // 2 via mid (twice) + 1 direct
    EXPECT_EQ(report.prims_by_kind[0], 5u);
    EXPECT_EQ(report.unique_prims, 1u);
    EXPECT_EQ(report.instances, 5u);
    Hit h;
    // The instance at (5, 0, 100): mid's translated leaf under top's z translation.
    ASSERT_TRUE(intersect(s, {{5, 0, 110}, {0, 0, -1}}, {0, kInf}, &h));
    EXPECT_NEAR(h.t, 9, 1e-12);
    std::filesystem::remove_all(dir);
}

// CompileProgress: three units per shape, all done at the end; a cancelled compile stops at its
// first check with an error at the file.
TEST(Compile, ReportsItsProgressAndStopsWhenCancelled) {
    const SceneDesc desc = test::parse(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#shape_sphere 0 0 0 0 1\n#shape_box 0 0 0 0 1 1 1\n"
        "#group_begin 1 0 0 5  0 1 0 0  0 0 1 0  0 0 0 1\n#shape_sphere 0 0 0 0 1\n#group_end\n");
    CompileProgress progress;
    std::atomic<bool> cancel{false};
    progress.cancel = &cancel;
    const RenderScene s = compile_scene(desc, nullptr, std::nullopt, nullptr, 0, &progress);
    EXPECT_EQ(s.sets.size(), 1u);
    EXPECT_EQ(progress.total.load(), 9u);
    EXPECT_EQ(progress.done.load(), 9u);

    CompileProgress stopped;
    cancel = true;
    stopped.cancel = &cancel;
    try {
        compile_scene(desc, nullptr, std::nullopt, nullptr, 0, &stopped);
        ADD_FAILURE() << "a cancelled compile finished";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("loading cancelled"), std::string::npos) << e.what();
    }
    EXPECT_LT(stopped.done.load(), stopped.total.load());
}

// compile_scene_releasing() frees the meshes it compiled (groups of triangles only, and every
// file's vertices) and makes the same scene; a group that mixes kinds keeps its shapes.
TEST(Compile, AReleasingCompileFreesTheMeshesAndRendersTheSame) {
    const auto dir = std::filesystem::temp_directory_path() / "rt_compile_release";
    std::filesystem::create_directories(dir);
    const std::string material =
        "#material 0 0 0  .1 .1 .1  .8 .6 .4  .5 .5 .5  20  0 0 0  1 -1 !!\n";
    const std::string corners =
        "#vertex -1 -1 0  0 0 1  0 0\n#vertex 1 -1 0  0 0 1  1 0\n#vertex 0 1 0  0 0 1  0 1\n";
    std::ofstream(dir / "part.ray") << material << corners << "#shape_triangle 0 0 1 2\n";
    std::ofstream(dir / "top.ray")
        << "#camera 0 0 8  0 0 -1  0 1 0  0.6\n#light_point 1 1 1  0 3 5  1 0 0\n"
        << material << corners
        << "#ray_file part.ray\n#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 1\n"
        << "#group_begin 1 0 0 2  0 1 0 0  0 0 1 0  0 0 0 1\n#shape_triangle 0 0 1 2\n"
        << "#shape_sphere 0 0 0 -1 0.5\n#group_end\n"
        << "#group_begin 1 0 0 -2  0 1 0 0  0 0 1 0  0 0 0 1\n#ray_file_instance 0\n#group_end\n";
    Diagnostics diag;
    const std::string top = (dir / "top.ray").string();
    const SceneDesc kept = parse_scene_file(top, diag);
    SceneDesc freed = parse_scene_file(top, diag);
    const Image expected = test::render(compile_scene(kept), 40, 30);
    const Image image = test::render(compile_scene_releasing(freed), 40, 30);
    EXPECT_EQ(image.rgb, expected.rgb);
    EXPECT_TRUE(std::any_of(image.rgb.begin(), image.rgb.end(),  // the triangles are in view
                            [&](const auto& v) { return v != image.rgb[0]; }));
    ASSERT_EQ(freed.files.size(), 2u);
    EXPECT_TRUE(freed.files[0].root.shapes.empty());
    EXPECT_TRUE(freed.files[0].vertices.empty());
    EXPECT_EQ(freed.files[0].root.groups[0].shapes.size(), 2u);  // a triangle and a sphere
    EXPECT_TRUE(freed.files[1].root.shapes.empty());
    EXPECT_TRUE(freed.files[1].vertices.empty());
    EXPECT_EQ(freed.lights.size(), kept.lights.size());
    std::filesystem::remove_all(dir);
}

// What a later compile reads is kept: a file instanced inside a CSG tree (and placed on its own
// too), and everything when the scene has animation tracks or locations are recorded.
TEST(Compile, AReleasingCompileKeepsWhatIsReadAgain) {
    SceneDesc d;
    d.dialect = Dialect::V3;
    for (const double z : {0.0, -4.0}) {
        FileDesc f;
        f.path = z == 0 ? "top.ray" : "part.ray";
        f.materials.emplace_back();
        f.vertices = {VertexDesc{{-1, -1, z}}, VertexDesc{{1, -1, z}}, VertexDesc{{0, 1, z}}};
        f.root.shapes = {ShapeDesc{{}, 0, TriangleDesc{{0, 1, 2}}}};
        d.files.push_back(f);
    }
    d.files[0].ray_files = {1};
    GroupDesc operand, moved;
    operand.instances = {InstanceDesc{{}, 0}};
    moved.matrix = glm::translate(Mat4(1.0), Vec3(5, 0, 0));
    moved.instances = {InstanceDesc{{}, 0}};
    CsgDesc u;
    u.op = CsgOp::Union;
    u.operands = {operand};
    d.files[0].root.csgs = {u};
    d.files[0].root.groups = {moved};
    SceneDesc freed = d;
    const RenderScene s = compile_scene_releasing(freed);
    EXPECT_TRUE(freed.files[0].root.shapes.empty());
    EXPECT_EQ(freed.files[1].root.shapes.size(), 1u);  // read by the CSG tree's set
    EXPECT_EQ(freed.files[1].vertices.size(), 3u);
    Hit h;
    ASSERT_TRUE(intersect(s, {{0, 0, -4.5}, {0, 0, 1}}, {0, kInf}, &h));  // the CSG's triangle
    EXPECT_NEAR(h.t, 0.5, 1e-12);
    ASSERT_TRUE(intersect(s, {{5, 0, -4.5}, {0, 0, 1}}, {0, kInf}, &h));  // the one placed
    EXPECT_NEAR(h.t, 0.5, 1e-12);

    SceneDesc animated = d;
    animated.tracks.emplace_back();
    compile_scene_releasing(animated);
    EXPECT_EQ(animated.files[0].root.shapes.size(), 1u);
    SceneDesc located = d;
    CompileReport report;
    report.record_locations = true;
    compile_scene_releasing(located, &report);
    EXPECT_EQ(located.files[0].root.shapes.size(), 1u);
    EXPECT_EQ(located.files[0].vertices.size(), 3u);
}

TEST(Compile, WorldBoundsCoverEveryInstance) {
    const RenderScene s = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#shape_sphere 0 -5 0 0 1\n#shape_box 0 5 0 0 2 2 2\n");
    EXPECT_NEAR(s.world_bounds.lo.x, -6, 1e-12);
    EXPECT_NEAR(s.world_bounds.hi.x, 6, 1e-12);
}

}  // namespace
}  // namespace rt

namespace rt {
namespace {

// The viewer points at the directive of a picked primitive.
TEST(Compile, RecordsWhereEachPrimitiveWasRead) {
    Diagnostics diag;
    const SceneDesc d = parse_scene_string(
        "#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0 0 0  1  -1 !chalk!\n"
        "#shape_sphere 0  0 0 0  1\n"
        "\n"
        "#shape_box 0  3 0 0  1 1 1\n",
        "picked.ray", diag);
    CompileReport report;
    report.record_locations = true;
    const RenderScene scene = compile_scene(d, &report);
    ASSERT_EQ(report.prim_locs.size(), scene.sets.size());
    const GeometrySet& set = scene.sets[0];
    ASSERT_EQ(report.prim_locs[0].size(), set.prims.size());
    for (size_t i = 0; i < set.prims.size(); ++i) {
        const int line = set.prims[i].kind == ShapeKind::Sphere ? 2 : 4;
        EXPECT_EQ(report.prim_locs[0][i].line, line);
        EXPECT_EQ(report.prim_locs[0][i].str().substr(0, 12), "picked.ray:" + std::to_string(line));
    }
    ASSERT_EQ(report.material_names.size(), scene.materials.size());
    EXPECT_EQ(report.material_names[0], "chalk");
    CompileReport plain;
    compile_scene(d, &plain);
    EXPECT_TRUE(plain.prim_locs.empty());  // only when asked
}

// A description's light, material and camera are the render's with a location (and a name):
// the compile takes them as they are, makes directions unit, keeps the file's texture index for
// the caller to renumber.
TEST(Compile, TakesTheLightMaterialAndCameraOfTheDescriptionAsTheyAre) {
    LightDesc spot;
    spot.kind = LightKind::Spot;
    spot.set_colour(Vec3(0.5, 0.25, 1));
    spot.position = Vec3(1, 2, 3);
    spot.direction = Vec3(0, 0, -2);
    spot.linear_atten = 0.5;
    spot.cutoff_rad = 0.3;
    spot.spot_exponent = 7;
    Light expected = spot;
    expected.direction = Vec3(0, 0, -1);
    EXPECT_EQ(compile_light(spot), expected);
    LightDesc point = spot;
    point.kind = LightKind::Point;
    EXPECT_EQ(compile_light(point).direction, Light{}.direction);  // a point has none

    MaterialDesc md;
    md.name = "glass";
    md.texture = 2;
    md.diffuse = Vec3(0.1, 0.2, 0.3);
    md.refractive_index = 1.5;
    const Material m = compile_material(md, MaterialOrigin{1, 0, 4, 3});
    EXPECT_EQ(m.diffuse, md.diffuse);
    EXPECT_EQ(m.refractive_index, 1.5);
    EXPECT_EQ(m.texture, 6);  // the file's third texture, after the 4 of the files before
    EXPECT_EQ(compile_material(md, MaterialOrigin{1, 0, 4, 2}).texture, -1);  // not its file's

    CameraDesc c;
    c.position = Vec3(1, 2, 3);
    c.half_height_angle_rad = 0.4;
    const CameraPose pose = compile_camera(c);
    EXPECT_EQ(pose.position, c.position);
    EXPECT_EQ(pose.direction, c.direction);
    EXPECT_EQ(pose.half_height_angle_rad, 0.4);
}

// One rule for a light with one colour (spec §7.1): no ambient, diffuse = specular, and never a
// sphere light (V3's, shaded by §13.9 with its shadow over the sphere).
TEST(Compile, OneColourLightsAreThoseOfSpec71AndNeverSpheres) {
    Light l;
    EXPECT_TRUE(l.one_colour());
    l.set_colour(Vec3(0.5));
    EXPECT_TRUE(l.one_colour());
    l.specular = Vec3(0.25);
    EXPECT_FALSE(l.one_colour());
    l.set_colour(Vec3(0.5));
    l.ambient = Vec3(0.1);
    EXPECT_FALSE(l.one_colour());
    l.set_colour(Vec3(0.5));
    l.kind = LightKind::Sphere;
    EXPECT_FALSE(l.one_colour());
}

}  // namespace
}  // namespace rt
