// Whole scenes: every scene of scenes/ and every complete public scene renders without error
// and with no NaN or Inf; the public scenes that are malformed as published fail with a
// file:line:col message and never crash; degenerate input still renders finite images.
#include <filesystem>
#include <set>

#include "extreme_util.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace rt {
namespace {

using namespace test;  // the helpers of extreme_util.h

Image render_file(const fs::path& path, Diagnostics& diag, int w = 160, int h = 120) {
    const RenderScene s = compile_scene(parse_scene_file(path.string(), diag));
    return test::render(s, w, h);
}

TEST(Scenes, OurScenesRenderCleanly) {
    const fs::path dir = fs::path(RT_SOURCE_DIR) / "scenes";
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() != ".ray") continue;
        Diagnostics diag;
        const Image img = render_file(e.path(), diag);
        EXPECT_EQ(count_non_finite(img), 0u) << e.path();
        for (const Warning& w : diag.warnings()) ADD_FAILURE() << w.str();
        ++n;
    }
    EXPECT_GE(n, 6);
}

// The complete, valid scenes of the public set (see shared/public-scenes/README.md).
const char* kCompletePublicScenes[] = {
    "BPkazemi__CS4810/test.ray",
    "matthew-richard__cg2/test.ray",
    "amm4yv__RayTracer/triangle_sphere_3.ray",
    "ijt3cd__4810Assignment3/entry.ray",
    "fayetality__Computer-Graphics-Assignment-2/testBubblePyramid.ray",
    "whitefusion__CG/dog.ray",
    "szhang37__Homework4/mine.ray",
};

TEST(PublicScenes, CompleteScenesRenderFinite) {
    const fs::path root(RT_PUBLIC_SCENES_DIR);
    if (!fs::exists(root)) GTEST_SKIP() << "no " << root;
    for (const char* name : kCompletePublicScenes) {
        Diagnostics diag;
        Image img;
        ASSERT_NO_THROW(img = render_file(root / name, diag)) << name;
        EXPECT_EQ(count_non_finite(img), 0u) << name;
        // Something other than the background is visible, except in the empty scene.
        if (std::string(name).find("mine.ray") == std::string::npos) {
            std::set<std::vector<double>> colours;
            for (size_t i = 0; i < img.rgb.size(); i += 3)
                colours.insert({img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]});
            EXPECT_GT(colours.size(), 3u) << name;
        }
    }
}

// The V3 public scenes (spec §13): every file of the three folders, each opened on its own as a
// user would (sub-files get the default camera with a warning), renders a finite image with
// checker stand-ins for the textures that were never published; the 11 complete scenes show
// more than the background.
TEST(PublicScenes, EveryV3FileRendersFinite) {
    const fs::path root(RT_PUBLIC_SCENES_DIR);
    if (!fs::exists(root)) GTEST_SKIP() << "no " << root;
    const std::set<std::string> complete = {
        "henry-md__ray-tracer/test.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/art_submission1.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/lens.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/test.directional.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/test.directional.cone.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/test.directional.cylinder.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/test.directional.torus.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/test.point.ray",
        "aarxa__RayForge-CPP-Ray-Tracing-Engine/test.spot.ray",
        "dcalvo__Graphics-2021/scene.ray",
        "dcalvo__Graphics-2021/chess_room.ray",
    };
    ParseOptions options;
    options.missing_textures = MissingTextures::Checker;
    int files = 0, scenes = 0;
    for (const char* folder : {"henry-md__ray-tracer", "aarxa__RayForge-CPP-Ray-Tracing-Engine",
                               "dcalvo__Graphics-2021"}) {
        for (const auto& e : fs::directory_iterator(root / folder)) {
            if (e.path().extension() != ".ray") continue;
            const std::string name = std::string(folder) + "/" + e.path().filename().string();
            SCOPED_TRACE(name);
            ++files;
            Diagnostics diag;
            Image img;
            ASSERT_NO_THROW({
                const RenderScene s =
                    compile_scene(parse_scene_file(e.path().string(), diag, options));
                img = test::render(s, 64, 48);
            });
            EXPECT_EQ(count_non_finite(img), 0u);
            if (!complete.count(name)) {
                EXPECT_TRUE(diag.has("camera-zero"));  // a sub-file: the default camera
                continue;
            }
            ++scenes;
            std::set<std::vector<double>> colours;
            for (size_t i = 0; i < img.rgb.size(); i += 3)
                colours.insert({img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]});
            EXPECT_GT(colours.size(), 3u);
        }
    }
    EXPECT_EQ(files, 41);
    EXPECT_EQ(scenes, 11);
}

