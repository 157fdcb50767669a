// Parser tests: every directive, the dialects, and every error of spec §2/§3 with its
// file:line:col and message.
#include <filesystem>
#include <fstream>

#include "test_util.h"

namespace rt {
namespace {

using test::parse;
using test::parse_error;

const char* kMatV1 = "#material 0 0 0  .1 .1 .1  .5 .5 .5  .2 .2 .2  10  0 0 0  1  -1 !!\n";
const char* kMatV0 = "#material .1 .1 .1  .5 .5 .5  .2 .2 .2  0 0 0  .5 .25 1.5 -1 !!\n";

TEST(Parser, GlobalsAndCamera) {
    Diagnostics diag;
    const SceneDesc s = parse(
        "#camera 1 2 3  0 0 -1  0 1 0  0.5\n#background .1 .2 .3\n#ambient .4 .5 .6\n", &diag);
    ASSERT_TRUE(s.camera);
    EXPECT_EQ(s.camera->position, Vec3(1, 2, 3));
    EXPECT_EQ(s.camera->direction, Vec3(0, 0, -1));
    EXPECT_EQ(s.camera->half_height_angle_rad, 0.5);
    EXPECT_EQ(s.background, Vec3(.1, .2, .3));
    EXPECT_EQ(s.ambient, Vec3(.4, .5, .6));
    EXPECT_EQ(s.camera->loc.line, 1);
    EXPECT_EQ(s.camera->loc.col, 1);
}

TEST(Parser, RepeatedGlobalsWarnAndFirstWins) {
    Diagnostics diag;
    const SceneDesc s = parse(
        "#camera 1 2 3 0 0 -1 0 1 0 .5\n#camera 9 9 9 0 0 -1 0 1 0 .5\n#background 1 0 0\n"
        "#background 0 1 0\n#ambient 1 1 1\n#ambient 0 0 0\n",
        &diag);
    EXPECT_EQ(s.camera->position, Vec3(1, 2, 3));
    EXPECT_EQ(s.background, Vec3(1, 0, 0));
    EXPECT_EQ(s.ambient, Vec3(1, 1, 1));
    ASSERT_EQ(diag.warnings().size(), 3u);
    EXPECT_EQ(diag.warnings()[0].str().substr(0, 13), "test.ray:2:1:");
}

TEST(Parser, NoCameraWarns) {
    Diagnostics diag;
    const SceneDesc s = parse("#background 0 0 0\n", &diag);
    EXPECT_FALSE(s.camera);
    EXPECT_TRUE(diag.has("no-camera"));
}

TEST(Parser, Lights) {
    const SceneDesc s = parse(
        "#light_num 3\n#light_dir 1 1 1  0 -2 0\n#light_point .5 .5 .5  1 2 3  .1 .2 .3\n"
        "#light_spot 1 0 0  0 5 0  0 -1 0  1 0 0  0.5 2\n" +
        std::string(kMatV1));
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].kind, LightKind::Directional);
    EXPECT_EQ(s.lights[0].direction, Vec3(0, -2, 0));
    EXPECT_EQ(s.lights[1].kind, LightKind::Point);
    EXPECT_EQ(s.lights[1].quadratic_atten, .3);
    EXPECT_EQ(s.lights[2].kind, LightKind::Spot);
    EXPECT_EQ(s.lights[2].cutoff_rad, 0.5);
    EXPECT_EQ(s.lights[2].spot_exponent, 2.0);  // V1: p = dor
}

TEST(Parser, V0SpotExponentIs128TimesDropOff) {
    const SceneDesc s =
        parse("#light_spot 1 1 1  5 5 5  -2 -5 1  0.3 0.02 0  0.5 0.5\n" + std::string(kMatV0));
    EXPECT_EQ(s.dialect, Dialect::V0);
    EXPECT_EQ(s.lights[0].spot_exponent, 64.0);
}

