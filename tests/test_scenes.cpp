// Whole scenes: every scene of scenes/ and every complete public scene renders without error
// and with no NaN or Inf; the public scenes that are malformed as published fail with a
// file:line:col message and never crash.
#include <filesystem>
#include <set>

#include "test_util.h"

namespace fs = std::filesystem;

namespace rt {
namespace {

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
        {"henry-md__ray-tracer/test.ray", "V3 scenes are not supported yet"},
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

}  // namespace
}  // namespace rt
