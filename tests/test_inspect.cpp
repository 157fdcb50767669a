// The ray tree of a pixel (rt/render/inspect.h): its colour is the rendered pixel bit for bit on
// every scene of scenes/ and of the public set, with the specialised and the generic plans; its
// terms add up to it; what it records of a hit, a light and a shadow ray is what the formulas of
// spec §7 give; its text and JSON name what they explain.
#include <cstring>
#include <filesystem>

#include "rt/render/inspect.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace rt {
namespace {

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The colour of a ray rebuilt from its recorded terms, added in the order the shading adds them
// (so it must be equal, not close); checks every child's term on the way.
Vec3 sum_of_terms(const PixelTree& tree, int index) {
    const InspectRay& r = tree.rays[static_cast<size_t>(index)];
    if (!r.hit) return r.color;
    Vec3 c = r.emissive + r.ambient;
    for (const InspectLight& l : r.lights) {
        if (l.ambient_term != Vec3(0.0)) c += l.ambient_term;
        c += l.value;
    }
    for (int k : r.children) {
        const InspectRay& child = tree.rays[static_cast<size_t>(k)];
        const Vec3 below = sum_of_terms(tree, k);
        EXPECT_TRUE(same_bits(below, child.color));
        const bool refl = child.kind == InspectRay::Kind::Reflected;
        EXPECT_TRUE(same_bits((refl ? r.k_reflect : r.k_transmit) * below,
                              refl ? r.reflected : r.refracted));
        c += refl ? r.reflected : r.refracted;
    }
    return c;
}

// 20 pixels spread over the image (a fixed pseudo-random choice, the corners among them).
std::vector<std::pair<int, int>> some_pixels(int w, int h) {
    std::vector<std::pair<int, int>> px = {{0, 0}, {w - 1, h - 1}, {w / 2, h / 2}};
    uint32_t s = 12345;
    while (px.size() < 20) {
        s = s * 1664525u + 1013904223u;
        const int x = static_cast<int>((s >> 8) % static_cast<uint32_t>(w));
        s = s * 1664525u + 1013904223u;
        px.emplace_back(x, static_cast<int>((s >> 8) % static_cast<uint32_t>(h)));
    }
    return px;
}

// Renders the scene at w x h, 1 spp, with both plans and checks 20 pixels' trees against it.
// Returns the number of rays the trees held.
size_t check_scene(const RenderScene& scene, int w, int h, const std::string& name) {
    size_t rays = 0;
    for (const bool specialize : {true, false}) {
        RenderSettings s;
        s.width = w;
        s.height = h;
        s.threads = 2;
        s.specialize = specialize;
        const RenderPlan plan = make_render_plan(scene, s);
        RenderState state;
        rt::render_samples(state, scene, plan, s, 1);
        const Image img = state.image();
        for (const auto& [x, y] : some_pixels(w, h)) {
            SCOPED_TRACE(name + (specialize ? " specialised" : " generic") + " pixel " +
                         std::to_string(x) + "," + std::to_string(y));
            const PixelTree tree = inspect_pixel(scene, plan, s, x, y);
            const Vec3 pixel = img.at(x, y);
            EXPECT_TRUE(same_bits(tree.color, pixel))
                << tree.color.x << " " << tree.color.y << " " << tree.color.z << " vs " << pixel.x
                << " " << pixel.y << " " << pixel.z;
            EXPECT_TRUE(same_bits(tree.pixel, pixel));
            EXPECT_TRUE(same_bits(sum_of_terms(tree, 0), tree.color));
            rays += tree.rays.size();
        }
    }
    return rays;
}

TEST(Inspect, TreeColourIsThePixelOnEverySceneOfScenes) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(fs::path(RT_SOURCE_DIR) / "scenes")) {
        if (e.path().extension() != ".ray") continue;
        Diagnostics diag;
        const RenderScene scene = compile_scene(parse_scene_file(e.path().string(), diag));
        check_scene(scene, 64, 48, e.path().filename().string());
        ++n;
    }
    EXPECT_GE(n, 6);
}