TEST(Parser, MaterialsV1AndV0FieldOrder) {
    const SceneDesc v1 =
        parse("#material 1 2 3  4 5 6  7 8 9  10 11 12  13  .1 .2 .3  1.5  -1 !a name!\n");
    EXPECT_EQ(v1.dialect, Dialect::V1);
    const MaterialDesc& m = v1.files[0].materials[0];
    EXPECT_EQ(m.emissive, Vec3(1, 2, 3));
    EXPECT_EQ(m.ambient, Vec3(4, 5, 6));
    EXPECT_EQ(m.diffuse, Vec3(7, 8, 9));
    EXPECT_EQ(m.specular, Vec3(10, 11, 12));
    EXPECT_EQ(m.specular_exponent, 13);
    EXPECT_EQ(m.transparent, Vec3(.1, .2, .3));
    EXPECT_EQ(m.refractive_index, 1.5);
    EXPECT_EQ(m.texture, -1);
    EXPECT_EQ(m.name, "a name");

    const SceneDesc v0 = parse("#material 1 2 3  4 5 6  7 8 9  10 11 12  .5 .25 1.3 -1 !!\n");
    EXPECT_EQ(v0.dialect, Dialect::V0);
    const MaterialDesc& n = v0.files[0].materials[0];
    EXPECT_EQ(n.ambient, Vec3(1, 2, 3));
    EXPECT_EQ(n.diffuse, Vec3(4, 5, 6));
    EXPECT_EQ(n.specular, Vec3(7, 8, 9));
    EXPECT_EQ(n.emissive, Vec3(10, 11, 12));
    EXPECT_EQ(n.specular_exponent, 64);  // 128 * kspec
    EXPECT_EQ(n.transparent, Vec3(.25));
    EXPECT_EQ(n.refractive_index, 1.3);
}

TEST(Parser, RefractiveIndexNotPositiveWarnsAndUsesOne) {
    Diagnostics diag;
    const SceneDesc s = parse("#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 0.0 -1 !!\n", &diag);
    EXPECT_EQ(s.files[0].materials[0].refractive_index, 1.0);
    ASSERT_EQ(diag.warnings().size(), 2u);  // refind + no camera
    EXPECT_EQ(diag.warnings()[0].str().substr(0, 14), "test.ray:1:43:");
}

TEST(Parser, DialectDetection) {
    // No materials: V0 when a shape uses -1, else V1.
    EXPECT_EQ(parse("#shape_sphere -1 0 0 0 1\n").dialect, Dialect::V0);
    EXPECT_EQ(parse("#background 0 0 0\n").dialect, Dialect::V1);
    ParseOptions v0;
    v0.dialect = Dialect::V0;
    EXPECT_EQ(parse("#background 0 0 0\n", nullptr, v0).dialect, Dialect::V0);
}

TEST(Parser, V0DefaultMaterial) {
    const SceneDesc s = parse(std::string(kMatV0) + "#shape_sphere -1 0 0 0 1\n");
    EXPECT_EQ(s.files[0].root.shapes[0].material, -1);
    const MaterialDesc d = v0_default_material();
    EXPECT_EQ(d.ambient, Vec3(.2));
    EXPECT_EQ(d.diffuse, Vec3(.8));
    EXPECT_EQ(d.specular, Vec3(.8));
    EXPECT_EQ(d.specular_exponent, 128);
}

