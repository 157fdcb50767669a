// The scene builder (core/src/format/scene_builder.h) on its own: what the directives mean, given
// values and their locations as a grammar walk hands them over, with no text to parse.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "format/scene_builder.h"

namespace rt::parser_impl {
namespace {

namespace fs = std::filesystem;

SourceLoc at(int line, int col = 1) { return {intern_file_name("b.ray"), line, col}; }

// A file that a #ray_file can find (empty).
std::string a_file() {
    const std::string path = (fs::temp_directory_path() / "rt_test_builder_sub.ray").string();
    std::ofstream(path) << "";
    return path;
}

// A builder of a tree in `dialect` with its top-level file open (or, not `top`, a file it
// includes).
struct Tree {
    Diagnostics diag;
    SceneBuilder b{diag, ParseOptions{}};
    SceneBuilder::Include include{at(1), at(1, 11), "c.ray", "/c.ray", 0};
    explicit Tree(Dialect dialect, bool top = true) {
        b.set_dialect(dialect, ".");
        b.open_file({"b.ray", "/b.ray", "."});
        if (top) return;
        b.ray_file(include.loc, include.path_loc, a_file());  // its slot
        b.open_file({"c.ray", "/c.ray", ".", &include});
    }
    // The tree's description, its files closed.
    SceneDesc scene(bool top = true) {
        if (!top) b.close_file(at(90));
        b.close_file(at(99));
        return b.finish();
    }
    // The message of the SceneError that `fn` throws ("" when none).
    template <class Fn>
    static std::string error(Fn fn) {
        try {
            fn();
        } catch (const SceneError& e) {
            return e.what();
        }
        return "";
    }
};

CameraDesc camera(double z, int line) {
    CameraDesc c;
    c.loc = at(line);
    c.position = Vec3(0, 0, z);
    c.direction = Vec3(0, 0, -1);
    c.up = Vec3(0, 1, 0);
    c.half_height_angle_rad = 0.5;
    return c;
}

TEST(SceneBuilder, TheFirstCameraWinsInV1AndTheLastInV3) {
    Tree v1(Dialect::V1);
    v1.b.camera(camera(1, 1));
    v1.b.camera(camera(2, 2));
    EXPECT_EQ(v1.scene().camera->position.z, 1);
    ASSERT_EQ(v1.diag.warnings().size(), 1u);
    EXPECT_EQ(v1.diag.warnings()[0].str(),
              "b.ray:2:1: warning: second #camera ignored; the first one (b.ray:1:1) wins");

    Tree v3(Dialect::V3);
    v3.b.camera(camera(1, 1));
    v3.b.camera(camera(2, 2));
    EXPECT_EQ(v3.scene().camera->position.z, 2);
    ASSERT_EQ(v3.diag.warnings().size(), 1u);
    EXPECT_EQ(v3.diag.warnings()[0].kind, "camera-repeat");
}

TEST(SceneBuilder, IncludedFilesCamerasAndLightsAreIgnored) {
    Tree t(Dialect::V1, /*top=*/false);
    t.b.camera(camera(1, 1));
    LightDesc l;
    l.loc = at(2);
    l.kind = LightKind::Directional;
    l.direction = Vec3(0, -1, 0);
    t.b.light(l);
    t.b.light(l);
    const SceneDesc scene = t.scene(false);
    EXPECT_FALSE(scene.camera);
    EXPECT_TRUE(scene.lights.empty());
    // V0/V1 warn at every light of an included file (with the include), V3 once per file.
    ASSERT_EQ(t.diag.warnings().size(), 2u);
    EXPECT_EQ(t.diag.warnings()[0].count, 2);
    EXPECT_EQ(t.diag.warnings()[0].str(),
              "b.ray:2:1: warning: lights in included files are ignored (2 times in this file)\n"
              "  included from b.ray:1:1");
    EXPECT_EQ(t.diag.warnings()[1].kind, "no-camera");
}

TEST(SceneBuilder, AnAllZeroCameraIsTheDefaultCamera) {
    Tree t(Dialect::V3);
    t.b.camera(camera(1, 1));
    CameraDesc zero = camera(0, 2);
    zero.direction = zero.up = Vec3(0);
    zero.half_height_angle_rad = 0;
    t.b.camera(zero);  // the last one wins, and it is the course's dummy
    EXPECT_FALSE(t.scene().camera);
    EXPECT_TRUE(t.diag.has("camera-zero"));
    EXPECT_FALSE(t.diag.has("no-camera"));  // the dummy camera's warning said so already
}

TEST(SceneBuilder, AMaterialsNumbersMeanWhatTheDialectSays) {
    MaterialNumbers m;
    m.loc = at(3);
    m.n = 16;
    for (int i = 0; i < 16; ++i) {
        m.v[static_cast<size_t>(i)] = 0.1 * (i + 1);
        m.at[static_cast<size_t>(i)] = at(3, 10 + 2 * i);
    }
    Tree v0(Dialect::V0);
    const MaterialDesc d = v0.b.material(m);
    EXPECT_DOUBLE_EQ(d.ambient.x, 0.1);  // V0: ambient first
    EXPECT_DOUBLE_EQ(d.emissive.x, 1.0);
    EXPECT_DOUBLE_EQ(d.specular_exponent, 128 * 1.3);  // kspec scaled by 128
    EXPECT_DOUBLE_EQ(d.transparent.z, 1.4);            // one ktran for all three

    // The same 16 numbers in a V1 tree: an error at the directive.
    Tree v1(Dialect::V1);
    EXPECT_EQ(Tree::error([&] { v1.b.material(m); }),
              "b.ray:3:1: error: #material has 16 numbers in a V1 scene");
    // A negative colour: an error at its own number.
    m.v[4] = -2;
    EXPECT_EQ(Tree::error([&] { v0.b.material(m); }), "b.ray:3:18: error: negative diffuse -2");
}

TEST(SceneBuilder, ShapesGoIntoTheInnermostGroupAndDegenerateOnesAreSkipped) {
    Tree t(Dialect::V1);
    for (int i = 0; i < 3; ++i) {
        VertexDesc v;
        v.position = Vec3(i == 1, i == 2, 0);
        t.b.vertex(v);
    }
    SceneBuilder::Construct group{SceneBuilder::Construct::Group, at(2), "#group_begin"};
    group.matrix[3] = glm::dvec4(1, 2, 3, 1);
    t.b.open(group);
    ShapeDesc s;
    s.loc = at(3);
    s.geometry = TriangleDesc{{0, 1, 2}};
    ShapeDesc flat = s;
    flat.loc = at(4);
    flat.geometry = TriangleDesc{{0, 1, 1}};
    t.b.shape(std::move(s));
    t.b.shape(std::move(flat));
    t.b.close(at(5), "#group_end");

    const SceneDesc scene = t.scene();
    const FileDesc& f = scene.files.at(0);
    ASSERT_EQ(f.root.groups.size(), 1u);
    EXPECT_EQ(f.root.groups[0].shapes.size(), 1u);
    EXPECT_EQ(f.root.groups[0].matrix[3].y, 2);
    EXPECT_TRUE(f.root.shapes.empty());
    EXPECT_EQ(scene.skipped_shapes, 1u);
    ASSERT_EQ(t.diag.warnings().size(), 2u);
    EXPECT_EQ(t.diag.warnings()[0].str(), "b.ray:4:1: warning: degenerate triangle skipped");
}

// A run in pieces: each piece's copy writes its range of the run's room in place; a range
// written short (a degenerate triangle skipped) is closed up by the merge, in file order.
TEST(SceneBuilder, ARunsPiecesWriteTheirRangesInPlace) {
    Tree t(Dialect::V1);
    for (int i = 0; i < 3; ++i) {
        VertexDesc v;
        v.position = Vec3(i == 1, i == 2, 0);
        t.b.vertex(v);
    }
    const auto triangle = [](int line, bool flat) {
        ShapeDesc s;
        s.loc = at(line);
        s.geometry = TriangleDesc{{0, 1, flat ? 1 : 2}};
        return s;
    };
    t.b.shape(triangle(10, false));  // the run's first directive
    t.b.open_run(false, 4, 1);       // directives 1 .. 4; the file writes the first
    Diagnostics own_a, own_b;
    SceneBuilder a(t.b, own_a, SceneBuilder::Piece{false, 2, 2});
    SceneBuilder b(t.b, own_b, SceneBuilder::Piece{false, 4, 1});
    b.shape(triangle(14, false));
    t.b.shape(triangle(11, true));  // skipped: the file's range is written short
    a.shape(triangle(12, false));
    a.shape(triangle(13, false));
    EXPECT_FALSE(t.b.merge(a));
    EXPECT_FALSE(t.b.merge(b));
    t.b.close_run();
    t.b.shape(triangle(15, false));  // after the run: appended

    const SceneDesc scene = t.scene();
    const HugePageVector<ShapeDesc>& shapes = scene.files.at(0).root.shapes;
    ASSERT_EQ(shapes.size(), 5u);
    const int lines[] = {10, 12, 13, 14, 15};
    for (size_t i = 0; i < shapes.size(); ++i) EXPECT_EQ(shapes[i].loc.line, lines[i]);
    EXPECT_EQ(scene.skipped_shapes, 1u);
}

TEST(SceneBuilder, TheGraphsRulesAreErrorsAtTheirDirectives) {
    Tree t(Dialect::V1);
    EXPECT_EQ(Tree::error([&] { t.b.close(at(7, 3), "#joint_end"); }),
              "b.ray:7:3: error: #joint_end without #joint_begin");
    SceneBuilder::Construct singular{SceneBuilder::Construct::Group, at(8), "#group_begin"};
    singular.matrix[1] = glm::dvec4(0);
    EXPECT_EQ(Tree::error([&] { t.b.open(singular); }), "b.ray:8:1: error: singular group matrix");
    EXPECT_EQ(Tree::error([&] { t.b.instance(at(9), at(9, 20), 0); }),
              "b.ray:9:20: error: ray file index 0 out of range [0,0)");
}

TEST(SceneBuilder, CountsAreCheckedAsItemsArrive) {
    Tree t(Dialect::V1);
    t.b.declare_count(at(1), kMaterials, 1, at(1, 15), 100);
    t.b.count_item(at(2), kMaterials);
    EXPECT_EQ(Tree::error([&] { t.b.count_item(at(3), kMaterials); }),
              "b.ray:3:1: error: more #material than declared by #material_num at b.ray:1:1");
    EXPECT_EQ(Tree::error([&] { t.b.place(at(4), "#vertex", SceneBuilder::Definition); }), "");
    t.b.open({SceneBuilder::Construct::Group, at(5), "#group_begin"});  // the graph starts
    EXPECT_EQ(Tree::error([&] { t.b.place(at(6), "#vertex", SceneBuilder::Definition); }),
              "b.ray:6:1: error: definition after the scene graph started");
}

TEST(SceneBuilder, ASpotsNumbersAreCheckedAndAV0DropOffIsScaled) {
    LightDesc l;
    l.loc = at(1);
    l.kind = LightKind::Spot;
    l.direction = Vec3(0, -1, 0);
    l.cutoff_rad = 2;
    l.spot_exponent = 0.5;
    Tree v0(Dialect::V0);
    v0.b.spot(l, at(1, 30), at(1, 35));
    EXPECT_DOUBLE_EQ(l.spot_exponent, 64);  // 128 x the drop-off, as a material's kspec
    EXPECT_TRUE(v0.diag.has("spot-cutoff"));
    Tree v1(Dialect::V1);
    l.spot_exponent = -1;
    EXPECT_EQ(Tree::error([&] { v1.b.spot(l, at(1, 30), at(1, 35)); }),
              "b.ray:1:35: error: negative spot drop-off -1");
}

TEST(SceneBuilder, AV3FilesPartsComeInOrder) {
    Tree t(Dialect::V3);
    t.b.place(at(1), "#camera", SceneBuilder::Global);
    t.b.place(at(2), "#shape_sphere", SceneBuilder::Shapes);
    EXPECT_EQ(Tree::error([&] { t.b.place(at(3), "#vertex", SceneBuilder::Local); }),
              "b.ray:3:1: error: '#vertex' after the shapes part started at b.ray:2:1 (V3 order: "
              "global, local, shapes)");
    EXPECT_EQ(Tree::error([&] { t.b.place(at(4), "#shape_triangle", SceneBuilder::Shapes); }),
              "b.ray:4:1: error: #shape_triangle outside #shape_triangles");
}

// A file parsed ahead into a copy: merged in the tree's order, its warnings with the include
// chain, its #ray_file directives handed to the driver where they came.
TEST(SceneBuilder, ACopysResultIsMergedInTheTreesOrder) {
    const std::string sub = a_file();
    Tree t(Dialect::V1);
    Diagnostics own;
    SceneBuilder copy(t.b, own);
    copy.open_file({"c.ray", "/c.ray", "."});
    copy.warn(at(1), "first", "before the include");
    copy.ray_file(at(2), at(2, 11), sub);
    EXPECT_FALSE(copy.take_include());  // kept for the merge
    copy.warn(at(3), "second", "after it");
    copy.close_file(at(9));

    t.b.ray_file(at(5), at(5, 11), sub);  // the top-level file includes the same file first
    const std::optional<SceneBuilder::Include> first = t.b.take_include();
    ASSERT_TRUE(first);
    t.b.open_file({sub, first->canonical, ".", &*first});
    t.b.close_file(at(1));
    SceneBuilder::Include c{at(6), at(6, 11), "c.ray", "/c.ray", 1};
    t.b.ray_file(at(6), at(6, 11), sub);  // slot 1, then the copy's file
    EXPECT_FALSE(t.b.take_include());     // already in the tree: numbered only
    EXPECT_TRUE(t.b.merge(copy, &c));
    EXPECT_FALSE(t.b.take_include());  // the copy's #ray_file: numbered in the tree
    EXPECT_FALSE(t.b.merge(copy, &c));
    const SceneDesc scene = t.scene();
    ASSERT_EQ(scene.files.size(), 3u);
    EXPECT_EQ(scene.files[2].ray_files, std::vector<int>{1});
    ASSERT_GE(t.diag.warnings().size(), 2u);
    EXPECT_EQ(t.diag.warnings()[0].str(),
              "b.ray:1:1: warning: before the include\n  included from b.ray:6:1");
    EXPECT_EQ(t.diag.warnings()[1].kind, "second");
}

}  // namespace
}  // namespace rt::parser_impl
