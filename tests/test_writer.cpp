// The scene writer: parse, write, parse again gives the same description (both dialects, every
// directive of the top-level file), and edits of the camera and lights survive the round trip.
#include <filesystem>

#include "rt/format/writer.h"
#include "test_util.h"

namespace rt {
namespace {

void expect_same_group(const GroupDesc& a, const GroupDesc& b) {
    EXPECT_EQ(a.matrix, b.matrix);
    ASSERT_EQ(a.shapes.size(), b.shapes.size());
    for (size_t i = 0; i < a.shapes.size(); ++i) {
        EXPECT_EQ(a.shapes[i].material, b.shapes[i].material);
        EXPECT_EQ(a.shapes[i].geometry.index(), b.shapes[i].geometry.index());
        EXPECT_TRUE(a.shapes[i].geometry == b.shapes[i].geometry) << "shape " << i;
    }
    ASSERT_EQ(a.instances.size(), b.instances.size());
    for (size_t i = 0; i < a.instances.size(); ++i)
        EXPECT_EQ(a.instances[i].ray_file, b.instances[i].ray_file);
    ASSERT_EQ(a.groups.size(), b.groups.size());
    for (size_t i = 0; i < a.groups.size(); ++i) expect_same_group(a.groups[i], b.groups[i]);
}

void expect_same(const SceneDesc& a, const SceneDesc& b) {
    EXPECT_EQ(a.dialect, b.dialect);
    ASSERT_EQ(a.camera.has_value(), b.camera.has_value());
    if (a.camera) {
        EXPECT_EQ(a.camera->position, b.camera->position);
        EXPECT_EQ(a.camera->direction, b.camera->direction);
        EXPECT_EQ(a.camera->up, b.camera->up);
        EXPECT_EQ(a.camera->half_height_angle_rad, b.camera->half_height_angle_rad);
    }
    EXPECT_EQ(a.background, b.background);
    EXPECT_EQ(a.ambient, b.ambient);
    ASSERT_EQ(a.lights.size(), b.lights.size());
    for (size_t i = 0; i < a.lights.size(); ++i) {
        const LightDesc &x = a.lights[i], &y = b.lights[i];
        EXPECT_EQ(x.kind, y.kind);
        EXPECT_EQ(x.ambient, y.ambient);
        EXPECT_EQ(x.diffuse, y.diffuse);
        EXPECT_EQ(x.specular, y.specular);
        EXPECT_EQ(x.radius, y.radius);
        EXPECT_EQ(x.position, y.position);
        EXPECT_EQ(x.direction, y.direction);
        EXPECT_EQ(x.constant_atten, y.constant_atten);
        EXPECT_EQ(x.linear_atten, y.linear_atten);
        EXPECT_EQ(x.quadratic_atten, y.quadratic_atten);
        EXPECT_EQ(x.cutoff_rad, y.cutoff_rad);
        EXPECT_EQ(x.spot_exponent, y.spot_exponent);
    }
    const FileDesc &fa = a.files[0], &fb = b.files[0];
    ASSERT_EQ(fa.materials.size(), fb.materials.size());
    for (size_t i = 0; i < fa.materials.size(); ++i) {
        const MaterialDesc &x = fa.materials[i], &y = fb.materials[i];
        EXPECT_EQ(x.emissive, y.emissive);
        EXPECT_EQ(x.ambient, y.ambient);
        EXPECT_EQ(x.diffuse, y.diffuse);
        EXPECT_EQ(x.specular, y.specular);
        EXPECT_EQ(x.specular_exponent, y.specular_exponent);
        EXPECT_EQ(x.transparent, y.transparent);
        EXPECT_EQ(x.refractive_index, y.refractive_index);
        EXPECT_EQ(x.texture, y.texture);
        EXPECT_EQ(x.name, y.name);
    }
    ASSERT_EQ(fa.vertices.size(), fb.vertices.size());
    for (size_t i = 0; i < fa.vertices.size(); ++i) {
        EXPECT_EQ(fa.vertices[i].position, fb.vertices[i].position);
        // Normals are normalised when read; a unit normal read again moves by an ulp at most.
        EXPECT_VEC_NEAR(fa.vertices[i].normal, fb.vertices[i].normal, 1e-15);
        EXPECT_EQ(fa.vertices[i].uv, fb.vertices[i].uv);
    }
    ASSERT_EQ(fa.textures.size(), fb.textures.size());
    ASSERT_EQ(fa.ray_files.size(), fb.ray_files.size());
    expect_same_group(fa.root, fb.root);
}

TEST(Writer, OurScenesRoundTrip) {
    const std::filesystem::path dir = std::filesystem::path(RT_SOURCE_DIR) / "scenes";
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().extension() != ".ray") continue;
        Diagnostics d1, d2;
        const SceneDesc a = parse_scene_file(e.path().string(), d1);
        const std::string text = write_scene(a);
        const SceneDesc b = parse_scene_string(text, "written.ray", d2, {}, dir.string());
        SCOPED_TRACE(e.path().string());
        expect_same(a, b);
        ++n;
    }
    EXPECT_GE(n, 7);
}

TEST(Writer, V0AndEditsRoundTrip) {
    SceneDesc a = test::parse(
        "#camera 0 1 5 0 0 -1 0 1 0 0.3\n#ambient 0.1 0.2 0.3\n"
        "#light_spot 1 1 1  5 5 5  -2 -5 1  0.3 0.02 0  0.5 0.5\n"
        "#material .1 .2 .3  .4 .5 .6  .7 .8 .9  0 0 0  0.78125 0.25 1.5 -1 !glass and !\n"
        "#vertex 0 0 0 0 0 3 0.125 1e-7\n#vertex 1 0 0 0 0 0 1 0\n#vertex 0 1 0 0 0 0 0 1\n"
        "#group_begin 0.5 0 0 1  0 2 0 2  0 0 1 3  0 0 0 1\n"
        "#shape_triangle 0 0 1 2\n#shape_sphere -1 0 0 0 0.3333333333333333\n#group_end\n");
    ASSERT_EQ(a.dialect, Dialect::V0);
    // The viewer's edits: camera and lights.
    a.camera->position = Vec3(0.1, 2.0 / 3.0, 7);
    a.lights[0].set_colour(Vec3(0.5, 0.25, 1e-3));
    LightDesc p;
    p.kind = LightKind::Point;
    p.position = Vec3(1, 2, 3);
    p.linear_atten = 0.1;
    a.lights.push_back(p);
    Diagnostics d;
    const SceneDesc b = parse_scene_string(write_scene(a), "written.ray", d);
    expect_same(a, b);
}

}  // namespace
}  // namespace rt