TEST(Parser, ShapesAndGroups) {
    const SceneDesc s = parse(std::string(kMatV1) +
                              "#vertex 0 0 0  0 0 2  0 0\n#vertex 1 0 0  0 0 0  1 0\n"
                              "#vertex 0 1 0  0 0 0  0 1\n"
                              "#shape_sphere 0 1 2 3 4\n"
                              "#group_begin 1 0 0 5  0 2 0 6  0 0 3 7  0 0 0 1\n"
                              "  #shape_box 0 0 0 0 1 2 3\n"
                              "  #group_begin 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
                              "    #shape_cylinder 0 0 0 0 1 2\n    #shape_cone 0 0 0 0 1 2\n"
                              "  #group_end\n"
                              "#group_end\n"
                              "#shape_triangle 0 0 1 2\n");
    const FileDesc& f = s.files[0];
    EXPECT_EQ(f.vertices[0].normal, Vec3(0, 0, 1));  // normalised when read
    ASSERT_EQ(f.root.shapes.size(), 2u);
    const auto& sp = std::get<Sphere>(f.root.shapes[0].geometry);
    EXPECT_EQ(sp.centre, Vec3(1, 2, 3));
    EXPECT_EQ(sp.radius, 4);
    ASSERT_EQ(f.root.groups.size(), 1u);
    const GroupDesc& g = f.root.groups[0];
    // Row-major in the file: translation is (m14, m24, m34).
    EXPECT_EQ(g.matrix[3][0], 5);
    EXPECT_EQ(g.matrix[3][1], 6);
    EXPECT_EQ(g.matrix[3][2], 7);
    EXPECT_EQ(g.matrix[1][1], 2);
    EXPECT_EQ(std::get<BoxDesc>(g.shapes[0].geometry).size, Vec3(1, 2, 3));
    EXPECT_EQ(g.groups[0].shapes.size(), 2u);
    EXPECT_EQ(g.loc.line, 6);
    const auto& tri = std::get<TriangleDesc>(f.root.shapes[1].geometry);
    EXPECT_EQ(tri.v[2], 2);
}

TEST(Parser, CommandsMaySpanLinesAndShareLines) {
    const SceneDesc s = parse("#background\n 1\n 0 // red\n 0 #ambient 1 1 1\n");
    EXPECT_EQ(s.background, Vec3(1, 0, 0));
    EXPECT_EQ(s.ambient, Vec3(1));
}

TEST(Parser, DegenerateShapesSkippedWithOneCountedWarning) {
    Diagnostics diag;
    const SceneDesc s = parse(std::string(kMatV1) +
                                  "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 0 0 0 0 0 0 0\n"
                                  "#vertex 2 0 0 0 0 0 0 0\n"
                                  "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 0 1\n"
                                  "#shape_triangle 0 1 2 0\n#shape_sphere 0 0 0 0 0\n",
                              &diag);
    EXPECT_TRUE(s.files[0].root.shapes.empty());
    bool found = false;
    for (const Warning& w : diag.warnings())
        if (w.kind == "skip:degenerate triangle") {
            found = true;
            EXPECT_EQ(w.count, 3);
            EXPECT_EQ(w.loc.line, 5);
            EXPECT_NE(w.str().find("3 times"), std::string::npos);
        }
    EXPECT_TRUE(found);
    EXPECT_TRUE(diag.has("skip:sphere of radius 0"));
}

struct ErrorCase {
    const char* text;
    const char* expected;  // must appear in what()
};

class ParserErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(ParserErrors, ReportsLocationAndMessage) {
    const std::string err = parse_error(GetParam().text);
    EXPECT_NE(err.find(GetParam().expected), std::string::npos)
        << "text: " << GetParam().text << "\nerror: " << err;
}