TEST(Inspect, TreeColourIsThePixelOnEveryPublicScene) {
    const fs::path root(RT_PUBLIC_SCENES_DIR);
    if (!fs::exists(root)) GTEST_SKIP() << "no " << root;
    ParseOptions options;
    options.missing_textures = MissingTextures::Checker;
    int n = 0;
    size_t rays = 0;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        if (e.path().extension() != ".ray") continue;
        Diagnostics diag;
        RenderScene scene;
        try {
            scene = compile_scene(parse_scene_file(e.path().string(), diag, options));
        } catch (const SceneError&) {
            continue;  // malformed as published (test_scenes.cpp checks their messages)
        }
        rays += check_scene(scene, 48, 36, fs::relative(e.path(), root).string());
        ++n;
    }
    EXPECT_GE(n, 60);
    EXPECT_GT(rays, static_cast<size_t>(n) * 40);  // reflected and refracted rays among them
}

// A sphere lit by one point light, in front of a mirror: every term of the camera ray's hit is
// what spec §7.1 and §7.2 give, and the reflected ray is its child.
constexpr const char* kMirrorScene = R"(
#camera 0 0 5  0 0 -1  0 1 0  0.5
#background 0.1 0.2 0.3
#ambient 0.2 0.2 0.2
#light_point 1 0.9 0.8  0 4 4  1 0.1 0
#material 0 0 0  0.1 0.1 0.1  0.5 0.5 0.5  0.25 0.25 0.25  10  0 0 0  1  -1 !shiny!
#shape_sphere 0  0 0 0  1
)";

TEST(Inspect, TermsAreThoseOfTheFormulas) {
    const RenderScene scene = test::compile(kMirrorScene);
    RenderSettings s;
    s.width = 41;
    s.height = 41;
    const RenderPlan plan = make_render_plan(scene, s);
    const PixelTree tree = inspect_pixel(scene, plan, s, 20, 20);
    ASSERT_FALSE(tree.rays.empty());
    const InspectRay& cam = tree.rays[0];
    ASSERT_TRUE(cam.hit);
    EXPECT_NEAR(cam.distance, 4.0, 1e-9);  // the camera at z 5, the sphere's front at z 1
    EXPECT_VEC_NEAR(cam.point, Vec3(0, 0, 1), 1e-9);
    EXPECT_VEC_NEAR(cam.n, Vec3(0, 0, 1), 1e-9);
    EXPECT_TRUE(cam.entering);
    EXPECT_EQ(cam.prim.kind, ShapeKind::Sphere);
    EXPECT_VEC_NEAR(cam.ambient, Vec3(0.1 * 0.2), 1e-15);
    ASSERT_EQ(cam.lights.size(), 1u);
    const InspectLight& l = cam.lights[0];
    const double d = std::sqrt(16.0 + 9.0);  // (0 4 4) - (0 0 1)
    EXPECT_TRUE(l.attenuated);
    EXPECT_NEAR(l.distance, d, 1e-9);
    EXPECT_NEAR(l.denominator, 1 + 0.1 * d, 1e-12);
    EXPECT_NEAR(l.factor, 1 / (1 + 0.1 * d), 1e-12);
    EXPECT_NEAR(l.n_dot_l, 3.0 / d, 1e-9);
    EXPECT_TRUE(l.shadow_tested);
    EXPECT_EQ(l.shadow_ray_count, 1u);
    EXPECT_VEC_NEAR(l.shadow, Vec3(1.0), 0);
    const Vec3 i = Vec3(1, 0.9, 0.8) * l.factor;
    EXPECT_VEC_NEAR(l.diffuse_term, i * 0.5 * l.n_dot_l, 1e-12);
    // R: the view ray (0 0 -1) mirrored about N = (0 0 1) is (0 0 1); R.L = 3 / d.
    EXPECT_NEAR(l.r_dot_l, 3.0 / d, 1e-9);
    EXPECT_NEAR(l.highlight, std::pow(3.0 / d, 10), 1e-9);
    EXPECT_VEC_NEAR(l.specular_term, i * 0.25 * l.highlight, 1e-12);
    // The mirror ray goes back toward the camera and misses: the background times K_S.
    ASSERT_EQ(cam.children.size(), 1u);
    const InspectRay& refl = tree.rays[static_cast<size_t>(cam.children[0])];
    EXPECT_EQ(refl.kind, InspectRay::Kind::Reflected);
    EXPECT_EQ(refl.depth, s.max_depth - 1);
    EXPECT_FALSE(refl.hit);
    EXPECT_VEC_NEAR(refl.color, Vec3(0.1, 0.2, 0.3), 0);
    EXPECT_VEC_NEAR(cam.reflected, Vec3(0.1, 0.2, 0.3) * 0.25, 1e-15);
}

