// The scene writer: parse, write, parse again gives the same description (every dialect, every
// directive of the top-level file), and edits of the camera and lights survive the round trip.
// V3 (spec §13): the exact directive sequences of descriptions built here, and the round trip of
// a rich V3 text and of the public V3 scenes.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "rt/format/writer.h"
#include "rt/util/file_io.h"
#include "test_util.h"

namespace rt {
namespace {

void expect_same_group(const GroupDesc& a, const GroupDesc& b);

void expect_same_csg(const CsgDesc& a, const CsgDesc& b) {
    EXPECT_EQ(a.op, b.op);
    ASSERT_EQ(a.operands.size(), b.operands.size());
    for (size_t i = 0; i < a.operands.size(); ++i) {
        SCOPED_TRACE("operand " + std::to_string(i));
        expect_same_group(a.operands[i], b.operands[i]);
    }
}

void expect_same_group(const GroupDesc& a, const GroupDesc& b) {
    EXPECT_EQ(a.matrix, b.matrix);
    EXPECT_EQ(a.joint, b.joint);
    EXPECT_EQ(a.track, b.track);
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
    ASSERT_EQ(a.csgs.size(), b.csgs.size());
    for (size_t i = 0; i < a.csgs.size(); ++i) expect_same_csg(a.csgs[i], b.csgs[i]);
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
    EXPECT_EQ(a.shader_vertex, b.shader_vertex);
    EXPECT_EQ(a.shader_fragment, b.shader_fragment);
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
    ASSERT_EQ(fa.key_files.size(), fb.key_files.size());
    // The joints stay joints, bound to the same keys (V1 and V3 alike).
    ASSERT_EQ(a.tracks.size(), b.tracks.size());
    for (size_t i = 0; i < a.tracks.size(); ++i) {
        EXPECT_EQ(a.tracks[i].name, b.tracks[i].name);
        EXPECT_EQ(a.tracks[i].keys, b.tracks[i].keys);
    }
    ASSERT_EQ(a.files.size(), b.files.size());
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

// Saved next to a file, paths are relative to its directory (once: the viewer wrote
// absolute paths), and the saved file reads back with the same textures and includes.
TEST(Writer, PathsRelativeToTheSavedFile) {
    const std::filesystem::path dir = std::filesystem::path(RT_SOURCE_DIR) / "scenes";
    Diagnostics d1, d2;
    const SceneDesc shapes = parse_scene_file((dir / "shapes.ray").string(), d1);
    const std::string here = write_scene_for(shapes, (dir / "edited.ray").string());
    EXPECT_NE(here.find("#texture textures/grid.png"), std::string::npos) << here;
    const SceneDesc groups = parse_scene_file((dir / "groups.ray").string(), d1);
    const std::string below = write_scene_for(groups, (dir / "parts" / "edited.ray").string());
    EXPECT_NE(below.find("#ray_file floor.ray"), std::string::npos) << below;
    EXPECT_NE(below.find("#ray_file pawn.ray"), std::string::npos) << below;
    // Elsewhere: a relative path that still reaches the file.
    const std::filesystem::path out = std::filesystem::path(::testing::TempDir()) / "rt_rel";
    std::filesystem::create_directories(out);
    const std::string saved = (out / "shapes_edited.ray").string();
    write_file_atomic(saved, write_scene_for(shapes, saved));
    std::string text;
    ASSERT_TRUE(read_file(saved, &text));
    EXPECT_EQ(text.find("#texture /"), std::string::npos) << text;
    const SceneDesc back = parse_scene_file(saved, d2);
    expect_same(shapes, back);
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

// An edited material replaced in a file's text: that directive (its numbers and !name!)
// becomes the writer's, every other byte stays, and the result parses to the edit.
TEST(Writer, ReplacesAMaterialInPlace) {
    const std::string text =
        "// a part\n#material 0 0 0  .1 .1 .1  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !dull!  // old\n"
        "  #material 0 0 0  .2 .2 .2  .5 .5 .5  0 0 0\n    1  0 0 0  1  -1 !two lines!\n"
        "#shape_sphere 1 0 0 0 1\n";
    SceneDesc a = test::parse(text);
    ASSERT_EQ(a.files[0].materials.size(), 2u);
    MaterialDesc m = a.files[0].materials[1];
    m.diffuse = Vec3(0.25, 0.5, 0.75);
    m.specular_exponent = 12;
    const std::string patched =
        replace_materials(text, "part.ray", {{m.loc, write_material(m, a.dialect)}});
    EXPECT_EQ(patched.substr(0, text.find("  #material")),
              text.substr(0, text.find("  #material")));
    EXPECT_NE(patched.find("  #material 0 0 0 0.2 0.2 0.2 0.25 0.5 0.75"), std::string::npos)
        << patched;
    EXPECT_NE(patched.find("!two lines!\n#shape_sphere 1 0 0 0 1\n"), std::string::npos) << patched;
    Diagnostics d;
    const SceneDesc b = parse_scene_string(patched, "part.ray", d);
    ASSERT_EQ(b.files[0].materials.size(), 2u);
    EXPECT_EQ(b.files[0].materials[1].diffuse, Vec3(0.25, 0.5, 0.75));
    EXPECT_EQ(b.files[0].materials[1].specular_exponent, 12.0);
    EXPECT_EQ(b.files[0].materials[0].diffuse, Vec3(0.8));  // not edited
    // V0: kspec = e / 128 and one transparency, as the file has them.
    MaterialDesc v0 = m;
    v0.specular_exponent = 64;
    EXPECT_NE(write_material(v0, Dialect::V0).find(" 0.5 0 1 -1 !two lines!"), std::string::npos)
        << write_material(v0, Dialect::V0);
}

// A file that changed since it was read is not patched blind: the location no longer holds a
// #material, or a comment sits inside the directive; the error names the file, line and column.
TEST(Writer, RefusesToReplaceWhatIsNoLongerThere) {
    const std::string text = "#material 0 0 0  .1 .1 .1  .8 .8 .8  0 0 0  1  0 0 0  1  -1 !m!\n";
    MaterialDesc m = test::parse(text).files[0].materials[0];
    const std::string with = write_material(m, Dialect::V1);
    try {
        replace_materials("// a new first line\n" + text, "part.ray", {{m.loc, with}});
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("part.ray:1:1: error: cannot write the edited "
                                             "material here: the file no longer has its "
                                             "#material there"),
                  std::string::npos)
            << e.what();
    }
    const std::string commented =
        "#material 0 0 0  .1 .1 .1 // diffuse\n .8 .8 .8  0 0 0  1  0 0 0  1  -1 !m!\n";
    EXPECT_THROW(replace_materials(commented, "part.ray", {{m.loc, with}}), SceneError);
    SourceLoc beyond = m.loc;
    beyond.line = 7;
    EXPECT_THROW(replace_materials(text, "part.ray", {{beyond, with}}), SceneError);
    EXPECT_THROW(replace_materials("#material 0 0 0 !m", "part.ray", {{m.loc, with}}), SceneError);
}

// ---- V3 (spec §13) ----

// A V3 description with two materials and four vertices in its top-level file.
SceneDesc v3_desc() {
    SceneDesc d;
    d.dialect = Dialect::V3;
    d.files.resize(1);
    d.files[0].materials.resize(2);
    d.files[0].materials[0].name = "a";
    d.files[0].materials[1].name = "b";
    d.files[0].vertices.resize(4);
    return d;
}

template <class G>
ShapeDesc shape(int material, const G& geometry) {
    ShapeDesc s;
    s.material = material;
    s.geometry = geometry;
    return s;
}
ShapeDesc sphere(double x) { return shape(0, Sphere{Vec3(x, 0, 0), 1.0}); }
ShapeDesc triangle(int m, int a, int b, int c) { return shape(m, TriangleDesc{{a, b, c}}); }

GroupDesc group_of(HugePageVector<ShapeDesc> shapes) {
    GroupDesc g;
    g.shapes = std::move(shapes);
    return g;
}

CsgDesc csg(CsgOp op, std::vector<GroupDesc> operands) {
    CsgDesc c;
    c.op = op;
    c.operands = std::move(operands);
    return c;
}

// The written text after its first line (the comment naming the dialect).
std::string written_body(const SceneDesc& d) {
    const std::string text = write_scene(d, false);
    EXPECT_EQ(text.substr(0, text.find('\n')), "// Written by rayview/raytrace (V3 dialect).");
    return text.substr(text.find('\n') + 1);
}

TEST(WriterV3, GlobalAndLocalParts) {
    SceneDesc d = v3_desc();
    d.files[0].materials.resize(1);
    d.files[0].materials[0].emissive = Vec3(0.5, 0.25, 0.125);
    d.files[0].materials[0].texture = 0;
    d.files[0].vertices.resize(1);
    d.files[0].vertices[0] = {Vec3(1, 2, 3), Vec3(0, 0, 1), Vec2(0.5, 1e-7)};
    d.files[0].textures.resize(1);
    d.files[0].textures[0].path = "tex.bmp";
    d.files[0].key_files = {"anim.key"};
    d.files.push_back({});
    d.files[1].path = "sub.ray";
    d.files[0].ray_files = {1};
    d.shader_vertex = "v.glsl";
    d.shader_fragment = "f.glsl";
    LightDesc l;
    l.ambient = Vec3(0.1, 0.2, 0.3), l.diffuse = Vec3(1, 0.5, 0.25);
    l.specular = Vec3(0.4, 0.6, 0.8);
    l.position = Vec3(1, 2, 3), l.direction = Vec3(0, 0, -1);
    l.constant_atten = 0.5, l.linear_atten = 0.25, l.quadratic_atten = 0.125;
    l.cutoff_rad = 0.75, l.spot_exponent = 64, l.radius = 1.5;
    for (LightKind k :
         {LightKind::Directional, LightKind::Point, LightKind::Spot, LightKind::Sphere}) {
        l.kind = k;
        d.lights.push_back(l);
    }
    // No camera: none is written (spec §6.3); V3 has no #background and no #ambient.
    EXPECT_EQ(written_body(d),
              "#light_dir 0.1 0.2 0.3 1 0.5 0.25 0.4 0.6 0.8 0 0 -1\n"
              "#light_point 0.1 0.2 0.3 1 0.5 0.25 0.4 0.6 0.8 1 2 3 0.5 0.25 0.125\n"
              "#light_spot 0.1 0.2 0.3 1 0.5 0.25 0.4 0.6 0.8 1 2 3 0 0 -1 0.5 0.25 0.125 "
              "0.75 64\n"
              "#light_sphere 0.1 0.2 0.3 1 0.5 0.25 0.4 0.6 0.8 1 2 3 1.5 0.5 0.25 0.125\n"
              "#shader v.glsl f.glsl\n"
              "#texture tex.bmp\n"
              "#material 0.5 0.25 0.125 0 0 0 0 0 0 0 0 0 0 0 0 0 1 0 !a!\n"
              "#vertex 1 2 3 0 0 1 0.5 1e-07\n"
              "#ray_file sub.ray\n"
              "#key_file anim.key\n");
    d.camera = CameraDesc{};
    d.camera->position = Vec3(0, 1, 2);
    d.camera->half_height_angle_rad = 0.5;
    EXPECT_EQ(written_body(d).substr(0, 42), "#camera 0 1 2 0 0 -1 0 1 0 0.5\n#light_dir ");
}

TEST(WriterV3, ShapesTrianglesAndTransforms) {
    SceneDesc d = v3_desc();
    GroupDesc& root = d.files[0].root;
    root.shapes = {sphere(0),
                   triangle(1, 0, 1, 2),
                   triangle(1, 2, 1, 3),
                   triangle(0, 0, 2, 3),
                   shape(0, Torus{Vec3(1, 2, 3), 0.25, 2.0}),
                   shape(1, BoxDesc{Vec3(1, 2, 3), Vec3(4, 5, 6)}),
                   shape(0, Cylinder{Vec3(1, 2, 3), 0.5, 4.0}),
                   shape(1, Cone{Vec3(1, 2, 3), 0.5, 4.0})};
    // A transform with one shape; its matrix has m12 = 0.5 and the translation (1, 2, 3).
    GroupDesc affine = group_of({sphere(1)});
    affine.matrix[0] = glm::dvec4(2, 0, 0, 0);
    affine.matrix[1] = glm::dvec4(0.5, 3, 0, 0);
    affine.matrix[2] = glm::dvec4(0, 0, 4, 0);
    affine.matrix[3] = glm::dvec4(1, 2, 3, 1);
    root.groups.push_back(affine);
    // A joint (its frame-0 matrix is not written) with two shapes.
    GroupDesc joint = group_of({sphere(2), sphere(3)});
    joint.joint = "arm";
    joint.matrix[3] = glm::dvec4(7, 0, 0, 1);
    root.groups.push_back(joint);
    // Plain lists: one shape; one list (the parser makes a list of a list); empty.
    root.groups.push_back(group_of({sphere(4)}));
    GroupDesc outer;
    outer.groups.push_back(group_of({sphere(5)}));
    root.groups.push_back(outer);
    root.groups.push_back(GroupDesc{});
    // A transform whose one child is a list: that list is written (a bare list would be folded).
    GroupDesc wrapped = outer;
    wrapped.matrix = affine.matrix;
    root.groups.push_back(wrapped);
    // A transform whose one child is a transform; a #shape_triangles list as a child list.
    GroupDesc nested;
    nested.matrix = affine.matrix;
    nested.groups.push_back(affine);
    root.groups.push_back(nested);
    root.groups.push_back(group_of({triangle(1, 3, 2, 1)}));
    root.instances.resize(1);
    d.files.push_back({});
    d.files[1].path = "sub.ray";
    d.files[0].ray_files = {1};
    const std::string expected =
        "#shape_sphere 0 0 0 0 1\n"
        "#shape_triangles 1\n#shape_list_begin\n"
        "  #shape_triangle 0 1 2\n  #shape_triangle 2 1 3\n#shape_list_end\n"
        "#shape_triangles 0\n#shape_list_begin\n  #shape_triangle 0 2 3\n#shape_list_end\n"
        "#shape_torus 0 1 2 3 0.25 2\n"
        "#shape_box 1 1 2 3 4 5 6\n"
        "#shape_cylinder 0 1 2 3 0.5 4\n"
        "#shape_cone 1 1 2 3 0.5 4\n"
        "#static_affine 2 0 0 0 0.5 3 0 0 0 0 4 0 1 2 3 1\n#shape_sphere 0 1 0 0 1\n"
        "#dynamic_affine arm\n#shape_list_begin\n"
        "  #shape_sphere 0 2 0 0 1\n  #shape_sphere 0 3 0 0 1\n#shape_list_end\n"
        "#shape_list_begin\n  #shape_sphere 0 4 0 0 1\n#shape_list_end\n"
        "#shape_list_begin\n  #shape_list_begin\n    #shape_sphere 0 5 0 0 1\n"
        "  #shape_list_end\n#shape_list_end\n"
        "#shape_list_begin\n#shape_list_end\n"
        "#static_affine 2 0 0 0 0.5 3 0 0 0 0 4 0 1 2 3 1\n#shape_list_begin\n"
        "  #shape_list_begin\n    #shape_sphere 0 5 0 0 1\n  #shape_list_end\n#shape_list_end\n"
        "#static_affine 2 0 0 0 0.5 3 0 0 0 0 4 0 1 2 3 1\n"
        "#static_affine 2 0 0 0 0.5 3 0 0 0 0 4 0 1 2 3 1\n#shape_sphere 0 1 0 0 1\n"
        "#shape_triangles 1\n#shape_list_begin\n  #shape_triangle 3 2 1\n#shape_list_end\n"
        "#ray_file_instance 0\n";
    const std::string body = written_body(d);
    EXPECT_EQ(body.substr(body.find("#shape_sphere")), expected);
}

TEST(WriterV3, Csg) {
    SceneDesc d = v3_desc();
    GroupDesc affine = group_of({sphere(6)});
    affine.matrix[3] = glm::dvec4(1, 2, 3, 1);
    GroupDesc list_operand;  // an operand whose one child is a list
    list_operand.groups.push_back(group_of({sphere(7)}));
    GroupDesc affine_operand;  // an operand whose one child is a transform
    affine_operand.groups.push_back(affine);
    GroupDesc csg_operand;  // an operand whose one child is a CSG node
    csg_operand.csgs.push_back(
        csg(CsgOp::Intersection, {group_of({sphere(8)}), group_of({sphere(9)})}));
    d.files[0].root.csgs = {
        csg(CsgOp::Union, {group_of({sphere(1)}), group_of({sphere(2), sphere(3)}), GroupDesc{},
                           list_operand, affine_operand}),
        csg(CsgOp::Difference, {group_of({shape(1, Torus{Vec3(0.0), 0.5, 2.0})}), csg_operand}),
        csg(CsgOp::Difference, {GroupDesc{}, group_of({triangle(1, 0, 1, 2)})}),
        csg(CsgOp::Intersection, {})};
    const std::string expected =
        "#shape_union\n#shape_list_begin\n"
        "  #shape_sphere 0 1 0 0 1\n"                                                  // one shape
        "  #shape_list_begin\n    #shape_sphere 0 2 0 0 1\n"                           // two shapes
        "    #shape_sphere 0 3 0 0 1\n  #shape_list_end\n"                             //
        "  #shape_list_begin\n  #shape_list_end\n"                                     // empty
        "  #shape_list_begin\n    #shape_list_begin\n      #shape_sphere 0 7 0 0 1\n"  // a list
        "    #shape_list_end\n  #shape_list_end\n"                                     //
        "  #static_affine 1 0 0 0 0 1 0 0 0 0 1 0 1 2 3 1\n  #shape_sphere 0 6 0 0 1\n"
        "#shape_list_end\n"
        "#shape_difference\n#shape_torus 1 0 0 0 0.5 2\n"
        "#shape_intersection\n#shape_list_begin\n"
        "  #shape_sphere 0 8 0 0 1\n  #shape_sphere 0 9 0 0 1\n#shape_list_end\n"
        "#shape_difference\n#shape_list_begin\n#shape_list_end\n"
        "#shape_triangles 1\n#shape_list_begin\n  #shape_triangle 0 1 2\n#shape_list_end\n"
        "#shape_intersection\n#shape_list_begin\n#shape_list_end\n";
    const std::string body = written_body(d);
    EXPECT_EQ(body.substr(body.find("#shape_union")), expected);

    d.files[0].root.csgs = {csg(CsgOp::Difference, {group_of({sphere(1)})})};
    try {
        write_scene(d);
        ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("a CSG difference needs exactly two operands to be "
                                             "written, got 1"),
                  std::string::npos)
            << e.what();
    }
}

// The message of the SceneError that writing `d` throws ("" when none).
std::string write_error(const SceneDesc& d) {
    try {
        write_scene(d);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

TEST(Writer, V3FeaturesInV1AreRefused) {
    const SceneDesc v1 = test::parse(
        "#light_point 1 1 1  0 5 5  1 0 0\n"
        "#material 0 0 0  .1 .1 .1  .5 .5 .5  0 0 0  1  0 0 0  1  -1 !m!\n"
        "#shape_sphere 0 0 0 0 1\n");
    ASSERT_EQ(v1.dialect, Dialect::V1);
    EXPECT_EQ(write_error(v1), "");
    auto refused = [&](auto edit, const std::string& message) {
        SceneDesc d = v1;
        edit(d);
        EXPECT_NE(write_error(d).find(message), std::string::npos) << write_error(d);
        d.dialect = Dialect::V0;
        EXPECT_NE(write_error(d).find(message), std::string::npos) << write_error(d);
    };
    refused([](SceneDesc& d) { d.files[0].root.shapes[0].geometry = Torus{}; },
            "a torus cannot be written in V0 or V1 (#shape_torus is V3 only)");
    refused(
        [](SceneDesc& d) {
            d.files[0].root.groups.resize(1);
            d.files[0].root.groups[0].csgs.push_back(csg(CsgOp::Intersection, {}));
        },
        "a CSG intersection cannot be written in V0 or V1 (#shape_intersection is V3 only)");
    refused([](SceneDesc& d) { d.lights[0].kind = LightKind::Sphere; },
            "a sphere light cannot be written in V0 or V1 (#light_sphere is V3 only)");
    refused([](SceneDesc& d) { d.lights[0].ambient = Vec3(0.1); }, "three-colour lights are V3");
    refused([](SceneDesc& d) { d.lights[0].specular = Vec3(0.5); }, "three-colour lights are V3");
    refused([](SceneDesc& d) { d.shader_vertex = "v.glsl"; }, "#shader is V3 only");
    // And V3 has no global background or ambient colour.
    SceneDesc d = v1;
    d.dialect = Dialect::V3;
    d.background = Vec3(0.5);
    EXPECT_NE(write_error(d).find("a background colour cannot be written in V3"),
              std::string::npos);
}

// parse -> write -> parse gives the same description; the written text is V3 again.
void expect_round_trip(const std::string& path, const ParseOptions& options) {
    SCOPED_TRACE(path);
    Diagnostics d1, d2;
    const SceneDesc a = parse_scene_file(path, d1, options);
    const std::string text = write_scene(a);
    const SceneDesc b = parse_scene_string(text, "written.ray", d2, options,
                                           std::filesystem::path(path).parent_path().string());
    expect_same(a, b);
    // The text of the description read back is the same text.
    EXPECT_EQ(write_scene(b), text);
}

TEST(WriterV3, RichSceneRoundTrips) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("rt_writer_v3_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto put = [&](const char* name, const char* text) { std::ofstream(dir / name) << text; };
    put("anim.key", "#DOFS 1 arm #DURATION 1 #FRAMES 1\n1 0 0 0 0 1 0 0 0 0 1 0 0 0.5 0 1\n");
    put("sub.ray",
        "#camera 0 0 0 0 0 0 0 0 0 0\n"
        "#material 0 0 0  .1 .1 .1  .5 .5 .5  0 0 0  1  0 0 0  1  -1 !s!\n"
        "#shape_sphere 0 0 0 0 1\n");
    put("scene.ray",
        "#camera 0 1 5  0 0 -1  0 1 0  0.5\n"
        "#light_dir 0.1 0.1 0.1  1 1 1  0.5 0.5 0.5  0 -1 0\n"
        "#light_point 0 0 0  1 0.5 0.25  1 1 1  0 5 5  1 0.1 0.01\n"
        "#light_spot 0.1 0.2 0.3  0.4 0.5 0.6  0.7 0.8 0.9  0 5 0  0 -1 0  1 0 0  0.5 64\n"
        "#light_sphere 0 0 0  1 1 1  1 1 1  0 4 0  0.5  1 0 0\n"
        "#shader shaders/v.glsl shaders/f.glsl\n"
        "#texture missing.bmp\n"
        "#material 0.1 0.1 0.1  0.3 0.3 0.3  0.1 0.1 0.5  1 1 1  100  0 0 0  1  -1 !a!\n"
        "#material 0 0 0  0.2 0.2 0.2  0.8 0.8 0.8  0 0 0  1  0.5 0.5 0.5  1.5  0 !textured b!\n"
        "#vertex 0 0 0  0 0 1  0 0\n#vertex 1 0 0  0 0 1  1 0\n"
        "#vertex 1 1 0  0 0 1  1 1\n#vertex 0 1 0  0 0 0  0.1 0.7\n"
        "#ray_file sub.ray\n#key_file anim.key\n"
        "#shape_sphere 0 0 0 0 0.3333333333333333\n"
        "#shape_torus 1 1 2 3 0.25 2\n"
        "#shape_triangles 1\n#shape_list_begin\n"
        "#shape_triangle 0 1 2\n#shape_triangle 0 2 3\n#shape_list_end\n"
        "#shape_triangles 0 #shape_list_begin #shape_triangle 0 1 3 #shape_list_end\n"
        "#static_affine 0.5 0 0 0  0 1 0 0  0 0 0.5 0  0 2.5 0 1\n  #ray_file_instance 0\n"
        "#static_affine 1 0 -1 0  0 1 0 0  1 0 1 0  0 0 0 1\n"
        "  #shape_list_begin #shape_box 0 0 0 0 1 2 3 #shape_cylinder 0 0 0 0 1 2 "
        "#shape_list_end\n"
        "#static_affine 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n"
        "  #shape_list_begin #shape_list_begin #shape_sphere 0 0 0 0 1 #shape_list_end "
        "#shape_list_end\n"
        "#dynamic_affine arm\n  #shape_cone 0 0 0 0 1 2\n"
        "#dynamic_affine arm #static_affine 2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1 "
        "#shape_sphere 0 0 0 0 1\n"
        "#shape_list_begin\n  #shape_list_begin\n  #shape_list_end\n"
        "  #shape_sphere 1 1 1 1 0.5\n#shape_list_end\n"
        "#shape_union\n#shape_list_begin\n  #shape_sphere 0 0 0 0 1\n"
        "  #shape_list_begin #shape_box 0 0 0 0 1 1 1 #shape_cylinder 0 0 0 0 1 1 "
        "#shape_list_end\n"
        "  #shape_list_begin #shape_list_end\n"
        "  #shape_list_begin #shape_list_begin #shape_torus 0 0 0 0 1 3 #shape_list_end "
        "#shape_list_end\n"
        "  #static_affine 2 0 0 0 0 2 0 0 0 0 2 0 1 1 1 1 #shape_sphere 0 0 0 0 1\n"
        "  #ray_file_instance 0\n"
        "#shape_list_end\n"
        "#shape_intersection\n#shape_list_begin\n  #shape_sphere 0 0 0 -0.5 1\n"
        "  #shape_sphere 0 0 0 0.5 1\n  #shape_cylinder 0 0 0 0 0.8 2\n#shape_list_end\n"
        "#shape_difference\n  #shape_torus 0 0 0 0 0.5 2\n"
        "  #shape_difference #shape_sphere 0 0 0 0 1 #shape_sphere 0 0 0 0 0\n"
        "#shape_difference #shape_triangles 1 #shape_list_begin #shape_triangle 0 1 2 "
        "#shape_list_end #shape_union #shape_list_begin #shape_list_end\n"
        "#shape_intersection #shape_list_begin #shape_list_end\n");
    ParseOptions options;
    options.missing_textures = MissingTextures::Checker;
    expect_round_trip((dir / "scene.ray").string(), options);
    std::filesystem::remove_all(dir);
}

// Every file of the public V3 sets, read as V3 (their sub-files, such as _sphere.ray, have no V3
// marker of their own and a dummy camera), and the files detected as V3 also as detected.
TEST(WriterV3, PublicScenesRoundTrip) {
    ParseOptions detected;
    detected.missing_textures = MissingTextures::Checker;  // their textures were never published
    ParseOptions forced = detected;
    forced.dialect = Dialect::V3;
    int n = 0, n_detected = 0;
    for (const char* repo : {"henry-md__ray-tracer", "aarxa__RayForge-CPP-Ray-Tracing-Engine",
                             "dcalvo__Graphics-2021"}) {
        const std::filesystem::path dir = std::filesystem::path(RT_PUBLIC_SCENES_DIR) / repo;
        for (const auto& e : std::filesystem::directory_iterator(dir)) {
            if (e.path().extension() != ".ray") continue;
            expect_round_trip(e.path().string(), forced);
            ++n;
            Diagnostics diag;
            try {
                if (parse_scene_file(e.path().string(), diag, detected).dialect != Dialect::V3)
                    continue;
            } catch (const SceneError&) {
                continue;
            }
            expect_round_trip(e.path().string(), detected);
            ++n_detected;
        }
    }
    EXPECT_EQ(n, 41);
    EXPECT_EQ(n_detected, 34);
}

}  // namespace
}  // namespace rt