// Each case: one mistake, with the exact location and the message.
INSTANTIATE_TEST_SUITE_P(
    AllErrors, ParserErrors,
    ::testing::Values(
        ErrorCase{"#shape_tours 0 1", "test.ray:1:1: error: unknown directive '#shape_tours'"},
        ErrorCase{"#background 0 0 0\nBroken",
                  "test.ray:2:1: error: expected a directive, got 'Broken'"},
        ErrorCase{"#background 1 x 1",
                  "test.ray:1:15: error: expected 3 numbers after "
                  "#background, got 'x'"},
        ErrorCase{"#background 1 1",
                  "test.ray:1:1: error: expected 3 numbers after #background, "
                  "got end of file"},
        ErrorCase{"#ambient 1 1\n#background 0 0 0",
                  "test.ray:1:1: error: expected 3 numbers after #ambient, got '#background'"},
        ErrorCase{"#background nan 0 0", "test.ray:1:13: error: non-finite number 'nan'"},
        ErrorCase{"#background 0 -inf 0", "test.ray:1:15: error: non-finite number '-inf'"},
        ErrorCase{"#background 0 1e999 0", "test.ray:1:15: error: non-finite number '1e999'"},
        ErrorCase{"#background 0 -1 0", "test.ray:1:15: error: negative background colour -1"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!\n#shape_sphere 0.0 0 0 0 1",
                  "test.ray:2:15: error: expected an integer (material index), got '0.0'"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!\n#shape_sphere 3 0 0 0 1",
                  "test.ray:2:15: error: material index 3 out of range [0,1)"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!\n#shape_sphere -1 0 0 0 1",
                  "test.ray:2:15: error: material index -1 out of range"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!\n#shape_sphere -1 0 0 0 1",
                  "(-1 is V0 only; try --dialect v0)"},
        ErrorCase{"#vertex 0 0 0 0 0 0 0 0\n#shape_triangle -1 0 0 9",
                  "test.ray:2:24: error: vertex index 9 out of range [0,1)"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 3 !!",
                  "test.ray:1:45: error: texture index 3 out of range [-1,0)"},
        ErrorCase{"#ray_file_instance 2",
                  "test.ray:1:20: error: ray file index 2 out of range "
                  "[0,0)"},
        ErrorCase{"#material_num 1\n#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!\n"
                  "#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!",
                  "test.ray:3:1: error: more #material than declared by #material_num at "
                  "test.ray:1:1"},
        ErrorCase{"#vertex_num 3\n#vertex 0 0 0 0 0 0 0 0\n",
                  "test.ray:3:1: error: #vertex_num at test.ray:1:1 declares 3, found 1"},
        ErrorCase{"#light_num -1", "test.ray:1:12: error: negative count -1"},
        ErrorCase{"#light_num 1\n#light_num 1", "test.ray:2:1: error: second #light_num"},
        ErrorCase{"#light_dir 1 1 1 0 -1 0\n#light_num 1",
                  "test.ray:2:1: error: #light_num after the first light"},
        ErrorCase{"#shape_sphere -1 0 0 0 -2", "test.ray:1:24: error: negative sphere radius -2"},
        ErrorCase{"#shape_box -1 0 0 0 1 -1.5 1", "test.ray:1:23: error: negative box size -1.5"},
        ErrorCase{"#shape_cylinder -1 0 0 0 1 -1",
                  "test.ray:1:28: error: negative cylinder height"},
        ErrorCase{"#shape_cone -1 0 0 0 -1 1", "test.ray:1:22: error: negative cone radius"},
        ErrorCase{"#camera 0 0 0  0 0 0  0 1 0  .5",
                  "test.ray:1:1: error: camera view direction "
                  "is zero"},
        ErrorCase{"#camera 0 0 0  0 0 -1  0 0 0  .5",
                  "test.ray:1:1: error: camera up vector is zero"},
        ErrorCase{"#camera 0 0 0  0 1 0  0 2 0  .5",
                  "test.ray:1:1: error: camera up vector is parallel to the view direction"},
        ErrorCase{"#camera 0 0 0  0 0 -1  0 1 0  1.6",
                  "test.ray:1:1: error: camera half-height angle 1.6 is outside (0, pi/2)"},
        ErrorCase{"#camera 0 0 0  0 0 -1  0 1 0  0",
                  "test.ray:1:1: error: camera half-height angle 0 is outside"},
        ErrorCase{"#group_begin 1 0 0 0  0 1 0 0  0 0 0 0  0 0 0 1\n#group_end",
                  "test.ray:1:1: error: singular group matrix"},
        ErrorCase{"#group_begin 1 0 0 0  0 1 0 0  0 0 1 0  0 0 1 1\n#group_end",
                  "test.ray:1:1: error: projective group matrix"},
        ErrorCase{"#group_begin 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n",
                  "test.ray:2:1: error: #group_begin at test.ray:1:1 is never closed"},
        ErrorCase{"#group_end", "test.ray:1:1: error: #group_end without #group_begin"},
        ErrorCase{"#shape_sphere -1 0 0 0 1\n#background 0 0 0",
                  "test.ray:2:1: error: definition after the scene graph started"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 !!",
                  "test.ray:1:1: error: #material needs 16 (V0) or 18 (V1) numbers before its "
                  "!…! string, got 17"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1\n#shape_sphere 0 0 0 0 1",
                  "test.ray:1:1: error: #material needs its !…! string after the numbers, "
                  "got '#shape_sphere'"},
        ErrorCase{"#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!\n"
                  "#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 1 -1 !!",
                  "test.ray:2:1: error: mixed dialects: V0 material at test.ray:2:1, V1 material "
                  "at test.ray:1:1"},
        ErrorCase{"#static_affine 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1",
                  "test.ray:1:47: error: #static_affine at test.ray:1:1 has no shape before end "
                  "of file"},
        ErrorCase{"#background 1 1 1 #shape_torus",
                  "test.ray:1:19: error: mixed dialects: V3 '#shape_torus' at test.ray:1:19, V1 "
                  "'#background' at test.ray:1:1"},
        ErrorCase{"#texture missing.bmp",
                  "test.ray:1:10: error: cannot open texture 'missing.bmp' (tried ./missing.bmp)"},
        ErrorCase{"#ray_file nothere.ray",
                  "test.ray:1:11: error: cannot open ray file "
                  "'nothere.ray'"},
        ErrorCase{"#joint_end", "test.ray:1:1: error: #joint_end without #joint_begin"},
        ErrorCase{"#light_spot 1 1 1 0 0 0 0 -1 0 1 0 0 -0.5 1",
                  "test.ray:1:38: error: negative spot cutoff -0.5"},
        ErrorCase{"#light_dir 1 1 1 0 0 0", "test.ray:1:1: error: light direction is zero"},
        ErrorCase{"#shape_sphere 99999999999 0 0 0 1",
                  "test.ray:1:15: error: integer '99999999999' out of range"}),
    // Readable names: the case number and the directive the text starts with.
    [](const ::testing::TestParamInfo<ErrorCase>& p) {
        std::string name = "case" + std::to_string(p.index) + "_";
        for (const char* c = p.param.text; *c && *c != ' ' && *c != '\n'; ++c)
            if (std::isalnum(static_cast<unsigned char>(*c))) name += *c;
        return name;
    });