TEST(PublicScenes, EveryFileLoadsOrFailsWithALocatedMessage) {
    const fs::path root(RT_PUBLIC_SCENES_DIR);
    if (!fs::exists(root)) GTEST_SKIP() << "no " << root;
    int loaded = 0, failed = 0;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        std::string ext = e.path().extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (ext != ".ray") continue;
        Diagnostics diag;
        try {
            const Image img = render_file(e.path(), diag, 32, 24);
            EXPECT_EQ(count_non_finite(img), 0u) << e.path();
            ++loaded;
        } catch (const SceneError& err) {
            // file:line:col: error: ...
            EXPECT_NE(std::string(err.what()).find(": error: "), std::string::npos);
            EXPECT_GT(err.loc().line, 0) << err.what();
            ++failed;
        }
    }
    EXPECT_GT(loaded, 10);
    EXPECT_GT(failed, 10);
}

TEST(PublicScenes, MalformedScenesFailAsTheSpecSays) {
    const fs::path root(RT_PUBLIC_SCENES_DIR);
    if (!fs::exists(root)) GTEST_SKIP() << "no " << root;
    struct Case {
        const char* file;
        const char* message;
    };
    const Case cases[] = {
        {"amm4yv__RayTracer/test2.ray", "got 17"},
        {"szhang37__Homework3/square.ray", "cannot open texture 'lightwood.jpg'"},
        {"mymary08054__graphicsAg3/chair.ray", "negative box size"},
        {"henry-md__ray-tracer/test.ray", "cannot open texture"},
        {"nabergh__ray-tracer/testpointlight.ray", "cannot open texture 'checkerboard.jpg'"},
    };
    for (const Case& c : cases) {
        Diagnostics diag;
        try {
            parse_scene_file((root / c.file).string(), diag);
            ADD_FAILURE() << c.file << " loaded";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Degenerate input: every image finite, every render finished.

bool all_finite(const Image& img) {
    for (const double v : img.rgb)
        if (!std::isfinite(v)) return false;
    return true;
}

TEST(Scenes, DegenerateInputRendersFiniteImages) {
    const std::string camera = "#camera 0 0.5 6  0 -0.08 -1  0 1 0  0.5\n";
    const std::string light = "#light_point 1 1 1  2 3 4  1 0 0\n";
    auto v1 = [](const std::string& spec, const std::string& n, const std::string& tr,
                 const std::string& ior) {
        std::string s = "#material 0 0 0  0.1 0.1 0.1  0.7 0.6 0.5  ";
        s += spec + "  " + n + "  " + tr + "  " + ior + " -1 !!\n";
        return s;
    };
    const std::string plain = v1("0.3 0.3 0.3", "20", "0 0 0", "1");
    const std::string body = "#shape_sphere 0 0 0.5 0 1\n#shape_box 0 0 -1 0 8 0.2 8\n";
    struct Case {
        const char* name;
        std::string text;
        int depth;
    };
    const Case cases[] = {
        {"zero-area and repeated-vertex triangles",
         camera + light + plain +
             "#vertex 0 0 0 0 0 0 0 0\n#vertex 1 1 1 0 0 0 1 0\n#vertex 2 2 2 0 0 0 0 1\n"
             "#vertex 1e-9 0 0 0 0 0 0 0\n#vertex 0 1 0 0 0 0 0 0\n"
             "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 0 1\n#shape_triangle 0 0 3 4\n" +
             body,
         5},
        {"group scaled by 1e-6 on one axis",
         camera + light + plain + "#group_begin 1 0 0 0  0 1e-6 0 0  0 0 1 0  0 0 0 1\n" + body +
             "#shape_cylinder 0 0 0 0 1 2\n#shape_cone 0 1 0 0 1 2\n#group_end\n" + body,
         5},
        {"rotated group scaled by 1e-6",
         camera + light + plain +
             "#group_begin 0.6 -0.8e-6 0 0.1  0.8 0.6e-6 0 0.2  0 0 1 0  0 0 0 1\n" + body +
             "#group_end\n",
         5},
        {"light inside a sphere and a box",
         camera +
             "#light_point 1 1 1  0 0.5 0  1 0 0\n#light_spot 1 1 1  0 -1 0  0 -1 0  1 0 0  "
             "0.5 1\n" +
             plain + body,
         5},
        {"attenuation all zero", camera + "#light_point 1 1 1  2 3 4  0 0 0\n" + plain + body, 5},
        {"spot exponent 1e6",
         camera + "#light_spot 1 1 1  0 3 0  0 -1 0  1 0 0  1.5 1e6\n" + plain + body, 5},
        {"specular exponent 0", camera + light + v1("1 1 1", "0", "0 0 0", "1") + body, 5},
        {"specular exponent 1e4", camera + light + v1("1 1 1", "1e4", "0 0 0", "1") + body, 5},
        {"refraction index 1", camera + light + v1("0.1 0.1 0.1", "20", "0.9 0.9 0.9", "1") + body,
         8},
        {"refraction index 1e-3",
         camera + light + v1("0.1 0.1 0.1", "20", "0.9 0.9 0.9", "1e-3") + body, 8},
        {"refraction index 10",
         camera + light + v1("0.1 0.1 0.1", "20", "0.9 0.9 0.9", "10") + body, 8},
        {"mirror box, depth 0",
         "#camera 0 0 0  0 0.1 -1  0 1 0  0.6\n" + light +
             "#light_point 1 1 1  0.3 0.2 0.1  1 0 0\n" + v1("1 1 1", "50", "0 0 0", "1") +
             "#shape_box 0 0 0 0 4 3 5\n#shape_sphere 0 0.5 -0.3 -1 0.4\n",
         0},
        {"mirror box, depth 100",
         "#camera 0 0 0  0 0.1 -1  0 1 0  0.6\n" +
             std::string("#light_point 1 1 1  0.3 0.2 0.1  1 0 0\n") +
             v1("1 1 1", "50", "0 0 0", "1") +
             "#shape_box 0 0 0 0 4 3 5\n#shape_sphere 0 0.5 -0.3 -1 0.4\n",
         100},
    };
    for (const Case& c : cases) {
        const RenderScene scene = test::compile(c.text);
        RenderSettings s;
        s.width = s.height = 32;
        s.max_depth = c.depth;
        s.cutoff = 0.0;  // depth alone bounds the recursion
        s.threads = 1;
        RenderState state;
        ASSERT_TRUE(render_samples(state, scene, make_render_plan(scene, s), s, 1)) << c.name;
        const Image img = state.image();
        double sum = 0;
        for (const double v : img.rgb) sum += v;
        std::printf("[ degenerate ] %-40s finite %d, mean %.4g, %llu rays\n", c.name,
                    all_finite(img), sum / static_cast<double>(img.rgb.size()),
                    static_cast<unsigned long long>(state.rays.total()));
        EXPECT_TRUE(all_finite(img)) << c.name;
        EXPECT_EQ(img.width, 32);
    }
    // Zero-length directions are parse errors (spec §3.1: d != 0), reported clearly.
    const std::string errors[][2] = {
        {"#camera 0 0 5  0 0 0  0 1 0  0.5\n", "camera view direction is zero"},
        {"#light_dir 1 1 1  0 0 0\n", "light direction is zero"},
        {"#light_spot 1 1 1  0 3 0  0 0 0  1 0 0  0.5 1\n", "spot light direction is zero"},
    };
    for (const auto& e : errors) {
        const std::string msg = test::parse_error(e[0] + plain + body);
        EXPECT_NE(msg.find("test.ray:1:"), std::string::npos) << msg;
        EXPECT_NE(msg.find(e[1]), std::string::npos) << msg;
    }
}

}  // namespace
}  // namespace rt