// A shadow ray through a glass ball and an opaque one: the occluders are listed in order with
// their transparency, and the light adds nothing.
TEST(Inspect, ShadowRaysListTheirOccluders) {
    const RenderScene scene = test::compile(R"(
#camera 5 0 0  -1 0 0  0 1 0  0.5
#light_point 1 1 1  6 6 0  1 0 0
#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0 0 0  1  -1 !white!
#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0.5 0.5 0.5  1  -1 !glass!
#shape_sphere 0  0 0 0  1
#shape_sphere 1  3 2.4 0  0.3
#shape_sphere 0  4.5 4.2 0  0.3
)");
    RenderSettings s;
    s.width = 41;
    s.height = 41;
    const RenderPlan plan = make_render_plan(scene, s);
    const PixelTree tree = inspect_pixel(scene, plan, s, 20, 20);
    ASSERT_EQ(tree.rays[0].lights.size(), 1u);
    const InspectLight& l = tree.rays[0].lights[0];
    ASSERT_EQ(l.shadow_rays.size(), 1u);
    const auto& occ = l.shadow_rays[0].occluders;
    // The segment from (1 0 0) to the light, 7.81 long, meets the glass sphere's centre at 0.4
    // of its length and the opaque one's at 0.7.
    const double len = std::sqrt(25.0 + 36.0);
    ASSERT_EQ(occ.size(), 3u);
    EXPECT_NEAR(occ[0].distance, 0.4 * len - 0.3, 1e-6);
    EXPECT_NEAR(occ[1].distance, 0.4 * len + 0.3, 1e-6);
    EXPECT_VEC_NEAR(occ[0].transparent, Vec3(0.5), 0);
    EXPECT_VEC_NEAR(occ[1].transparent, Vec3(0.5), 0);
    EXPECT_EQ(occ[2].transparent, Vec3(0.0));  // the opaque one ends the list
    EXPECT_NEAR(occ[2].distance, 0.7 * len - 0.3, 1e-6);
    EXPECT_EQ(l.shadow, Vec3(0.0));
    EXPECT_EQ(l.value, Vec3(0.0));
    EXPECT_EQ(l.note, "in shadow");
}

// Two equal lights (a public scene has them: dcalvo's chess_room.ray) keep their own numbers,
// and a dark one left out of the plan keeps the numbering of the file.
TEST(Inspect, EqualLightsKeepTheirNumbers) {
    const RenderScene scene = test::compile(R"(
#camera 0 0 5  0 0 -1  0 1 0  0.5
#light_point 1 1 1  0 0 5  1 0 0
#light_point 0 0 0  0 5 5  1 0 0
#light_point 1 1 1  0 0 5  1 0 0
#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0 0 0  1  -1 !white!
#shape_sphere 0  0 0 0  1
)");
    RenderSettings s;
    s.width = 21;
    s.height = 21;
    const PixelTree tree = inspect_pixel(scene, make_render_plan(scene, s), s, 10, 10);
    ASSERT_EQ(tree.rays.at(0).lights.size(), 2u);
    EXPECT_EQ(tree.rays[0].lights[0].light, 0);
    EXPECT_EQ(tree.rays[0].lights[1].light, 2);
}

// Inside glass of index 1.5, a ray meeting the surface at sin i = 0.9 cannot leave: the tree
// says so (and traces the mirror ray alone), and N is n_s flipped to face the ray.
TEST(Inspect, TotalInternalReflectionIsNamed) {
    const RenderScene scene = test::compile(R"(
#camera 0.9 0 0  0 0 -1  0 1 0  0.5
#light_point 1 1 1  0 5 0  1 0 0
#material 0 0 0  0 0 0  0 0 0  0.1 0.1 0.1  10  1 1 1  1.5  -1 !glass!
#shape_sphere 0  0 0 0  1
)");
    RenderSettings s;
    s.width = 41;
    s.height = 41;
    const PixelTree tree = inspect_pixel(scene, make_render_plan(scene, s), s, 20, 20);
    const InspectRay& r = tree.rays.at(0);
    ASSERT_TRUE(r.hit);
    EXPECT_FALSE(r.entering);
    EXPECT_VEC_NEAR(r.n, -r.n_shading, 0);
    ASSERT_EQ(r.stops.size(), 1u);
    EXPECT_EQ(r.stops[0].kind, "refracted");
    EXPECT_NE(r.stops[0].why.find("total internal reflection (eta 1.5: sin of the refracted "
                                  "angle would be 1.35"),
              std::string::npos)
        << r.stops[0].why;
    ASSERT_EQ(r.children.size(), 1u);
    EXPECT_EQ(tree.rays[static_cast<size_t>(r.children[0])].kind, InspectRay::Kind::Reflected);
}