TEST(Parser, CommentMayFollowATokenDirectly) {
    EXPECT_EQ(parse("#background 1 0 0// red\n").background, Vec3(1, 0, 0));
}

TEST(Parser, TextureMayBeDeclaredAfterTheMaterialThatUsesIt) {
    // Definitions come in any order (spec §3.1); the index is checked at the end of the file.
    const std::string err =
        parse_error("#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 0 !!\n#texture nothere.bmp\n");
    EXPECT_NE(err.find("cannot open texture 'nothere.bmp'"), std::string::npos) << err;
}

TEST(Parser, PointAndSpotColoursMayBeNegative) {
    const SceneDesc s = parse("#light_point -1 0 0  0 0 0  1 0 0\n");
    EXPECT_EQ(s.lights[0].diffuse, Vec3(-1, 0, 0));
}

TEST(Parser, DialectErrorsComeBeforeOtherErrors) {
    // The mixed dialect is found by the pre-scan, before the bad index on line 3.
    const std::string err = parse_error(
        "#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 -1 !!\n"
        "#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 1 -1 !!\n#shape_sphere 5 0 0 0 1\n");
    EXPECT_NE(err.find("test.ray:2:1: error: mixed dialects"), std::string::npos) << err;
    const std::string v3 = parse_error("#shape_sphere 5 0 0 0 1\n#shader a b\n#ambient 1 1 1\n");
    EXPECT_NE(v3.find("test.ray:3:1: error: mixed dialects: V3 '#shader' at test.ray:2:1, V1 "
                      "'#ambient' at test.ray:3:1"),
              std::string::npos)
        << v3;
}

