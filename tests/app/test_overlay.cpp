// The overlay's line geometry (state/overlay.h), headless: light markers, BVH and CSG node
// boxes, the scene graph's group boxes. (Drawn over the preview: tests/gl.)
#include "rt/compile/compile.h"
#include "state/overlay.h"
#include "test_util.h"

namespace rt {
namespace {

// A shape's description (a box's full sizes), and an operand holding it alone.
ShapeDesc shape(const Sphere& s) {
    ShapeDesc d;
    d.geometry = s;
    return d;
}
ShapeDesc shape(const Box& b) {
    ShapeDesc d;
    d.geometry = BoxDesc{b.centre, 2.0 * b.half};
    return d;
}
template <class S>
GroupDesc operand(const S& s) {
    GroupDesc g;
    g.shapes.push_back(shape(s));
    return g;
}

TEST(Overlay, LinesMarkLightsAndBoxes) {
    const RenderScene scene = test::compile(
        "#light_point 1 1 1  0 2 0  1 0 0\n#light_spot 1 0 0  0 3 0  0 -1 0  1 0 0  0.5 2\n"
        "#light_dir 1 1 1  0 -1 0\n"
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n#shape_sphere 0 0 0 0 1\n"
        "#shape_box 0 3 0 0 1 1 1\n");
    const view::LightMarkers off{false, -1, false}, small{true, -1, false};
    const auto none = view::overlay_lines(scene, off, 0);
    EXPECT_TRUE(none.empty());
    // By default small crosses only: the point and the spot light's (the directional light has
    // no position); the selected light's direction too, or every light's when asked.
    EXPECT_EQ(view::overlay_lines(scene, small, 0).size(), 2u * 6);
    const auto spot = view::overlay_lines(scene, {true, 1, false}, 0);
    EXPECT_GT(spot.size(), 2u * 6 + 2 * 16);  // the crosses and the spot's cone
    const auto arrows = view::overlay_lines(scene, {true, 2, false}, 0);
    EXPECT_EQ(arrows.size(), 2u * (6 + 3 * 3 + 1));  // the crosses and three arrows with a bar
    const auto lights = view::overlay_lines(scene, {true, -1, true}, 0);
    EXPECT_EQ(lights.size(), spot.size() + arrows.size() - 2 * 6);
    EXPECT_EQ(lights.size() % 2, 0u);
    // A sphere light: its cross and three circles of 32 segments at its radius.
    RenderScene with_sphere = scene;
    Light sphere;
    sphere.kind = LightKind::Sphere;
    sphere.position = Vec3(1, 2, 3);
    sphere.radius = 0.5;
    with_sphere.lights = {sphere};
    const auto marker = view::overlay_lines(with_sphere, small, 0);
    ASSERT_EQ(marker.size(), 2u * (3 + 3 * 32));
    for (size_t i = 6; i < marker.size(); ++i)
        EXPECT_NEAR(
            glm::length(Vec3(marker[i].position[0], marker[i].position[1], marker[i].position[2]) -
                        sphere.position),
            0.5, 1e-6);
    const auto boxes = view::overlay_lines(scene, off, 2);
    EXPECT_GE(boxes.size(), 2u * 12 * 2);  // the instance's box and its nodes' boxes
}

// Group boxes come from the scene graph, not the BVH: one box per group and per included file
// instance down to the level asked for, tight around what the group holds, in world space.
TEST(Overlay, GroupBoxesFollowTheSceneGraph) {
    const SceneDesc desc = test::parse(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#group_begin 1 0 0 2  0 1 0 0  0 0 1 0  0 0 0 1\n"
        "#shape_sphere 0 0 0 0 1\n"
        "#group_begin 2 0 0 0  0 1 0 5  0 0 1 0  0 0 0 1\n#shape_box 0 0 0 0 1 1 1\n#group_end\n"
        "#group_end\n#shape_sphere 0 -5 0 0 0.5\n");
    EXPECT_TRUE(view::group_box_lines(desc, 0).empty());
    const auto one = view::group_box_lines(desc, 1);
    ASSERT_EQ(one.size(), 24u);  // one box: 12 edges
    Bounds3 b;
    for (const view::LineVertex& v : one)
        b.extend(Vec3(v.position[0], v.position[1], v.position[2]));
    // The outer group: its sphere [1, 3] x [-1, 1] and the inner box scaled by 2 in x, moved by
    // (2, 5, 0): [1, 3] x [4.5, 5.5]; not the top-level sphere at x = -5.
    EXPECT_NEAR(b.lo.x, 1.0, 1e-6);
    EXPECT_NEAR(b.hi.x, 3.0, 1e-6);
    EXPECT_NEAR(b.lo.y, -1.0, 1e-6);
    EXPECT_NEAR(b.hi.y, 5.5, 1e-6);
    EXPECT_EQ(view::group_box_lines(desc, 2).size(), 48u);
    EXPECT_EQ(view::group_box_lines(desc, 8).size(), 48u);
}

// The bounds of `lines` (pairs of vertices) from vertex `first` on, `count` vertices.
Bounds3 line_bounds(const std::vector<view::LineVertex>& lines, size_t first, size_t count) {
    Bounds3 b;
    for (size_t i = first; i < first + count && i < lines.size(); ++i)
        b.extend(Vec3(lines[i].position[0], lines[i].position[1], lines[i].position[2]));
    return b;
}

// CSG nodes get a box each (intersection: the operands' boxes intersected; difference: A's),
// their operands one level deeper; an operand that only wraps a transform adds no level.
TEST(Overlay, GroupBoxesIncludeCsgNodes) {
    SceneDesc desc;
    desc.dialect = Dialect::V3;
    desc.files.resize(1);
    GroupDesc& root = desc.files[0].root;
    CsgDesc lens;
    lens.op = CsgOp::Intersection;
    lens.operands = {operand(Sphere{Vec3(0.0), 1.0}), operand(Box{Vec3(1, 0, 0), Vec3(1.0)})};
    CsgDesc ring;
    ring.op = CsgOp::Difference;
    GroupDesc moved;  // a #static_affine of a sphere, wrapped as the operand A
    moved.matrix[3] = glm::dvec4(5, 0, 0, 1);
    moved.shapes.push_back(shape(Sphere{Vec3(0.0), 1.0}));
    GroupDesc a;
    a.groups.push_back(moved);
    ring.operands = {a, operand(Box{Vec3(5, 0, 0), Vec3(10.0)})};
    root.csgs = {lens, ring};
    const auto one = view::group_box_lines(desc, 1);
    ASSERT_EQ(one.size(), 2u * 24);  // the two nodes
    const Bounds3 lens_box = line_bounds(one, 0, 24), ring_box = line_bounds(one, 24, 24);
    EXPECT_VEC_NEAR(lens_box.lo, Vec3(0, -1, -1), 1e-6);
    EXPECT_VEC_NEAR(lens_box.hi, Vec3(1, 1, 1), 1e-6);
    EXPECT_VEC_NEAR(ring_box.lo, Vec3(4, -1, -1), 1e-6);  // A's box, not B's
    EXPECT_VEC_NEAR(ring_box.hi, Vec3(6, 1, 1), 1e-6);
    // Level 2: the lens's two operands, the ring's moved sphere (its wrapper adds no box) and
    // its box B.
    EXPECT_EQ(view::group_box_lines(desc, 2).size(), 6u * 24);
    EXPECT_EQ(view::group_box_lines(desc, 8).size(), 6u * 24);
    // The BVH overlay ends with the compiled nodes' boxes: the same two.
    const auto bvh = view::overlay_lines(compile_scene(desc), {false, -1, false}, 1);
    ASSERT_GE(bvh.size(), 4u * 24);
    const Bounds3 lens_node = line_bounds(bvh, bvh.size() - 48, 24);
    const Bounds3 ring_node = line_bounds(bvh, bvh.size() - 24, 24);
    EXPECT_VEC_NEAR(lens_node.lo, lens_box.lo, 1e-6);
    EXPECT_VEC_NEAR(lens_node.hi, lens_box.hi, 1e-6);
    EXPECT_VEC_NEAR(ring_node.lo, ring_box.lo, 1e-6);
    EXPECT_VEC_NEAR(ring_node.hi, ring_box.hi, 1e-6);
}

}  // namespace
}  // namespace rt