// Supersampled and soft-shadowed: each sample's tree draws the random numbers the render draws,
// so the samples' colours, summed as the render sums them, give the pixel.
TEST(Inspect, SamplesOfAJitteredPixelSumToIt) {
    const RenderScene scene = test::compile(kMirrorScene);
    RenderSettings s;
    s.width = 17;
    s.height = 17;
    s.light_radius = 0.5;
    const RenderPlan plan = make_render_plan(scene, s);
    RenderState state;
    rt::render_samples(state, scene, plan, s, 4);
    const Image img = state.image();
    for (const auto& [x, y] : some_pixels(17, 17)) {
        Vec3 c[4];
        for (uint32_t k = 0; k < 4; ++k) {
            const PixelTree t = inspect_pixel(scene, plan, s, x, y, k, 4);
            c[k] = t.color;
            EXPECT_TRUE(t.random);
            EXPECT_TRUE(same_bits(t.pixel, img.at(x, y)));
        }
        EXPECT_FALSE(same_bits(c[0], c[1]) && same_bits(c[1], c[2]) && same_bits(c[2], c[3]) &&
                     x == 8 && y == 8);
        // The render's pairwise sum of four samples: (0 + 1) + (2 + 3).
        EXPECT_TRUE(same_bits(((c[0] + c[1]) + (c[2] + c[3])) / 4.0, img.at(x, y)));
    }
}

// The check above sees a term that is off by a relative 1e-12: a tree whose terms do not add up
// fails it.
TEST(Inspect, ABrokenTermIsCaught) {
    const RenderScene scene = test::compile(kMirrorScene);
    RenderSettings s;
    s.width = 41;
    s.height = 41;
    PixelTree tree = inspect_pixel(scene, make_render_plan(scene, s), s, 20, 20);
    ASSERT_TRUE(same_bits(sum_of_terms(tree, 0), tree.color));
    Vec3& v = tree.rays[0].lights.at(0).value;
    v.y *= 1.0 + 1e-12;
    EXPECT_FALSE(same_bits(sum_of_terms(tree, 0), tree.color));
}

TEST(Inspect, OutOfRangeIsAnError) {
    const RenderScene scene = test::compile(kMirrorScene);
    RenderSettings s;
    s.width = 8;
    s.height = 6;
    const RenderPlan plan = make_render_plan(scene, s);
    EXPECT_THROW(inspect_pixel(scene, plan, s, 8, 0), std::invalid_argument);
    EXPECT_THROW(inspect_pixel(scene, plan, s, 0, -1), std::invalid_argument);
    EXPECT_THROW(inspect_pixel(scene, plan, s, 0, 0, 1, 1), std::invalid_argument);
    try {
        inspect_pixel(scene, plan, s, 0, 6);
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("rows 0..5"), std::string::npos) << e.what();
    }
}

TEST(Inspect, TextAndJsonNameTheTerms) {
    Diagnostics diag;
    const SceneDesc desc = test::parse(kMirrorScene, &diag);
    CompileReport report;
    report.record_locations = true;
    const RenderScene scene = compile_scene(desc, &report);
    RenderSettings s;
    s.width = 41;
    s.height = 41;
    const PixelTree tree = inspect_pixel(scene, make_render_plan(scene, s), s, 20, 20);
    const InspectNames names{&desc, &report.prim_locs, &report.material_names};
    const std::string text = inspect_text(tree, scene, names);
    for (const char* want : {"camera ray, depth 5", "hits sphere 0 of instance 0 at test.ray:7:1",
                             "attenuation = 1 / (c0 1 + c1 0.1", "diffuse  = I_l",
                             "x N.L 0.6 =", "reflected = K_S (0.25 0.25 0.25)",
                             "misses everything: background (0.1 0.2 0.3)", "pixel value"})
        EXPECT_NE(text.find(want), std::string::npos) << want << "\n" << text;
    const std::string json = inspect_json(tree, scene, names);
    for (const char* want : {"{\"pixel\":[20,20],\"sample\":0,", "\"kind\":\"camera\"",
                             "\"kind\":\"reflected\"", "\"kind\":\"shadow\"",
                             "\"location\":\"test.ray:7:1\"", "\"hit\":null", "\"n_dot_l\":0.6"})
        EXPECT_NE(json.find(want), std::string::npos) << want << "\n" << json;
}

}  // namespace
}  // namespace rt
