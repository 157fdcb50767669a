// Bad input never crashes: huge counts and indices, numbers out of range, deep nesting,
// include cycles and chains, instancing that multiplies, a 100 MB file, binary garbage, NUL
// bytes, truncated files and invalid UTF-8 all end in a `file:line:col: error: ...` (or a
// correct scene), in bounded memory and time.
#include <filesystem>
#include <fstream>
#include <random>

#include "rt/util/file_io.h"
#include "test_util.h"

namespace rt {
namespace {

using test::parse;
using test::parse_error;

const char* kLimitsMat = "#material 0 0 0  .1 .1 .1  .5 .5 .5  .2 .2 .2  10  0 0 0  1  -1 !m!\n";
const char* kIdentityGroup = "#group_begin 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n";

// Parses and compiles; returns the error text ("" when the scene is fine).
std::string parse_compile_error(const std::string& text, const std::string& base_dir = ".") {
    try {
        Diagnostics diag;
        compile_scene(parse_scene_string(text, "test.ray", diag, {}, base_dir));
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

std::string repeat(const std::string& s, int n) {
    std::string r;
    r.reserve(s.size() * static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) r += s;
    return r;
}

TEST(BadInput, HugeCounts) {
    EXPECT_EQ(parse_error("#vertex_num 1000000000000\n"),
              "test.ray:1:13: error: integer '1000000000000' out of range");
    EXPECT_EQ(parse_error("#light_num 99999999999999999999\n"),
              "test.ray:1:12: error: integer '99999999999999999999' out of range");
    // In range but far more than the file holds: no giant reservation, a shortfall at the end.
    EXPECT_EQ(parse_error("#vertex_num 2147483647\n#vertex 0 0 0 0 0 1 0 0\n"),
              "test.ray:3:1: error: #vertex_num at test.ray:1:1 declares 2147483647, found 1");
    EXPECT_EQ(parse_error("#material_num 2147483647\n"),
              "test.ray:2:1: error: #material_num at test.ray:1:1 declares 2147483647, found 0");
}

TEST(BadInput, HugeIndices) {
    const std::string verts = "#vertex 0 0 0 0 0 1 0 0\n#vertex 1 0 0 0 0 1 0 0\n";
    EXPECT_EQ(
        parse_error(std::string(kLimitsMat) + verts + "#shape_triangle 0 0 1 1000000000000\n"),
        "test.ray:4:23: error: integer '1000000000000' out of range");
    EXPECT_EQ(parse_error(std::string(kLimitsMat) + verts + "#shape_triangle 0 0 1 2147483647\n"),
              "test.ray:4:23: error: vertex index 2147483647 out of range [0,2)");
    EXPECT_EQ(parse_error(std::string(kLimitsMat) + verts + "#shape_triangle 0 -2147483648 0 1\n"),
              "test.ray:4:19: error: vertex index -2147483648 out of range [0,2)");
    EXPECT_EQ(parse_error("#shape_sphere 4294967296 0 0 0 1\n"),
              "test.ray:1:15: error: integer '4294967296' out of range");
    EXPECT_EQ(parse_error("#ray_file_instance 99999999999\n"),
              "test.ray:1:20: error: integer '99999999999' out of range");
    EXPECT_EQ(parse_error(std::string(kLimitsMat) + "#material 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 1 "
                                                    "1000000000000 !m!\n"),
              "test.ray:2:45: error: expected an integer (texture index), got '1000000000000'");
}

TEST(BadInput, GiganticNumbers) {
    EXPECT_EQ(parse_error("#ambient 1e400 0 0\n"),
              "test.ray:1:10: error: non-finite number '1e400'");
    EXPECT_EQ(parse_error("#ambient -1e400 0 0\n"),
              "test.ray:1:10: error: non-finite number '-1e400'");
    EXPECT_EQ(parse_error("#ambient 0 -nan 0\n"), "test.ray:1:12: error: non-finite number '-nan'");
    EXPECT_EQ(parse_error("#ambient 0 0 inf\n"), "test.ray:1:14: error: non-finite number 'inf'");
    EXPECT_EQ(parse_error("#ambient 0 0 -Infinity\n"),
              "test.ray:1:14: error: non-finite number '-Infinity'");
    EXPECT_EQ(parse_error("#ambient 0 0 0x10\n"),
              "test.ray:1:14: error: expected 3 numbers after #ambient, got '0x10'");
    // A long integer literal is a fine real; underflow is zero.
    const SceneDesc s = parse("#ambient 99999999999999999999 1e-400 0\n");
    EXPECT_EQ(s.ambient.x, 1e20);
    EXPECT_EQ(s.ambient.y, 0.0);
    // Finite but enormous geometry: up to +-1e300 it compiles; beyond, an error at the shape.
    EXPECT_EQ(parse_compile_error(std::string(kLimitsMat) +
                                  "#shape_sphere 0 1e299 -1e299 1e299 1e299\n"
                                  "#shape_box 0 0 0 0 1e300 1e300 1e300\n"
                                  "#shape_cylinder 0 1e-308 0 0 1e299 1e-308\n"),
              "");
    EXPECT_EQ(parse_compile_error(std::string(kLimitsMat) + "#shape_sphere 0 0 0 0 1\n" +
                                  "#shape_cylinder 0 0 6 1e308 3 .2\n"),
              "test.ray:3:1: error: shape reaches beyond +-1e300 in its file's frame "
              "(coordinates too large for the renderer)");
    // Large group matrices work while their determinant is finite; past that, an error.
    EXPECT_EQ(parse_compile_error(std::string(kLimitsMat) +
                                  "#group_begin 1e100 0 0 0  0 1e100 0 0  0 0 1e100 0  0 0 0 1\n" +
                                  kIdentityGroup + "#shape_sphere 0 0 1e100 0 1e100\n" +
                                  "#group_end\n#group_end\n"),
              "");
    // Nested matrices whose product overflows: the shape is out of range, not a NaN.
    EXPECT_EQ(parse_compile_error(std::string(kLimitsMat) +
                                  "#group_begin 1e200 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n" +
                                  "#group_begin 1e200 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\n" +
                                  "#shape_sphere 0 0 0 0 1\n#group_end\n#group_end\n"),
              "test.ray:4:1: error: shape reaches beyond +-1e300 in its file's frame "
              "(coordinates too large for the renderer)");
    EXPECT_EQ(parse_error("#group_begin 1e300 0 0 0  0 1e300 0 0  0 0 1e300 0  0 0 0 1\n"),
              "test.ray:1:1: error: group matrix too large: its determinant overflows");
}

TEST(BadInput, DeepNestingHasALimit) {
    // 10^5 levels: an error at the first group past the limit, no stack overflow.
    const std::string deep = repeat(kIdentityGroup, 100000);
    EXPECT_EQ(parse_error(deep),
              "test.ray:10001:1: error: #group_begin nests groups deeper than 10000 levels");
    const std::string joints = repeat("#joint_begin j\n", 100000);
    EXPECT_EQ(parse_error(joints),
              "test.ray:10001:1: error: #joint_begin nests groups deeper than 10000 levels");
    // At the limit the scene parses, compiles and renders (the walks are iterative).
    const std::string ok2 = "#camera 0 0 0 0 0 -1 0 1 0 0.5\n#ambient 1 1 1\n" +
                            std::string(kLimitsMat) + repeat(kIdentityGroup, 10000) +
                            "#shape_sphere 0 0 0 -3 1\n" + repeat("#group_end\n", 10000);
    CompileReport report;
    const RenderScene scene = compile_scene(test::parse(ok2), &report);
    EXPECT_EQ(report.unique_prims, 1u);
    const Image img = test::render(scene, 4, 4);
    EXPECT_GT(img.rgb[3 * (2 * 4 + 2)], 0.0);  // the sphere covers the centre
    // Unclosed: reported at the end of the file, naming the innermost open group.
    EXPECT_EQ(parse_error(repeat(kIdentityGroup, 3)),
              "test.ray:4:1: error: #group_begin at test.ray:3:1 is never closed");
}

TEST(BadInput, BinaryGarbage) {
    std::mt19937 rng(6);
    for (int round = 0; round < 50; ++round) {
        std::string junk(4096, '\0');
        for (char& c : junk) c = static_cast<char>(rng() & 0xFF);
        if (round % 2) junk = "#camera 0 0 0 0 0 -1 0 1 0 .5\n" + junk;
        const std::string err = parse_compile_error(junk);
        EXPECT_EQ(err.rfind("test.ray:", 0), 0u) << err;
        EXPECT_NE(err.find(": error: "), std::string::npos) << err;
        EXPECT_LT(err.size(), 1000u) << err;  // quoted garbage is escaped and cut
    }
}

TEST(BadInput, NulBytesAndControlBytesAreEscaped) {
    EXPECT_EQ(parse_error(std::string("#ambient 0 0 0\n#camera\0 0", 25)),
              "test.ray:2:1: error: unknown directive '#camera\\x00'");
    EXPECT_EQ(parse_error(std::string("#ambient 0 0 \0\n", 16)),
              "test.ray:1:14: error: expected 3 numbers after #ambient, got '\\x00'");
    EXPECT_EQ(parse_error(std::string("#ambient 0 0 0\n\0\0\0", 18)),
              "test.ray:2:1: error: expected a directive, got '\\x00\\x00\\x00'");
    // A file's first token is never quoted when it is not printable text: a binary file or a
    // secret (/proc/self/environ's NUL-separated variables) never reaches the message.
    const std::string not_text =
        "test.ray:1:1: error: 'test.ray' is not a .ray scene: its first bytes are not printable "
        "text";
    EXPECT_EQ(parse_error(std::string("\0\0\0", 3)), not_text);
    EXPECT_EQ(parse_error(std::string("#camera\0 0", 10)), not_text);
    EXPECT_EQ(parse_error(std::string("SECRET=1\0HOME=/root\0", 21)), not_text);
    EXPECT_EQ(parse_error("\x89PNG\r\n\x1a\n"), not_text);
    EXPECT_EQ(parse_error("#ambient 0 0 \x1b[31m\n"),
              "test.ray:1:14: error: expected 3 numbers after #ambient, got '\\x1b[31m'");
    // NUL inside comments and strings is just text.
    static const char kNul[] =
        "// a \0 b\n#material 0 0 0 .1 .1 .1 .5 .5 .5 .2 .2 .2 10 0 0 0 1 -1 !n\0m!\n";
    const SceneDesc s = parse(std::string(kNul, sizeof kNul - 1));
    ASSERT_EQ(s.files[0].materials.size(), 1u);
    EXPECT_EQ(s.files[0].materials[0].name, std::string("n\0m", 3));
}

TEST(BadInput, InvalidUtf8) {
    // Invalid sequences are escaped in messages; valid UTF-8 is kept as is (after a file's first
    // token, which is never quoted when it is not text: BadInput.NulBytesAndControlBytesAre...).
    const std::string a = "#ambient 0 0 0\n";
    EXPECT_EQ(parse_error(a + "#\xff\xfe\n"),
              "test.ray:2:1: error: unknown directive '#\\xff\\xfe'");
    EXPECT_EQ(parse_error("#caf\xc3\xa9\n"),
              "test.ray:1:1: error: unknown directive '#caf\xc3\xa9'");
    EXPECT_EQ(parse_error(a + "#x\xc3\n"), "test.ray:2:1: error: unknown directive '#x\\xc3'");
    EXPECT_EQ(parse_error(a + "#x\xed\xa0\x80\n"),  // a UTF-16 surrogate
              "test.ray:2:1: error: unknown directive '#x\\xed\\xa0\\x80'");
    EXPECT_EQ(parse_error(a + "#x\xc0\xaf\n"),  // overlong '/'
              "test.ray:2:1: error: unknown directive '#x\\xc0\\xaf'");
    EXPECT_EQ(parse_error("#x\xc0\xaf\n"),
              "test.ray:1:1: error: 'test.ray' is not a .ray scene: its first bytes are not "
              "printable text");
    EXPECT_EQ(parse_error("#joint_begin \xff\n"),
              "test.ray:1:14: error: non-ASCII byte in a joint name '\\xff'");
    // In comments and strings it is only text (spec §2).
    Diagnostics diag;
    const SceneDesc s = parse(
        "// \xff\xfe\n#material 0 0 0 .1 .1 .1 .5 .5 .5 .2 .2 .2 10 0 0 0 1 "
        "-1 !\xc3\x28!\n",
        &diag);
    EXPECT_EQ(s.files[0].materials[0].name, "\xc3\x28");
}

TEST(BadInput, LongTokensAreCutInMessages) {
    const std::string big(1 << 20, 'x');
    const std::string err = parse_error("#ambient 0 0 " + big + "\n");
    EXPECT_EQ(err, "test.ray:1:14: error: expected 3 numbers after #ambient, got '" +
                       std::string(200, 'x') + "'... (1048576 bytes)");
}

TEST(BadInput, PathTooLongForTheFilesystem) {
    // ENAMETOOLONG is "cannot open", not an exception from std::filesystem.
    const std::string name(5000, 'n');
    for (const char* d : {"#ray_file ", "#texture ", "#key_file "}) {
        std::string text = d;
        text += name;
        text += "\n";
        const std::string err = parse_error(text);
        EXPECT_EQ(err.rfind("test.ray:1:", 0), 0u) << err.substr(0, 100);
        EXPECT_NE(err.find(": error: cannot open "), std::string::npos) << err.substr(0, 100);
    }
}

TEST(BadInput, UnterminatedString) {
    EXPECT_EQ(parse_error(std::string(kLimitsMat).substr(0, 60) + "!abc"),
              "test.ray:1:61: error: unterminated !…! string (it must close on the same line)");
}

// Every prefix of a real scene (with its includes and textures) parses or fails cleanly.
TEST(BadInput, TruncatedScenes) {
    const std::string dir = std::string(RT_SOURCE_DIR) + "/scenes";
    for (const char* name : {"showpiece.ray", "v0.ray", "groups.ray"}) {
        std::string path = dir;
        path += "/";
        path += name;
        std::string text;
        ASSERT_TRUE(read_file(path, &text)) << path;
        size_t errors = 0;
        const size_t stride = text.size() / 150 + 1;
        for (size_t n = 0; n < text.size(); n += stride) {
            const std::string err = parse_compile_error(text.substr(0, n), dir);
            if (err.empty()) continue;
            ++errors;
            EXPECT_EQ(err.rfind("test.ray:", 0), 0u) << n << ": " << err;
        }
        EXPECT_GT(errors, 0u) << name;
        EXPECT_EQ(parse_compile_error(text, dir), "") << name;
    }
}

class BadFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir = std::filesystem::temp_directory_path() /
              ("rt_bad_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) {
        const auto p = dir / name;
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
    std::string load_error(const std::string& path) {
        try {
            Diagnostics diag;
            compile_scene(parse_scene_file(path, diag));
        } catch (const SceneError& e) {
            return e.what();
        }
        return "";
    }
    std::filesystem::path dir;
};

TEST_F(BadFiles, SelfInclude) {
    const std::string self = write("self.ray", "#ray_file self.ray\n");
    EXPECT_EQ(load_error(self), self + ":1:11: error: include cycle: self.ray -> self.ray");
}

TEST_F(BadFiles, IncludeChainHasALimit) {
    for (int i = 0; i < 300; ++i) {
        std::string name = "f", text = "#ray_file f";
        name += std::to_string(i);
        name += ".ray";
        text += std::to_string(i + 1);
        text += ".ray\n";
        write(name, text);
    }
    write("f300.ray", "");
    const std::string err = load_error((dir / "f0.ray").string());
    const std::string f199 = (dir / "f199.ray").lexically_normal().string();
    EXPECT_EQ(err.rfind(f199 + ":1:1: error: #ray_file includes nested deeper than 200 files", 0),
              0u)
        << err.substr(0, 300);
    // 150 deep is fine.
    write("f150.ray", "");
    EXPECT_EQ(load_error((dir / "f0.ray").string()), "");
}

TEST_F(BadFiles, InstancingThatMultipliesHasALimit) {
    // Each level instances the next 100 times: 100^5 = 10^10 placements of leaf.ray.
    write("leaf.ray", std::string(kLimitsMat) + "#shape_sphere 0 0 0 0 1\n");
    std::string prev = "leaf.ray";
    for (int level = 0; level < 5; ++level) {
        std::string name = "l", text = "#ray_file ";
        name += std::to_string(level);
        name += ".ray";
        text += prev;
        text += "\n";
        text += repeat("#ray_file_instance 0\n", 100);
        write(name, text);
        prev = name;
    }
    const std::string err = load_error((dir / "l4.ray").string());
    EXPECT_NE(err.find(":3:1: error: instancing places more than 1048576 copies of files "
                       "(nested instances multiply)"),
              std::string::npos)
        << err;
    // 100^2 = 10^4 placements are fine.
    Diagnostics diag;
    const RenderScene s = compile_scene(parse_scene_file((dir / "l1.ray").string(), diag));
    EXPECT_EQ(s.instances.size(), 10000u);
}

TEST_F(BadFiles, HugeTextureHeader) {
    write("big.ppm", "P3 4096 4096 255\n0 0 0\n");
    const std::string scene = write("t.ray", "#texture big.ppm\n");
    EXPECT_EQ(load_error(scene),
              scene + ":1:10: error: cannot decode texture '" + (dir / "big.ppm").string() +
                  "': truncated PNM: 4096x4096 pixels need 50331648 samples, the file has room "
                  "for at most 3");
}

// A directory found where a file is named is said to be one (it read as "not found"); a file of
// the kernel is refused before a byte of it is read, so none reaches the message.
TEST_F(BadFiles, DirectoriesAndKernelFilesAreNamedAsSuch) {
    std::filesystem::create_directories(dir / "sub");
    const std::string scene = write("d.ray", "#ray_file sub\n");
    EXPECT_EQ(load_error(scene), scene + ":1:11: error: cannot open ray file 'sub' (tried " +
                                     (dir / "sub").string() + " (a directory), ./sub)");
    const std::string tex = write("t.ray", "#texture " + (dir / "sub").string() + "\n");
    EXPECT_EQ(load_error(tex), tex + ":1:10: error: cannot open texture '" +
                                   (dir / "sub").string() + "' (tried " + (dir / "sub").string() +
                                   " (a directory))");
    const std::string env = write("e.ray", "#ray_file /proc/self/environ\n");
    EXPECT_EQ(load_error(env), env +
                                   ":1:11: error: cannot read ray file '/proc/self/environ': "
                                   "'/proc/self/environ' is a file of the kernel (in /proc), "
                                   "not a regular file");
}

// The textures of one scene hold at most 4 x --max-pixels texels together: the #texture that
// would pass that is refused with its place before its pixels are allocated, however small its
// file. Here the budget is 64x64 per image, so 4 textures of 64x64 fit and a fifth does not.
TEST_F(BadFiles, TheTexturesOfASceneHaveABudget) {
    const uint64_t before = max_image_pixels();
    set_max_image_pixels(64 * 64);
    std::string scene;
    for (int i = 0; i < 5; ++i) {
        // P5 64x64: a file of its own each (a file named twice decodes once and counts once).
        std::string name = "t";  // (GCC 12 warns of "t" + std::to_string as an overflow)
        name += std::to_string(i);
        name += ".pgm";
        write(name, "P5 64 64 255\n" + std::string(64 * 64, static_cast<char>(i)));
        scene += "#texture " + name + "\n";
    }
    const std::string four =
        write("four.ray", scene.substr(0, scene.rfind("#texture")) + "#texture t0.pgm\n");
    EXPECT_EQ(load_error(four), "");
    const std::string five = write("five.ray", scene);
    const std::string err = load_error(five);
    set_max_image_pixels(before);
    EXPECT_EQ(err, five + ":5:10: error: cannot decode texture '" + (dir / "t4.pgm").string() +
                       "': PNM image of 64x64 pixels (4096) is larger than what is left of the "
                       "scene's texture budget (0 of 16384 texels, 4 x --max-pixels); "
                       "--max-pixels raises it");
}

// 100 MB of text, generated here: a long comment line and 100 MB of vertices-free filler; the
// lexer keeps its columns and lines and the memory stays a small multiple of the text.
TEST_F(BadFiles, HundredMegabytes) {
    std::string text = "#camera 0 0 0 0 0 -1 0 1 0 0.5\n";
    text += kLimitsMat;
    text += "// " + std::string(50u << 20, 'c') + "\n";
    text += std::string(50u << 20, ' ');
    text += "#shape_sphere 0 0 0 -3 1 #oops\n";
    const std::string path = write("big.ray", text);
    text.clear();
    text.shrink_to_fit();
    EXPECT_EQ(load_error(path), path + ":4:52428826: error: unknown directive '#oops'");
}

}  // namespace
}  // namespace rt
