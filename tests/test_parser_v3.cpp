// V3 parser tests (spec §13, §10 detection, §14.2 binding): every directive with its argument
// order, the file order rule, lists, transforms, CSG, paths, missing textures, every error
// message, and the public V3 scenes.
#include <filesystem>
#include <fstream>
#include <set>

#include "test_util.h"

namespace rt {
namespace {

namespace fs = std::filesystem;
using test::parse;
using test::parse_error;

const std::string kMat = "#material 0 0 0  .1 .1 .1  .5 .5 .5  .2 .2 .2  10  0 0 0  1  -1 !!\n";
const std::string kAffineId = "#static_affine 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n";

ParseOptions v3_options() {
    ParseOptions o;
    o.dialect = Dialect::V3;
    return o;
}

// A scene read as V3 (--dialect v3): one material, then `shapes`.
SceneDesc v3(const std::string& shapes, Diagnostics* diag = nullptr) {
    return parse(kMat + shapes, diag, v3_options());
}
std::string v3_error(const std::string& text) { return parse_error(text, v3_options()); }

#define EXPECT_HAS(haystack, needle) \
    EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

bool has_warning(const Diagnostics& d, const std::string& text) {
    for (const Warning& w : d.warnings())
        if (w.str().find(text) != std::string::npos) return true;
    return false;
}

int count_warnings(const Diagnostics& d, const std::string& kind) {
    int n = 0;
    for (const Warning& w : d.warnings()) n += w.kind == kind ? 1 : 0;
    return n;
}

// ---- detection (spec §10) ----------------------------------------------------------------

TEST(ParserV3Detect, AV3MarkerMakesTheTreeV3) {
    EXPECT_EQ(parse(kMat + "#shape_torus 0 0 0 0 0.25 1\n").dialect, Dialect::V3);
    EXPECT_EQ(parse("#shader a.vs a.fs\n").dialect, Dialect::V3);
    // A light with the V3 number count is a marker too.
    EXPECT_EQ(parse("#light_point 1 1 1  1 1 1  1 1 1  0 0 0  1 0 0\n").dialect, Dialect::V3);
    // No marker of either kind: V1, never V3.
    EXPECT_EQ(parse(kMat + "#shape_sphere 0 0 0 0 1\n").dialect, Dialect::V1);
}

TEST(ParserV3Detect, MixedDialectsNameBothMarkers) {
    EXPECT_HAS(parse_error(kAffineId + "#shape_sphere 0 0 0 0 1\n#group_begin 1 0 0 0 0 1 0 0 0 "
                                       "0 1 0 0 0 0 1\n#group_end\n"),
               "test.ray:3:1: error: mixed dialects: V3 '#static_affine' at test.ray:1:1, V1 "
               "'#group_begin' at test.ray:3:1");
    // The V3 marker second: the error is at it.
    EXPECT_HAS(parse_error("#ambient 1 1 1\n#light_dir 1 1 1 1 1 1 1 1 1 0 -1 0\n"),
               "test.ray:2:1: error: mixed dialects: V3 '#light_dir' at test.ray:2:1, V1 "
               "'#ambient' at test.ray:1:1");
    // V0/V1 markers: counts, a 4-integer triangle, a 16-number material, a V1 light.
    EXPECT_HAS(parse_error("#shader a b\n#vertex_num 0\n"), "V1 '#vertex_num' at test.ray:2:1");
    EXPECT_HAS(parse_error("#shader a b\n#shape_triangle 0 0 1 2\n"),
               "V1 '#shape_triangle' at test.ray:2:1");
    EXPECT_HAS(parse_error("#shader a b\n#material .1 .1 .1  .5 .5 .5  .2 .2 .2  0 0 0  .5 .25 "
                           "1.5 -1 !!\n"),
               "mixed dialects: V3 '#shader' at test.ray:1:1, V0 '#material' at test.ray:2:1");
    EXPECT_HAS(parse_error("#shader a b\n#light_point 1 1 1 0 0 0 1 0 0\n"),
               "V1 '#light_point' at test.ray:2:1");
}

TEST(ParserV3Detect, LightWithAnotherCountIsAnError) {
    EXPECT_HAS(parse_error("#light_point 1 1 1  1 1 1  1 1 1  1 0 0\n"),
               "test.ray:1:1: error: #light_point needs 9 (V0/V1) or 15 (V3) numbers, got 12");
    EXPECT_HAS(parse_error("#light_dir 1 1 1 1 1 1 1 1\n"),
               "#light_dir needs 6 (V0/V1) or 12 (V3) numbers, got 8");
    EXPECT_HAS(parse_error("#light_spot 1 1 1\n"),
               "#light_spot needs 14 (V0/V1) or 20 (V3) numbers, got 3");
}

TEST(ParserV3Detect, OtherFormatsNamedRay) {
    EXPECT_HAS(parse_error("SBT-raytracer 1.0\ncamera {}\n"),
               "test.ray:1:1: error: this is an SBT-raytracer scene (U. Washington CSE 457 / UT "
               "Austin CS 354 format), not a Kazhdan .ray file");
    EXPECT_HAS(parse_error("#shader a b\n#version 1\n"),
               "test.ray:2:1: error: '#version' belongs to the HMC CS155 ray format, not a "
               "Kazhdan .ray file");
    // Checked under --dialect too.
    EXPECT_HAS(v3_error("SBT-raytracer 1.0\n"), "SBT-raytracer scene");
}

TEST(ParserV3Detect, DialectOverride) {
    EXPECT_HAS(v3_error("#ambient 1 1 1\n"),
               "test.ray:1:1: error: '#ambient' is V0/V1 syntax; the tree was forced to V3 by "
               "--dialect v3");
    EXPECT_HAS(v3_error("#light_dir 1 1 1 0 -1 0\n"),
               "'#light_dir' with 6 numbers is V0/V1 syntax; the tree was forced to V3");
    EXPECT_HAS(v3_error("#material .1 .1 .1  .5 .5 .5  .2 .2 .2  0 0 0  .5 .25 1.5 -1 !!\n"),
               "test.ray:1:1: error: #material has 16 numbers, but --dialect v3 needs 18");
    ParseOptions v1;
    v1.dialect = Dialect::V1;
    EXPECT_HAS(parse_error(kMat + kAffineId + "#shape_sphere 0 0 0 0 1\n", v1),
               "test.ray:2:1: error: '#static_affine' is V3 syntax; the tree was forced to V1 by "
               "--dialect v1");
    // A file without markers read as V3.
    EXPECT_EQ(v3("#shape_sphere 0 0 0 0 1\n").dialect, Dialect::V3);
}

// ---- global directives (spec §13.3) ---------------------------------------------------------

TEST(ParserV3Global, CameraLastWinsAndAllZeroIsTheDefault) {
    Diagnostics diag;
    SceneDesc s = parse("#camera 1 2 3  0 0 -1  0 1 0  0.5\n#camera 4 5 6  0 0 -1  0 1 0  0.25\n",
                        &diag, v3_options());
    ASSERT_TRUE(s.camera);
    EXPECT_EQ(s.camera->position, Vec3(4, 5, 6));
    EXPECT_EQ(s.camera->half_height_angle_rad, 0.25);
    EXPECT_TRUE(has_warning(diag, "test.ray:2:1: warning: second #camera: the last one wins"));
    Diagnostics zero;
    s = parse("#camera 0 0 0 0 0 0 0 0 0 0\n", &zero, v3_options());
    EXPECT_FALSE(s.camera);
    EXPECT_TRUE(has_warning(zero, "test.ray:1:1: warning: all-zero #camera"));
    EXPECT_HAS(v3_error("#camera 0 0 0  0 0 0  0 1 0  0.5\n"),
               "test.ray:1:1: error: camera view direction is zero");
    EXPECT_HAS(v3_error("#camera 0 0 0  0 0 -1  0 1 0\n"),
               "test.ray:1:1: error: expected 10 numbers after #camera, got end of file");
}

TEST(ParserV3Global, LightsHaveThreeColoursInOrder) {
    // Spec §13.10's light: A, D, S, position, ca la qa.
    const SceneDesc s = parse(
        "#light_point 0.5 0.5 0.5  1 0.5 1  0.2 0.4 0.6  5 5 5  0.01 0.02 0.03\n"
        "#light_dir .1 .2 .3  .4 .5 .6  .7 .8 .9  0 -1 0\n"
        "#light_spot 0 0 0  1 1 1  1 1 1  0 5 0  0 -1 0  1 0 0  0.5 2\n"
        "#light_sphere .1 .1 .1  1 1 1  .5 .5 .5  1 2 3  0.25  1 0 0.1\n");
    ASSERT_EQ(s.lights.size(), 4u);
    const LightDesc& p = s.lights[0];
    EXPECT_EQ(p.kind, LightKind::Point);
    EXPECT_EQ(p.ambient, Vec3(0.5, 0.5, 0.5));
    EXPECT_EQ(p.diffuse, Vec3(1, 0.5, 1));
    EXPECT_EQ(p.specular, Vec3(0.2, 0.4, 0.6));
    EXPECT_EQ(p.position, Vec3(5, 5, 5));
    EXPECT_EQ(p.constant_atten, 0.01);
    EXPECT_EQ(p.linear_atten, 0.02);
    EXPECT_EQ(p.quadratic_atten, 0.03);
    const LightDesc& d = s.lights[1];
    EXPECT_EQ(d.kind, LightKind::Directional);
    EXPECT_EQ(d.ambient, Vec3(.1, .2, .3));
    EXPECT_EQ(d.diffuse, Vec3(.4, .5, .6));
    EXPECT_EQ(d.specular, Vec3(.7, .8, .9));
    EXPECT_EQ(d.direction, Vec3(0, -1, 0));
    const LightDesc& sp = s.lights[2];
    EXPECT_EQ(sp.kind, LightKind::Spot);
    EXPECT_EQ(sp.position, Vec3(0, 5, 0));
    EXPECT_EQ(sp.direction, Vec3(0, -1, 0));
    EXPECT_EQ(sp.cutoff_rad, 0.5);
    EXPECT_EQ(sp.spot_exponent, 2.0);  // p = dropoff, not 128 dropoff
    const LightDesc& sph = s.lights[3];
    EXPECT_EQ(sph.kind, LightKind::Sphere);
    EXPECT_EQ(sph.position, Vec3(1, 2, 3));
    EXPECT_EQ(sph.radius, 0.25);
    EXPECT_EQ(sph.quadratic_atten, 0.1);
    EXPECT_EQ(s.dialect, Dialect::V3);
}

TEST(ParserV3Global, SphereLightRadius) {
    Diagnostics diag;
    const SceneDesc s =
        parse("#light_sphere 0 0 0  1 1 1  1 1 1  1 2 3  0  1 0 0\n", &diag, v3_options());
    EXPECT_EQ(s.lights[0].kind, LightKind::Point);  // radius 0 acts as a point light
    EXPECT_TRUE(has_warning(diag, "#light_sphere of radius 0 acts as a point light"));
    EXPECT_HAS(parse_error("#light_sphere 0 0 0  1 1 1  1 1 1  1 2 3  -1  1 0 0\n"),
               "test.ray:1:43: error: negative sphere light radius -1");
    EXPECT_HAS(v3_error("#light_sphere 0 0 0  1 1 1  1 1 1  1 2 3  1  1 0\n"),
               "test.ray:1:1: error: expected 16 numbers after #light_sphere, got end of file");
}

TEST(ParserV3Global, ShaderIsRecordedAndTheLastWins) {
    const SceneDesc s = parse("#shader a.vs a.fs\n#shader b.vs b.fs\n");
    EXPECT_EQ(s.shader_vertex, "b.vs");
    EXPECT_EQ(s.shader_fragment, "b.fs");
}

// ---- file order (spec §13.1) --------------------------------------------------------------------

TEST(ParserV3Order, GlobalThenLocalThenShapes) {
    EXPECT_HAS(v3_error(kMat + "#light_point 1 1 1 1 1 1 1 1 1 0 0 0 1 0 0\n"),
               "test.ray:2:1: error: '#light_point' after the local part started at test.ray:1:1 "
               "(V3 order: global, local, shapes)");
    EXPECT_HAS(v3_error(kMat + "#shape_sphere 0 0 0 0 1\n" + kMat),
               "test.ray:3:1: error: '#material' after the shapes part started at test.ray:2:1 "
               "(V3 order: global, local, shapes)");
    EXPECT_HAS(v3_error(kMat + "#shape_sphere 0 0 0 0 1\n#camera 0 0 1 0 0 -1 0 1 0 .5\n"),
               "'#camera' after the shapes part started at test.ray:2:1");
    // Any part may be empty.
    EXPECT_EQ(v3("#shape_sphere 0 0 0 0 1\n").files[0].root.shapes.size(), 1u);
}

// ---- shapes, transforms, lists (spec §13.5, §13.6) ------------------------------------------

TEST(ParserV3Shapes, StaticAffineIsColumnMajor) {
    // Spec §13.6's first example: diag(0.5, 1, 0.5), then the translation (0, 2.5, 0).
    SceneDesc s =
        v3("#static_affine 0.5 0 0 0  0 1 0 0  0 0 0.5 0  0 2.5 0 1\n"
           "  #shape_sphere 0 0 0 0 1\n");
    ASSERT_EQ(s.files[0].root.groups.size(), 1u);
    const GroupDesc& g = s.files[0].root.groups[0];
    EXPECT_EQ(g.matrix * glm::dvec4(1, 1, 1, 1), glm::dvec4(0.5, 3.5, 0.5, 1));
    ASSERT_EQ(g.shapes.size(), 1u);
    EXPECT_EQ(g.loc.line, 2);  // after the material
    // The second: rows 1 0 1 / 0 1 0 / -1 0 1.
    s = v3("#static_affine 1 0 -1 0  0 1 0 0  1 0 1 0  0 0 0 1\n#shape_sphere 0 0 0 0 1\n");
    const Mat4& m = s.files[0].root.groups[0].matrix;
    EXPECT_EQ(m * glm::dvec4(1, 0, 0, 0), glm::dvec4(1, 0, -1, 0));  // column 1
    EXPECT_EQ(m * glm::dvec4(0, 0, 1, 0), glm::dvec4(1, 0, 1, 0));   // column 3
    // Read row by row, the first example puts its translation into the bottom row: an error.
    EXPECT_HAS(v3_error(kMat + "#static_affine 0.5 0 0 0  0 1 0 2.5  0 0 0.5 0  0 0 0 1\n"
                               "#shape_sphere 0 0 0 0 1\n"),
               "test.ray:2:1: error: projective #static_affine matrix: the bottom row must be 0 "
               "0 0 1");
    EXPECT_HAS(v3_error(kMat + "#static_affine 1 0 0 0  0 0 0 0  0 0 1 0  0 0 0 1\n"
                               "#shape_sphere 0 0 0 0 1\n"),
               "test.ray:2:1: error: singular #static_affine matrix");
    EXPECT_HAS(v3_error(kMat + "#static_affine 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0\n"
                               "#shape_sphere 0 0 0 0 1\n"),
               "test.ray:2:1: error: expected 16 numbers after #static_affine, got "
               "'#shape_sphere'");
}

TEST(ParserV3Shapes, AffineTakesExactlyOneShapeAndCommentsMaySitBetween) {
    const SceneDesc s = v3(kAffineId + "// the ball\n  // twice\n#shape_sphere 0 0 0 0 1\n" +
                           "#shape_sphere 0 1 0 0 1\n");
    EXPECT_EQ(s.files[0].root.groups.size(), 1u);
    EXPECT_EQ(s.files[0].root.groups[0].shapes.size(), 1u);
    EXPECT_EQ(s.files[0].root.shapes.size(), 1u);  // the second sphere is the root's
    EXPECT_HAS(v3_error(kMat + kAffineId),
               "test.ray:3:1: error: #static_affine at test.ray:2:1 has no shape before end of "
               "file");
    EXPECT_HAS(v3_error(kMat + "#shape_list_begin\n" + kAffineId + "#shape_list_end\n"),
               "test.ray:4:1: error: #static_affine at test.ray:3:1 has no shape before "
               "#shape_list_end");
}

TEST(ParserV3Shapes, AnAffineOfAListIsThatList) {
    // scene_desc.h: the list folds into the transform, so the writer's text parses back the same.
    const SceneDesc s =
        v3("#static_affine 2 0 0 0  0 2 0 0  0 0 2 0  1 2 3 1\n"
           "#shape_list_begin\n#shape_sphere 0 0 0 0 1\n#shape_box 0 0 0 0 1 1 1\n"
           "#shape_list_end\n");
    const GroupDesc& root = s.files[0].root;
    ASSERT_EQ(root.groups.size(), 1u);
    const GroupDesc& g = root.groups[0];
    EXPECT_EQ(Vec3(g.matrix[3]), Vec3(1, 2, 3));
    EXPECT_EQ(g.shapes.size(), 2u);
    EXPECT_TRUE(g.groups.empty());
    // An affine of an affine nests.
    const SceneDesc n = v3(kAffineId + kAffineId + "#shape_sphere 0 0 0 0 1\n");
    ASSERT_EQ(n.files[0].root.groups.size(), 1u);
    EXPECT_EQ(n.files[0].root.groups[0].groups.size(), 1u);
    EXPECT_EQ(n.files[0].root.groups[0].groups[0].shapes.size(), 1u);
}

TEST(ParserV3Shapes, Lists) {
    const SceneDesc s =
        v3("#shape_list_begin\n#shape_list_begin\n#shape_list_end\n"
           "#shape_sphere 0 0 0 0 1\n#shape_list_end\n");
    const GroupDesc& root = s.files[0].root;
    ASSERT_EQ(root.groups.size(), 1u);
    EXPECT_EQ(root.groups[0].matrix, Mat4(1.0));
    EXPECT_EQ(root.groups[0].shapes.size(), 1u);
    EXPECT_EQ(root.groups[0].groups.size(), 1u);  // the empty list is valid
    EXPECT_HAS(v3_error(kMat + "#shape_list_end\n"),
               "test.ray:2:1: error: #shape_list_end without #shape_list_begin");
    EXPECT_HAS(v3_error(kMat + "#shape_list_begin\n#shape_sphere 0 0 0 0 1\n"),
               "test.ray:4:1: error: #shape_list_begin at test.ray:2:1 is never closed");
}

TEST(ParserV3Shapes, TriangleLists) {
    const std::string verts =
        "#vertex 0 0 0  0 0 0  0 0\n#vertex 1 0 0  0 0 0  1 0\n#vertex 0 1 0  0 0 1  0 1\n";
    const SceneDesc s = v3(kMat + verts +
                           "#shape_triangles 1\n// the mesh\n#shape_list_begin\n"
                           "#shape_triangle 0 1 2\n#shape_triangle 2 1 0\n#shape_list_end\n");
    ASSERT_EQ(s.files[0].root.groups.size(), 1u);
    const GroupDesc& g = s.files[0].root.groups[0];
    ASSERT_EQ(g.shapes.size(), 2u);
    EXPECT_EQ(g.shapes[0].material, 1);  // every triangle takes the list's material
    EXPECT_EQ(g.shapes[1].material, 1);
    EXPECT_EQ(std::get<TriangleDesc>(g.shapes[1].geometry), (TriangleDesc{{2, 1, 0}}));
    const std::string pre = kMat + verts;
    EXPECT_HAS(v3_error(pre + "#shape_triangles 0\n#shape_sphere 0 0 0 0 1\n"),
               "test.ray:6:1: error: #shape_triangles at test.ray:5:1 expects "
               "#shape_list_begin, got '#shape_sphere'");
    EXPECT_HAS(v3_error(pre + "#shape_triangle 0 1 2\n"),
               "test.ray:5:1: error: #shape_triangle outside #shape_triangles");
    EXPECT_HAS(v3_error(pre + "#shape_list_begin\n#shape_triangle 0 1 2\n#shape_list_end\n"),
               "test.ray:6:1: error: #shape_triangle outside #shape_triangles");
    EXPECT_HAS(v3_error(pre + "#shape_triangles 0\n#shape_list_begin\n#shape_sphere 0 0 0 0 1\n"
                              "#shape_list_end\n"),
               "test.ray:7:1: error: '#shape_sphere' inside the list of #shape_triangles at "
               "test.ray:5:1 (only #shape_triangle may be there)");
    EXPECT_HAS(v3_error(pre + "#shape_triangles 0\n#shape_list_begin\n#shape_triangle 0 1 2\n"),
               "test.ray:8:1: error: the #shape_list_begin of #shape_triangles at test.ray:5:1 "
               "is never closed");
    EXPECT_HAS(v3_error(pre + "#shape_triangles 0\n#shape_list_begin\n#shape_triangle 0 1 5\n"),
               "test.ray:7:21: error: vertex index 5 out of range [0,3)");
    EXPECT_HAS(v3_error(pre + "#shape_triangles 0\n"),
               "test.ray:6:1: error: #shape_triangles at test.ray:5:1 expects "
               "#shape_list_begin, got end of file");
    // A degenerate triangle is skipped with a warning.
    Diagnostics diag;
    const SceneDesc d = v3(pre +
                               "#shape_triangles 0\n#shape_list_begin\n#shape_triangle 0 0 2\n"
                               "#shape_list_end\n",
                           &diag);
    EXPECT_EQ(d.skipped_shapes, 1u);
    EXPECT_TRUE(d.files[0].root.groups[0].shapes.empty());
}

TEST(ParserV3Shapes, TorusArgumentOrder) {
    Diagnostics diag;
    const SceneDesc s =
        v3("#shape_torus 0  1 2 3  0.25 2\n#shape_torus 0  0 0 0  0.1 0.01\n", &diag);
    ASSERT_EQ(s.files[0].root.shapes.size(), 2u);
    const Torus t = std::get<Torus>(s.files[0].root.shapes[0].geometry);
    EXPECT_EQ(t.centre, Vec3(1, 2, 3));
    EXPECT_EQ(t.tube, 0.25);  // iRadius: the minor radius
    EXPECT_EQ(t.ring, 2.0);   // oRadius: the major radius
    EXPECT_TRUE(has_warning(diag,
                            "test.ray:3:1: warning: spindle torus (iRadius 0.1 > oRadius "
                            "0.01): only its outer surface exists"));
    EXPECT_HAS(v3_error(kMat + "#shape_torus 0 0 0 0 -1 2\n"),
               "test.ray:2:22: error: negative torus radius -1");
    EXPECT_HAS(v3_error(kMat + "#shape_torus 0 0 0 0 1 -2\n"),
               "test.ray:2:24: error: negative torus radius -2");
    EXPECT_HAS(v3_error(kMat + "#shape_torus 0 0 0 0 1\n#shape_sphere 0 0 0 0 1\n"),
               "test.ray:2:1: error: expected 5 numbers after #shape_torus, got '#shape_sphere'");
    EXPECT_HAS(v3_error(kMat + "#shape_torus 0 0 0 0 1 nan\n"),
               "test.ray:2:24: error: non-finite number 'nan'");
    EXPECT_HAS(v3_error(kMat + "#shape_torus 3 0 0 0 1 2\n"),
               "test.ray:2:14: error: material index 3 out of range [0,1)");
    Diagnostics skip;
    const SceneDesc z = v3("#shape_torus 0 0 0 0 0 2\n", &skip);
    EXPECT_TRUE(z.files[0].root.shapes.empty());
    EXPECT_EQ(z.skipped_shapes, 1u);
    EXPECT_TRUE(has_warning(skip, "torus with a zero radius skipped"));
}

TEST(ParserV3Shapes, ClassicPrimitivesAndInstances) {
    const SceneDesc s =
        v3("#shape_sphere 0 1 2 3 4\n#shape_box 0 0 0 0 1 2 3\n"
           "#shape_cylinder 0 0 0 0 1 2\n#shape_cone 0 0 0 0 1 2\n");
    ASSERT_EQ(s.files[0].root.shapes.size(), 4u);
    EXPECT_EQ(std::get<Sphere>(s.files[0].root.shapes[0].geometry).radius, 4.0);
    EXPECT_EQ(std::get<BoxDesc>(s.files[0].root.shapes[1].geometry).size, Vec3(1, 2, 3));
    EXPECT_HAS(v3_error(kMat + "#shape_sphere -1 0 0 0 1\n"), "material index -1 out of range");
    EXPECT_HAS(v3_error(kMat + "#ray_file_instance 0\n"),
               "test.ray:2:20: error: ray file index 0 out of range [0,0)");
    EXPECT_HAS(v3_error(kMat + "#shape_bogus 0\n"),
               "test.ray:2:1: error: unknown directive '#shape_bogus'");
}

// ---- CSG (spec §13.8) ---------------------------------------------------------------------------

TEST(ParserV3Csg, OperandsAreOneChildEach) {
    const SceneDesc s =
        v3("#shape_intersection\n  #shape_list_begin\n"
           "    #shape_sphere 0 0 -0.95 0 1.5\n"
           "    #shape_list_begin #shape_box 0 0 0 0 1 1 1 #shape_box 0 1 1 1 1 1 "
           "1 #shape_list_end\n" +
           kAffineId + "    #shape_cylinder 0 0 0 0 1 2\n  #shape_list_end\n");
    const GroupDesc& root = s.files[0].root;
    ASSERT_EQ(root.csgs.size(), 1u);
    const CsgDesc& c = root.csgs[0];
    EXPECT_EQ(c.op, CsgOp::Intersection);
    EXPECT_EQ(c.loc.line, 2);
    ASSERT_EQ(c.operands.size(), 3u);
    EXPECT_EQ(c.operands[0].shapes.size(), 1u);  // the sphere, wrapped
    EXPECT_EQ(c.operands[1].shapes.size(), 2u);  // the list is the operand
    EXPECT_TRUE(c.operands[1].groups.empty());
    ASSERT_EQ(c.operands[2].groups.size(), 1u);  // the transform, wrapped
    EXPECT_EQ(c.operands[2].groups[0].shapes.size(), 1u);
    EXPECT_EQ(c.operands[2].matrix, Mat4(1.0));
}

TEST(ParserV3Csg, DifferenceTakesTwoShapes) {
    const SceneDesc s =
        v3("#shape_difference\n   #shape_cylinder 0 0 0 0 1.1 0.3\n"
           "   #shape_cylinder 0 0 0 0 1 1\n#shape_sphere 0 0 0 0 1\n");
    const GroupDesc& root = s.files[0].root;
    ASSERT_EQ(root.csgs.size(), 1u);
    EXPECT_EQ(root.csgs[0].op, CsgOp::Difference);
    ASSERT_EQ(root.csgs[0].operands.size(), 2u);
    EXPECT_EQ(std::get<Cylinder>(root.csgs[0].operands[0].shapes[0].geometry).radius, 1.1);
    EXPECT_EQ(std::get<Cylinder>(root.csgs[0].operands[1].shapes[0].geometry).radius, 1.0);
    EXPECT_EQ(root.shapes.size(), 1u);  // the sphere after it is the root's
    EXPECT_HAS(v3_error(kMat + "#shape_difference\n#shape_sphere 0 0 0 0 1\n"),
               "test.ray:4:1: error: #shape_difference at test.ray:2:1 needs two shapes, got 1 "
               "before end of file");
    EXPECT_HAS(v3_error(kMat + "#shape_list_begin\n#shape_difference\n#shape_sphere 0 0 0 0 1\n"
                               "#shape_list_end\n"),
               "test.ray:5:1: error: #shape_difference at test.ray:3:1 needs two shapes, got 1 "
               "before #shape_list_end");
}

TEST(ParserV3Csg, UnionNeedsAListAndAnEmptyOneWarns) {
    EXPECT_HAS(v3_error(kMat + "#shape_union\n#shape_sphere 0 0 0 0 1\n"),
               "test.ray:3:1: error: #shape_union at test.ray:2:1 expects #shape_list_begin, got "
               "'#shape_sphere'");
    EXPECT_HAS(v3_error(kMat + "#shape_intersection #shape_list_begin #shape_sphere 0 0 0 0 1\n"),
               "error: the #shape_list_begin of #shape_intersection at test.ray:2:1 is never "
               "closed");
    Diagnostics diag;
    const SceneDesc s = v3("#shape_union\n#shape_list_begin\n#shape_list_end\n", &diag);
    ASSERT_EQ(s.files[0].root.csgs.size(), 1u);
    EXPECT_TRUE(s.files[0].root.csgs[0].operands.empty());
    EXPECT_EQ(s.files[0].root.csgs[0].op, CsgOp::Union);
    EXPECT_TRUE(has_warning(diag,
                            "test.ray:2:1: warning: #shape_union with an empty list: the "
                            "node is empty"));
}

TEST(ParserV3Csg, ADegenerateShapeIsAnEmptyOperand) {
    Diagnostics diag;
    const SceneDesc s =
        v3("#shape_difference #shape_sphere 0 0 0 0 1 #shape_sphere 0 0 0 0 0\n", &diag);
    ASSERT_EQ(s.files[0].root.csgs[0].operands.size(), 2u);
    const GroupDesc& b = s.files[0].root.csgs[0].operands[1];
    EXPECT_TRUE(b.shapes.empty() && b.groups.empty() && b.csgs.empty() && b.instances.empty());
    EXPECT_EQ(s.skipped_shapes, 1u);
}

TEST(ParserV3Csg, NestingIsBoundedWithoutRecursion) {
    std::string deep;
    for (int i = 0; i < 100; ++i) deep += "#shape_difference\n";
    std::string ok = deep + "#shape_sphere 0 0 0 0 1\n";
    for (int i = 0; i < 100; ++i) ok += "#shape_sphere 0 0 0 0 1\n";
    EXPECT_EQ(v3(ok).files[0].root.csgs.size(), 1u);  // 100 deep is fine
    EXPECT_HAS(v3_error(kMat + deep + "#shape_difference\n"),
               "test.ray:102:1: error: '#shape_difference' nests CSG nodes deeper than 100 levels");
    std::string csg;
    for (int i = 0; i < 10000; ++i) csg += "#shape_union #shape_list_begin\n";
    EXPECT_HAS(v3_error(kMat + csg), "nests CSG nodes deeper than 100 levels");
    std::string affines;
    for (int i = 0; i < 10000; ++i) affines += kAffineId;
    EXPECT_HAS(v3_error(kMat + affines + "#shape_torus 0 0 0 0 1 2\n"),
               "test.ray:1002:1: error: '#static_affine' nests V3 shapes deeper than 1000 levels");
    std::string lists;
    for (int i = 0; i < 10000; ++i) lists += "#shape_list_begin\n";
    EXPECT_HAS(v3_error(kMat + lists), "nests V3 shapes deeper than 1000 levels");
    std::string fine;
    for (int i = 0; i < 999; ++i) fine += kAffineId;
    EXPECT_EQ(v3(fine + "#shape_sphere 0 0 0 0 1\n").files[0].root.groups.size(), 1u);
}

// ---- files: includes, paths, textures, key files ---------------------------------------------

class ParserV3Files : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() /
              ("rt_parser_v3_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir / "sub");
    }
    void TearDown() override { fs::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) {
        const auto p = dir / name;
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
    SceneDesc load(const std::string& path, Diagnostics* diag = nullptr, ParseOptions o = {}) {
        Diagnostics local;
        return parse_scene_file(path, diag ? *diag : local, o);
    }
    std::string load_error(const std::string& path, ParseOptions o = {}) {
        try {
            load(path, nullptr, o);
        } catch (const SceneError& e) {
            return e.what();
        }
        return "";
    }
    std::string d() const { return dir.string(); }
    fs::path dir;
};

const char kRedJpeg[] =
    "\xff\xd8\xff\xe0\x00\x10\x4a\x46\x49\x46\x00\x01\x01\x00\x00\x01\x00\x01\x00\x00\xff\xdb\x00"
    "\x84"
    "\x00\x02\x01\x01\x01\x01\x01\x02\x01\x01\x01\x02\x02\x02\x02\x02\x04\x03\x02\x02\x02\x02\x05"
    "\x04"
    "\x04\x03\x04\x06\x05\x06\x06\x06\x05\x06\x06\x06\x07\x09\x08\x06\x07\x09\x07\x06\x06\x08\x0b"
    "\x08"
    "\x09\x0a\x0a\x0a\x0a\x0a\x06\x08\x0b\x0c\x0b\x0a\x0c\x09\x0a\x0a\x0a\x01\x02\x02\x02\x02\x02"
    "\x02"
    "\x05\x03\x03\x05\x0a\x07\x06\x07\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a"
    "\x0a"
    "\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a"
    "\x0a"
    "\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\x0a\xff\xc0\x00\x11\x08\x00\x04\x00\x04\x03\x01\x11\x00"
    "\x02"
    "\x11\x01\x03\x11\x01\xff\xc4\x01\xa2\x00\x00\x01\x05\x01\x01\x01\x01\x01\x01\x00\x00\x00\x00"
    "\x00"
    "\x00\x00\x00\x01\x02\x03\x04\x05\x06\x07\x08\x09\x0a\x0b\x10\x00\x02\x01\x03\x03\x02\x04\x03"
    "\x05"
    "\x05\x04\x04\x00\x00\x01\x7d\x01\x02\x03\x00\x04\x11\x05\x12\x21\x31\x41\x06\x13\x51\x61\x07"
    "\x22"
    "\x71\x14\x32\x81\x91\xa1\x08\x23\x42\xb1\xc1\x15\x52\xd1\xf0\x24\x33\x62\x72\x82\x09\x0a\x16"
    "\x17"
    "\x18\x19\x1a\x25\x26\x27\x28\x29\x2a\x34\x35\x36\x37\x38\x39\x3a\x43\x44\x45\x46\x47\x48\x49"
    "\x4a"
    "\x53\x54\x55\x56\x57\x58\x59\x5a\x63\x64\x65\x66\x67\x68\x69\x6a\x73\x74\x75\x76\x77\x78\x79"
    "\x7a"
    "\x83\x84\x85\x86\x87\x88\x89\x8a\x92\x93\x94\x95\x96\x97\x98\x99\x9a\xa2\xa3\xa4\xa5\xa6\xa7"
    "\xa8"
    "\xa9\xaa\xb2\xb3\xb4\xb5\xb6\xb7\xb8\xb9\xba\xc2\xc3\xc4\xc5\xc6\xc7\xc8\xc9\xca\xd2\xd3\xd4"
    "\xd5"
    "\xd6\xd7\xd8\xd9\xda\xe1\xe2\xe3\xe4\xe5\xe6\xe7\xe8\xe9\xea\xf1\xf2\xf3\xf4\xf5\xf6\xf7\xf8"
    "\xf9"
    "\xfa\x01\x00\x03\x01\x01\x01\x01\x01\x01\x01\x01\x01\x00\x00\x00\x00\x00\x00\x01\x02\x03\x04"
    "\x05"
    "\x06\x07\x08\x09\x0a\x0b\x11\x00\x02\x01\x02\x04\x04\x03\x04\x07\x05\x04\x04\x00\x01\x02\x77"
    "\x00"
    "\x01\x02\x03\x11\x04\x05\x21\x31\x06\x12\x41\x51\x07\x61\x71\x13\x22\x32\x81\x08\x14\x42\x91"
    "\xa1"
    "\xb1\xc1\x09\x23\x33\x52\xf0\x15\x62\x72\xd1\x0a\x16\x24\x34\xe1\x25\xf1\x17\x18\x19\x1a\x26"
    "\x27"
    "\x28\x29\x2a\x35\x36\x37\x38\x39\x3a\x43\x44\x45\x46\x47\x48\x49\x4a\x53\x54\x55\x56\x57\x58"
    "\x59"
    "\x5a\x63\x64\x65\x66\x67\x68\x69\x6a\x73\x74\x75\x76\x77\x78\x79\x7a\x82\x83\x84\x85\x86\x87"
    "\x88"
    "\x89\x8a\x92\x93\x94\x95\x96\x97\x98\x99\x9a\xa2\xa3\xa4\xa5\xa6\xa7\xa8\xa9\xaa\xb2\xb3\xb4"
    "\xb5"
    "\xb6\xb7\xb8\xb9\xba\xc2\xc3\xc4\xc5\xc6\xc7\xc8\xc9\xca\xd2\xd3\xd4\xd5\xd6\xd7\xd8\xd9\xda"
    "\xe2"
    "\xe3\xe4\xe5\xe6\xe7\xe8\xe9\xea\xf2\xf3\xf4\xf5\xf6\xf7\xf8\xf9\xfa\xff\xda\x00\x0c\x03\x01"
    "\x00"
    "\x02\x11\x03\x11\x00\x3f\x00\xf8\xc2\xbf\x94\xcf\xf7\xf8\xff\xd9";

TEST_F(ParserV3Files, IncludedFilesIgnoreTheirCameraLightsAndShader) {
    write("sub/part.ray",
          "#camera 0 0 0 0 0 0 0 0 0 0\n#light_point 1 1 1 1 1 1 1 1 1 0 0 0 1 0 0\n"
          "#light_dir 1 1 1 1 1 1 1 1 1 0 -1 0\n#shader x y\n" +
              kMat + "#shape_torus 0 0 0 0 0.25 1\n");
    Diagnostics diag;
    const SceneDesc s = load(write("top.ray",
                                   "#camera 0 0 5 0 0 -1 0 1 0 0.5\n#shader a b\n"
                                   "#ray_file sub/part.ray\n#ray_file_instance 0\n"),
                             &diag);
    EXPECT_EQ(s.dialect, Dialect::V3);
    EXPECT_TRUE(s.lights.empty());
    EXPECT_EQ(s.camera->position, Vec3(0, 0, 5));
    EXPECT_EQ(s.shader_vertex, "a");
    EXPECT_EQ(count_warnings(diag, "included-light"), 1);  // one per file
    EXPECT_FALSE(diag.has("camera-zero"));
    ASSERT_EQ(s.files.size(), 2u);
    EXPECT_EQ(s.files[1].root.shapes.size(), 1u);
    EXPECT_EQ(s.files[0].root.instances.size(), 1u);
}

// Spec §2: a diagnostic in an included file is followed by its include chain, warnings too, and
// a mixed-dialect error reported in an included file.
TEST_F(ParserV3Files, DiagnosticsInIncludedFilesNameTheirIncludes) {
    write("sub/part.ray",
          "#light_point 1 1 1 1 1 1 1 1 1 0 0 0 1 0 0\n" + kMat + "#shape_torus 0 0 0 0 0.25 1\n");
    write("mid.ray", "#ray_file sub/part.ray\n#ray_file_instance 0\n");
    const std::string top = write("top.ray",
                                  "#camera 0 0 5 0 0 -1 0 1 0 0.5\n#ray_file mid.ray\n"
                                  "#ray_file_instance 0\n");
    Diagnostics diag;
    load(top, &diag);
    ASSERT_TRUE(diag.has("included-light"));
    for (const Warning& w : diag.warnings()) {
        if (w.kind != "included-light") continue;
        EXPECT_NE(w.str().find("part.ray:1:1: warning: lights in included files are ignored\n"
                               "  included from " +
                               (dir / "mid.ray").string() +
                               ":1:1\n"
                               "  included from " +
                               top + ":2:1"),
                  std::string::npos)
            << w.str();
    }
    write("v1.ray", "#group_begin 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n#group_end\n");
    const std::string mixed = write("mixed.ray",
                                    "#light_point 1 1 1 1 1 1 1 1 1 0 0 0 1 0 0\n"
                                    "#ray_file v1.ray\n#ray_file_instance 0\n");
    const std::string e = load_error(mixed);
    EXPECT_NE(e.find("v1.ray:1:1: error: mixed dialects: V3 '#light_point' at "), std::string::npos)
        << e;
    EXPECT_NE(e.find("\n  included from " + mixed + ":2:1"), std::string::npos) << e;
}

TEST_F(ParserV3Files, PathsTryTheTopLevelDirectoryFirst) {
    // sub/mid.ray names tex.ppm and leaf.ray: found next to top.ray, not in sub/.
    const std::string ppm = "P3 1 1 255 10 20 30\n";
    write("tex.ppm", ppm);
    write("sub/tex.ppm", "P3 1 1 255 99 99 99\n");
    write("leaf.ray", kMat + "#shape_sphere 0 0 0 0 1\n");
    write("sub/mid.ray", "#texture tex.ppm\n#ray_file leaf.ray\n#ray_file_instance 0\n");
    Diagnostics diag;
    const SceneDesc s = load(write("top.ray", "#shader a b\n#ray_file sub/mid.ray\n"), &diag);
    ASSERT_EQ(s.files.size(), 3u);
    EXPECT_EQ(s.files[1].textures[0].image->rgb[0], 10);
    EXPECT_EQ(s.files[2].path, (dir / "leaf.ray").lexically_normal().string());
    EXPECT_TRUE(diag.warnings().size() <= 1u);  // only the no-camera warning
}

TEST_F(ParserV3Files, PathsFoundOnlyNextToTheIncludingFileWarn) {
    write("sub/leaf.ray", kMat + "#shape_sphere 0 0 0 0 1\n");
    write("sub/mid.ray", "#ray_file leaf.ray\n");
    Diagnostics diag;
    const SceneDesc s = load(write("top.ray", "#shader a b\n#ray_file sub/mid.ray\n"), &diag);
    ASSERT_EQ(s.files.size(), 3u);
    EXPECT_TRUE(has_warning(diag, "sub/mid.ray:1:11: warning: 'leaf.ray' found as " +
                                      (dir / "sub/leaf.ray").lexically_normal().string() +
                                      ", not in " + d() +
                                      " (V3 resolves paths against the top-level file's "
                                      "directory)"));
}

TEST_F(ParserV3Files, PathNotFoundNamesEveryPlaceTried) {
    write("sub/mid.ray", "#texture checker.jpg\n");
    const std::string err = load_error(write("top.ray", "#shader a b\n#ray_file sub/mid.ray\n"));
    EXPECT_HAS(err, "sub/mid.ray:1:10: error: cannot open texture 'checker.jpg' (tried " + d() +
                        "/checker.jpg, " + d() + "/sub/checker.jpg, ./checker.jpg)");
    EXPECT_HAS(err, "included from " + d() + "/top.ray:2:1");
}

TEST_F(ParserV3Files, ADialectThatDependsOnPathResolutionIsAnError) {
    // By §4.2, sub/mid.ray's leaf.ray is sub/leaf.ray (V3); by §13.2 it is leaf.ray (no marker).
    write("sub/leaf.ray", kMat + "#shape_torus 0 0 0 0 0.25 1\n");
    write("leaf.ray", kMat + "#shape_sphere 0 0 0 0 1\n");
    write("sub/mid.ray", "#ray_file leaf.ray\n");
    const std::string top = write("top.ray", "#ray_file sub/mid.ray\n");
    EXPECT_HAS(load_error(top),
               "sub/mid.ray:1:11: error: the dialect of this tree depends on path resolution");
    // When the tree so found is V3 too, its files are the §13.2 ones.
    write("leaf.ray", kMat + "#shape_torus 0 0 0 0 0.5 2\n");
    const SceneDesc s = load(top);
    EXPECT_EQ(s.dialect, Dialect::V3);
    EXPECT_EQ(std::get<Torus>(s.files[2].root.shapes[0].geometry).ring, 2.0);
}

TEST_F(ParserV3Files, MixedDialectsAcrossFiles) {
    write("sub/v3.ray", kMat + "#shape_torus 0 0 0 0 0.25 1\n");
    const std::string err =
        load_error(write("top.ray", "#background 1 1 1\n#ray_file sub/v3.ray\n"));
    EXPECT_HAS(err, "sub/v3.ray:2:1: error: mixed dialects: V3 '#shape_torus' at " + d() +
                        "/sub/v3.ray:2:1, V1 '#background' at " + d() + "/top.ray:1:1");
}

TEST_F(ParserV3Files, JpegTexturesDecode) {
    std::ofstream(dir / "red.jpg", std::ios::binary).write(kRedJpeg, sizeof kRedJpeg - 1);
    const SceneDesc s = load(write("top.ray", "#shader a b\n#texture red.jpg\n"));
    const TextureImage& t = *s.files[0].textures[0].image;
    EXPECT_EQ(t.width, 4);
    EXPECT_EQ(t.height, 4);
    EXPECT_GT(t.rgb[0], 240);
    EXPECT_LT(t.rgb[1], 15);
}

TEST_F(ParserV3Files, MissingTexturesErrorOrCheckerStandIn) {
    write("sub/a.ray", "#texture gone.bmp\n#texture gone.bmp\n#texture junk.png\n");
    write("junk.png", "not a png");
    const std::string top = write("top.ray", "#shader a b\n#ray_file sub/a.ray\n");
    EXPECT_HAS(load_error(top), "sub/a.ray:1:10: error: cannot open texture 'gone.bmp' (tried ");
    ParseOptions checker;
    checker.missing_textures = MissingTextures::Checker;
    Diagnostics diag;
    const SceneDesc s = load(top, &diag, checker);
    ASSERT_EQ(s.files[1].textures.size(), 3u);
    EXPECT_EQ(s.missing_textures, (std::vector<std::string>{"gone.bmp", "junk.png"}));
    EXPECT_EQ(count_warnings(diag, "missing-texture:gone.bmp"), 1);  // one per missing file
    EXPECT_TRUE(has_warning(diag, "cannot decode texture"));
    const TextureImage& t = *s.files[1].textures[0].image;
    ASSERT_EQ(t.width, 64);
    ASSERT_EQ(t.height, 64);
    // Magenta at the top left, grey 8 pixels on.
    EXPECT_EQ(std::vector<int>(t.rgb.begin(), t.rgb.begin() + 3), (std::vector<int>{255, 0, 255}));
    const size_t grey = 8 * 3;
    EXPECT_EQ(std::vector<int>(t.rgb.begin() + grey, t.rgb.begin() + grey + 3),
              (std::vector<int>{128, 128, 128}));
    // V1 too.
    Diagnostics v1diag;
    const SceneDesc v1 = load(write("v1.ray", "#texture gone.bmp\n"), &v1diag, checker);
    EXPECT_EQ(v1.dialect, Dialect::V1);
    EXPECT_EQ(v1.missing_textures.size(), 1u);
    EXPECT_HAS(load_error(write("v1e.ray", "#texture gone.bmp\n")),
               "cannot open texture 'gone.bmp' (tried ");
}

TEST_F(ParserV3Files, DynamicAffineBindsToTheKeyFiles) {
    write("k.key",
          "#DOFS 2 Arm leg #DURATION 1 #FRAMES 1\n"
          "1 0 0 0 0 1 0 0 0 0 1 0 4 5 6 1   1 0 0 7 0 1 0 7 0 0 1 7 1 2 3 7\n");
    write("k2.key", "#DOFS 1 Arm #DURATION 1 #FRAMES 1\n1 0 0 0 0 1 0 0 0 0 1 0 9 9 9 1\n");
    const std::string shapes = "#shape_sphere 0 0 0 0 1\n";
    Diagnostics diag;
    const SceneDesc s = load(
        write("top.ray", "#key_file k.key\n#key_file k2.key\n" + kMat + "#dynamic_affine Arm " +
                             shapes + "#dynamic_affine leg #shape_list_begin " + shapes + shapes +
                             "#shape_list_end\n"),
        &diag);
    const GroupDesc& root = s.files[0].root;
    ASSERT_EQ(root.groups.size(), 2u);
    EXPECT_EQ(root.groups[0].joint, "Arm");
    EXPECT_EQ(Vec3(root.groups[0].matrix[3]), Vec3(4, 5, 6));  // frame 0 of k.key: the first wins
    EXPECT_TRUE(has_warning(diag, "DOF 'Arm' is also in 'k2.key'"));
    // V3 key files: the bottom row is ignored.
    EXPECT_EQ(root.groups[1].matrix[3], glm::dvec4(1, 2, 3, 1));
    EXPECT_EQ(root.groups[1].shapes.size(), 2u);  // the list folds
    Diagnostics ci;
    const SceneDesc c =
        load(write("ci.ray", "#key_file k.key\n" + kMat + "#dynamic_affine arm " + shapes), &ci);
    EXPECT_EQ(Vec3(c.files[0].root.groups[0].matrix[3]), Vec3(4, 5, 6));
    EXPECT_TRUE(has_warning(ci,
                            "ci.ray:3:17: warning: joint 'arm' matches DOF 'Arm' only when "
                            "case is ignored"));
    EXPECT_HAS(
        load_error(write("no.ray", "#key_file k.key\n" + kMat + "#dynamic_affine Foot " + shapes)),
        "no.ray:3:17: error: no DOF 'Foot' in key files k.key");
    write("amb.key", "#DOFS 2 ARM Arm #DURATION 1 #FRAMES 1\n" + std::string(32, ' ') +
                         "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
    EXPECT_HAS(load_error(write("amb.ray",
                                "#key_file amb.key\n" + kMat + "#dynamic_affine arm " + shapes)),
               "error: joint 'arm' matches several DOFs of 'amb.key' when case is ignored");
    // No key file: the identity, one warning per file.
    Diagnostics none;
    const SceneDesc n = load(
        write("none.ray", kMat + "#dynamic_affine a " + shapes + "#dynamic_affine b " + shapes),
        &none);
    EXPECT_EQ(n.files[0].root.groups[1].matrix, Mat4(1.0));
    EXPECT_EQ(n.files[0].root.groups[1].joint, "b");
    EXPECT_EQ(count_warnings(none, "joint-no-key"), 1);
    EXPECT_EQ(none.warnings()[0].count, 1);
}

// Every .ray file of the three public V3 folders, each opened on its own as a user would (no
// --dialect; sub-files get the default camera and a warning), with checker stand-ins for the
// unpublished textures. Six sub-files hold no V3 marker: they read as V1 (spec §10 step 4), and
// with --dialect v3 as V3, to the same shapes.
TEST(ParserV3Public, EveryV3SceneParses) {
    const fs::path root(RT_PUBLIC_SCENES_DIR);
    if (!fs::exists(root)) GTEST_SKIP() << "no " << root;
    const std::set<std::string> no_marker = {"_sphere.ray",   "_box.ray",   "_cone.ray",
                                             "_cylinder.ray", "_stool.ray", "_table.ray"};
    int files = 0;
    size_t csgs = 0, tori = 0;
    for (const char* folder : {"henry-md__ray-tracer", "aarxa__RayForge-CPP-Ray-Tracing-Engine",
                               "dcalvo__Graphics-2021"}) {
        for (const auto& e : fs::directory_iterator(root / folder)) {
            if (e.path().extension() != ".ray") continue;
            ++files;
            const std::string name = e.path().filename().string();
            try {
                Diagnostics diag;
                ParseOptions detect;
                detect.missing_textures = MissingTextures::Checker;
                const SceneDesc s = parse_scene_file(e.path().string(), diag, detect);
                EXPECT_EQ(s.dialect, no_marker.count(name) ? Dialect::V1 : Dialect::V3) << name;
                // The course's sub-files carry the all-zero dummy camera.
                if (name[0] == '_') {
                    EXPECT_FALSE(s.camera) << e.path();
                    EXPECT_TRUE(diag.has("camera-zero")) << e.path();
                }
                for (const FileDesc& f : s.files) {
                    csgs += f.root.csgs.size();
                    for (const ShapeDesc& sh : f.root.shapes)
                        tori += std::holds_alternative<Torus>(sh.geometry) ? 1 : 0;
                }
                ParseOptions forced = v3_options();
                forced.missing_textures = MissingTextures::Checker;
                Diagnostics d2;
                const SceneDesc v3 = parse_scene_file(e.path().string(), d2, forced);
                EXPECT_EQ(v3.dialect, Dialect::V3);
                EXPECT_EQ(v3.files.size(), s.files.size()) << name;
            } catch (const SceneError& err) {
                ADD_FAILURE() << err.what();
            }
        }
    }
    EXPECT_EQ(files, 41);
    EXPECT_GE(csgs, 2u);
    EXPECT_GT(tori, 10u);
}

// Every prefix of a V3 file with lists, CSG and transforms either parses or gives a located
// error (no crash, no other exception).
TEST(ParserV3Public, EveryPrefixParsesOrFailsCleanly) {
    const std::string text =
        kMat + "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 0 0 0 0 0 0 0\n#vertex 0 1 0 0 0 0 0 0\n" +
        "#shape_intersection\n #shape_list_begin\n  #shape_sphere 0 0 -0.95 0 1.5\n" +
        "  #shape_difference #shape_torus 0 0 0 0 0.25 1 // c\n  " + kAffineId +
        "  #shape_list_begin #shape_box 0 0 0 0 1 1 1 #shape_list_end\n #shape_list_end\n" +
        "#dynamic_affine arm #shape_triangles 0 #shape_list_begin #shape_triangle 0 1 2\n" +
        "#shape_list_end\n";
    EXPECT_EQ(v3(text).files[0].root.csgs.size(), 1u);
    int errors = 0;
    for (size_t n = 0; n < text.size(); ++n) {
        try {
            Diagnostics diag;
            parse(text.substr(0, n), &diag, v3_options());
        } catch (const SceneError& e) {
            EXPECT_GT(e.loc().line, 0) << e.what();
            ++errors;
        }
    }
    EXPECT_GT(errors, 100);
}

}  // namespace

// The dummy camera outside V3: a marker-less sub-file opened on its own reads as V1 and gets the
// default camera with a warning; any other invalid camera stays an error.
TEST(ParserV3, DummyCameraInAV1FileIsTheDefaultCamera) {
    Diagnostics diag;
    const SceneDesc s = parse_scene_string(
        "#camera 0 0 0  0 0 0  0 0 0  0\n"
        "#material 0 0 0  1 1 1  1 1 1  0 0 0  1  0 0 0  1  -1 !!\n#shape_sphere 0 0 0 0 1\n",
        "sub.ray", diag);
    EXPECT_EQ(s.dialect, Dialect::V1);
    EXPECT_FALSE(s.camera);
    EXPECT_TRUE(diag.has("camera-zero"));
    EXPECT_FALSE(diag.has("no-camera"));
    Diagnostics d2;
    EXPECT_THROW(parse_scene_string("#camera 0 0 0  0 0 0  0 1 0  0.5\n", "bad.ray", d2),
                 SceneError);
}

}  // namespace rt