TEST(Parser, DialectOverrideRejectsTheOtherCount) {
    ParseOptions v1;
    v1.dialect = Dialect::V1;
    EXPECT_NE(parse_error(kMatV0, v1)
                  .find("test.ray:1:1: error: #material has 16 numbers, but "
                        "--dialect v1 needs 18"),
              std::string::npos);
    ParseOptions v0;
    v0.dialect = Dialect::V0;
    EXPECT_NE(parse_error(kMatV1, v0).find("--dialect v0 needs 16"), std::string::npos);
}

// Files on disk: includes, cycles, textures, key files.
class ParserFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir = std::filesystem::temp_directory_path() /
              ("rt_parser_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir / "sub");
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) {
        const auto p = dir / name;
        std::ofstream(p) << text;
        return p.string();
    }
    std::string load_error(const std::string& path) {
        Diagnostics diag;
        try {
            parse_scene_file(path, diag);
        } catch (const SceneError& e) {
            return e.what();
        }
        return "";
    }
    std::filesystem::path dir;
};

TEST_F(ParserFiles, IncludesResolveAgainstTheIncludingFileAndShareOneCopy) {
    write("sub/ball.ray", std::string(kMatV1) + "#shape_sphere 0 0 0 0 1\n");
    write("sub/pair.ray", "#ray_file ball.ray\n#ray_file_instance 0\n");
    const std::string top = write("top.ray",
                                  "#ray_file sub/ball.ray\n#ray_file sub/pair.ray\n"
                                  "#ray_file_instance 0\n#ray_file_instance 1\n");
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(top, diag);
    ASSERT_EQ(s.files.size(), 3u);  // ball.ray parsed once though named twice
    EXPECT_EQ(s.files[0].ray_files[0], s.files[2].ray_files[0]);
}

TEST_F(ParserFiles, IncludedFilesIgnoreCameraBackgroundAndLights) {
    write("part.ray",
          "#camera 0 0 0 0 0 0 0 0 0 0.5\n#background 1 0 0\n#light_dir 1 1 1 0 -1 0\n");
    // The dummy all-zero camera of sub-files is only syntax-checked (spec §3.1, §12).
    EXPECT_EQ(load_error(write("a.ray", "#ray_file part.ray\n")), "");
    write("part2.ray", "#camera 0 0 0 0 0 0 x\n");
    EXPECT_NE(load_error(write("c.ray", "#ray_file part2.ray\n"))
                  .find("part2.ray:1:21: error: "
                        "expected 10 numbers"),
              std::string::npos);
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(write("b.ray", "#ray_file part.ray\n"), diag);
    EXPECT_EQ(s.background, Vec3(0.0));
    EXPECT_TRUE(s.lights.empty());
    EXPECT_TRUE(diag.has("included-light"));
}

