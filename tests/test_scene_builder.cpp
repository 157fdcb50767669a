// The scene builder (core/src/format/scene_builder.h) on its own: what the directives mean, given
// values and their locations as a grammar walk hands them over, with no text to parse.
#include <gtest/gtest.h>

#include <string>

#include "format/scene_builder.h"

namespace rt::parser_impl {
namespace {

SourceLoc at(int line, int col = 1) { return {intern_file_name("b.ray"), line, col}; }

// A builder of a tree in `dialect` and its top-level file, its groups open at the root.
struct Tree {
    Diagnostics diag;
    SceneBuilder b{diag, ParseOptions{}};
    FileState f{"", intern_file_name("b.ray")};
    explicit Tree(Dialect dialect, bool top = true) {
        b.set_dialect(dialect, "", ".");
        f.top = top;
        f.stack.push_back(&f.desc.root);
        f.stack_is_joint.push_back(0);
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
    v1.b.camera(v1.f, camera(1, 1));
    v1.b.camera(v1.f, camera(2, 2));
    EXPECT_EQ(v1.b.scene().camera->position.z, 1);
    ASSERT_EQ(v1.diag.warnings().size(), 1u);
    EXPECT_EQ(v1.diag.warnings()[0].str(),
              "b.ray:2:1: warning: second #camera ignored; the first one (b.ray:1:1) wins");

    Tree v3(Dialect::V3);
    v3.b.camera(v3.f, camera(1, 1));
    v3.b.camera(v3.f, camera(2, 2));
    EXPECT_EQ(v3.b.scene().camera->position.z, 2);
    ASSERT_EQ(v3.diag.warnings().size(), 1u);
    EXPECT_EQ(v3.diag.warnings()[0].kind, "camera-repeat");
}

TEST(SceneBuilder, IncludedFilesCamerasAndLightsAreIgnored) {
    Tree t(Dialect::V1, /*top=*/false);
    t.b.camera(t.f, camera(1, 1));
    LightDesc l;
    l.loc = at(2);
    l.kind = LightKind::Directional;
    l.direction = Vec3(0, -1, 0);
    t.b.light(t.f, l);
    t.b.light(t.f, l);
    EXPECT_FALSE(t.b.scene().camera);
    EXPECT_TRUE(t.b.scene().lights.empty());
    // V0/V1 warn at every light of an included file, V3 once per file.
    ASSERT_EQ(t.diag.warnings().size(), 1u);
    EXPECT_EQ(t.diag.warnings()[0].count, 2);
    EXPECT_EQ(t.diag.warnings()[0].kind, "included-light");
}

TEST(SceneBuilder, AnAllZeroCameraIsTheDefaultCamera) {
    Tree t(Dialect::V3);
    t.b.camera(t.f, camera(1, 1));
    CameraDesc zero = camera(0, 2);
    zero.direction = zero.up = Vec3(0);
    zero.half_height_angle_rad = 0;
    t.b.camera(t.f, zero);  // the last one wins, and it is the course's dummy
    EXPECT_FALSE(t.b.scene().camera);
    EXPECT_TRUE(t.diag.has("camera-zero"));
    t.b.scene().files.emplace_back().path = "b.ray";
    t.b.finish();
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
        t.b.vertex(t.f, at(1), v);
    }
    Mat4 m(1.0);
    m[3] = glm::dvec4(1, 2, 3, 1);
    t.b.group_begin(t.f, at(2), "#group_begin", m);
    ShapeDesc s;
    s.loc = at(3);
    s.geometry = TriangleDesc{{0, 1, 2}};
    ShapeDesc flat = s;
    flat.loc = at(4);
    flat.geometry = TriangleDesc{{0, 1, 1}};
    for (ShapeDesc* x : {&s, &flat})
        if (t.b.keep_shape(t.f, *x)) t.b.group_shape(t.f, std::move(*x));
    t.b.group_end(t.f, at(5), "#group_end", false);

    ASSERT_EQ(t.f.desc.root.groups.size(), 1u);
    EXPECT_EQ(t.f.desc.root.groups[0].shapes.size(), 1u);
    EXPECT_EQ(t.f.desc.root.groups[0].matrix[3].y, 2);
    EXPECT_TRUE(t.f.desc.root.shapes.empty());
    EXPECT_EQ(t.b.scene().skipped_shapes, 1u);
    ASSERT_EQ(t.diag.warnings().size(), 1u);
    EXPECT_EQ(t.diag.warnings()[0].str(), "b.ray:4:1: warning: degenerate triangle skipped");
}

TEST(SceneBuilder, TheGraphsRulesAreErrorsAtTheirDirectives) {
    Tree t(Dialect::V1);
    EXPECT_EQ(Tree::error([&] { t.b.group_end(t.f, at(7, 3), "#joint_end", true); }),
              "b.ray:7:3: error: #joint_end without #joint_begin");
    Mat4 singular(1.0);
    singular[1] = glm::dvec4(0);
    EXPECT_EQ(Tree::error([&] { t.b.group_begin(t.f, at(8), "#group_begin", singular); }),
              "b.ray:8:1: error: singular group matrix");
    EXPECT_EQ(Tree::error([&] { t.b.instance(t.f, at(9), at(9, 20), 0); }),
              "b.ray:9:20: error: ray file index 0 out of range [0,0)");
}

TEST(SceneBuilder, CountsAreCheckedAsItemsArrive) {
    Tree t(Dialect::V1);
    t.b.declare_count(t.f, at(1), kMaterials, 1, at(1, 15), 100);
    t.b.count_item(t.f, at(2), kMaterials);
    EXPECT_EQ(Tree::error([&] { t.b.count_item(t.f, at(3), kMaterials); }),
              "b.ray:3:1: error: more #material than declared by #material_num at b.ray:1:1");
    EXPECT_EQ(Tree::error([&] { t.b.definition(t.f, at(4)); }), "");
    t.b.graph(t.f);
    EXPECT_EQ(Tree::error([&] { t.b.definition(t.f, at(5)); }),
              "b.ray:5:1: error: definition after the scene graph started");
}

}  // namespace
}  // namespace rt::parser_impl