TEST_F(ParserFiles, ErrorInIncludedFileNamesTheIncludeChain) {
    write("sub/bad.ray", "\n  #shape_sphere 0 0 0 0 1\n");
    const std::string top = write("top.ray", "#background 0 0 0\n#ray_file sub/bad.ray\n");
    const std::string err = load_error(top);
    EXPECT_NE(err.find("sub/bad.ray:2:17: error: material index 0 out of range [0,0)"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("\n  included from " + top + ":2:1"), std::string::npos) << err;
}

TEST_F(ParserFiles, IncludeCycleIsAnErrorNamingTheChain) {
    write("a.ray", "#ray_file b.ray\n");
    write("b.ray", "#ray_file a.ray\n");
    const std::string err = load_error((dir / "a.ray").string());
    EXPECT_NE(err.find("include cycle: a.ray -> b.ray -> a.ray"), std::string::npos) << err;
    write("self.ray", "#ray_file self.ray\n");
    EXPECT_NE(load_error((dir / "self.ray").string()).find("include cycle: self.ray -> self.ray"),
              std::string::npos);
}

TEST_F(ParserFiles, MixedDialectsAcrossFiles) {
    write("v0.ray", std::string(kMatV0));
    const std::string err =
        load_error(write("top.ray", std::string(kMatV1) + "#ray_file v0.ray\n"));
    EXPECT_NE(err.find("mixed dialects: V0 material at "), std::string::npos) << err;
}

TEST_F(ParserFiles, EmptyIncludedFileIsAnEmptyGraph) {
    write("empty.ray", "");
    Diagnostics diag;
    const SceneDesc s =
        parse_scene_file(write("top.ray", "#ray_file empty.ray\n#ray_file_instance 0\n"), diag);
    EXPECT_EQ(s.files.size(), 2u);
    EXPECT_TRUE(s.files[1].root.shapes.empty());
}

TEST_F(ParserFiles, KeyFileGivesJointMatrices) {
    // Column-major blocks: translation in numbers 13-15.
    write("k.key",
          "#DOFS 2 Root arm\n#DURATION 1\n#FRAMES 2\n"
          "1 0 0 0 0 1 0 0 0 0 1 0 4 5 6 1   2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1\n"
          "1 0 0 0 0 1 0 0 0 0 1 0 9 9 9 1   1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
    Diagnostics diag;
    const SceneDesc s =
        parse_scene_file(write("top.ray",
                               "#key_file k.key\n#joint_begin ROOT\n#joint_begin ARM\n#joint_end\n"
                               "#joint_end\n"),
                         diag);
    const GroupDesc& root = s.files[0].root.groups[0];
    EXPECT_EQ(Vec3(root.matrix[3]), Vec3(4, 5, 6));
    EXPECT_EQ(root.groups[0].matrix[0][0], 2.0);
    // Spec §14.2: matched ignoring case, with a warning; every key is kept.
    EXPECT_TRUE(diag.has("joint-case"));
    ASSERT_EQ(s.tracks.size(), 2u);
    EXPECT_EQ(s.tracks[0].name, "Root");
    EXPECT_EQ(Vec3(s.tracks[0].keys[1][3]), Vec3(9, 9, 9));
    EXPECT_NE(load_error(write("nodof.ray", "#key_file k.key\n#joint_begin leg\n#joint_end\n"))
                  .find("nodof.ray:2:14: error: no DOF 'leg' in key files k.key"),
              std::string::npos);
    write("short.key", "#DOFS 1 a\n#DURATION 1\n#FRAMES 1\n1 0 0 0 0 1 0 0\n");
    EXPECT_NE(load_error(write("s.ray", "#key_file short.key\n"))
                  .find("short.key:5:1: error: key file has 8 numbers after #FRAMES, expected "
                        "16\u00b71\u00b71 = 16"),
              std::string::npos);
    // Spec §14.1: two DOFs of one name are an error; names differing only in case are not.
    const std::string id = " 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1";
    write("dup.key", "#DOFS 2 arm arm\n#DURATION 1\n#FRAMES 1\n" + id + id + "\n");
    EXPECT_NE(load_error(write("d.ray", "#key_file dup.key\n"))
                  .find("dup.key:1:13: error: duplicate DOF name 'arm'"),
              std::string::npos);
    write("case.key", "#DOFS 2 arm Arm\n#DURATION 1\n#FRAMES 1\n" + id + id + "\n");
    EXPECT_EQ(load_error(write("c.ray", "#key_file case.key\n")), "");
}

TEST_F(ParserFiles, JointsWithoutKeyFileAreIdentityWithOneWarning) {
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(
        write("top.ray", "#joint_begin a\n#joint_end\n#joint_begin b\n#joint_end\n"), diag);
    EXPECT_EQ(s.files[0].root.groups[1].matrix, Mat4(1.0));
    int n = 0;
    for (const Warning& w : diag.warnings()) n += w.kind == "joint-no-key" ? 1 : 0;
    EXPECT_EQ(n, 1);
}

TEST_F(ParserFiles, TexturesLoadAndResolve) {
    // A 2x1 BMP written by hand: 24-bit, bottom-up rows padded to 4 bytes.
    const unsigned char bmp[] = {
        'B', 'M', 62, 0, 0, 0, 0, 0,  0, 0, 54, 0, 0, 0, 40,  0,   0, 0, 2, 0, 0,
        0,   1,   0,  0, 0, 1, 0, 24, 0, 0, 0,  0, 0, 8, 0,   0,   0, 0, 0, 0, 0,
        0,   0,   0,  0, 0, 0, 0, 0,  0, 0, 0,  0, 0, 0, 255, 255, 0, 0, 0, 0};  // BGR: red, blue;
                                                                                 // padding
    std::ofstream((dir / "sub" / "t.bmp"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bmp), sizeof bmp);
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(write("sub/top.ray", "#texture t.bmp\n"), diag);
    ASSERT_EQ(s.files[0].textures.size(), 1u);
    const TextureImage& img = *s.files[0].textures[0].image;
    EXPECT_EQ(img.width, 2);
    EXPECT_EQ(img.rgb[0], 255);  // red first
    EXPECT_EQ(img.rgb[5], 255);  // then blue
    write("sub/broken.png", "not an image");
    EXPECT_NE(load_error(write("sub/b.ray", "#texture broken.png\n")).find("cannot decode texture"),
              std::string::npos);
}

TEST_F(ParserFiles, EveryCountDirectiveMatchingItsItems) {
    write("part.ray", "");
    write("k.key", "#DOFS 1 a #DURATION 1 #FRAMES 1 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
    write("t.ppm", "P3 1 1 255 10 20 30\n");  // an ASCII PPM texture
    Diagnostics diag;
    const SceneDesc s = parse_scene_file(
        write("top.ray",
              "#light_num 1\n#light_dir 1 1 1 0 -1 0\n#texture_num 1\n#texture t.ppm\n"
              "#material_num 1\n" +
                  std::string(kMatV1) +
                  "#vertex_num 1\n#vertex 0 0 0 0 0 0 0 0\n#ray_file_num 1\n#ray_file part.ray\n"
                  "#key_file_num 1\n#key_file k.key\n"),
        diag);
    EXPECT_EQ(s.files[0].textures[0].image->rgb[2], 30);
    EXPECT_EQ(s.files[0].ray_files.size(), 1u);
    const std::string err = load_error(write("bad.ray", "#texture_num 2\n#texture t.ppm\n"));
    EXPECT_NE(err.find("bad.ray:3:1: error: #texture_num at " + (dir / "bad.ray").string() +
                       ":1:1 declares 2, found 1"),
              std::string::npos)
        << err;
    EXPECT_NE(load_error(write("bad2.ray", "#ray_file_num 0\n#ray_file part.ray\n"))
                  .find("bad2.ray:2:1: error: more #ray_file than declared by #ray_file_num"),
              std::string::npos);
    EXPECT_NE(load_error(write("bad3.ray", "#key_file k.key\n#key_file_num 1\n"))
                  .find("bad3.ray:2:1: error: #key_file_num after the first #key_file"),
              std::string::npos);
}

TEST(Parser, MissingTopLevelFile) {
    Diagnostics diag;
    try {
        parse_scene_file("/nonexistent/x.ray", diag);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot open scene file"), std::string::npos);
    }
}

}  // namespace
}  // namespace rt
