// The ray tree of a pixel (rt/render/inspect.h): its colour is the rendered pixel bit for bit on
// every scene of scenes/ and of the public set, with the specialised and the generic plans; its
// terms add up to it; what it records of a hit, a light and a shadow ray is what the formulas of
// spec §7 give; its text and JSON name what they explain.
#include <cstring>
#include <filesystem>
#include <sstream>

#include "json_check.h"
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
    // The reflected term, then the refracted one, each from its ray (recorded or not).
    for (const auto kind : {InspectRay::Kind::Reflected, InspectRay::Kind::Refracted}) {
        const bool refl = kind == InspectRay::Kind::Reflected;
        const auto add = [&](const Vec3& below) {
            EXPECT_TRUE(same_bits((refl ? r.k_reflect : r.k_transmit) * below,
                                  refl ? r.reflected : r.refracted));
            c += refl ? r.reflected : r.refracted;
        };
        for (int k : r.children) {
            const InspectRay& child = tree.rays[static_cast<size_t>(k)];
            if (child.kind != kind) continue;
            const Vec3 below = sum_of_terms(tree, k);
            EXPECT_TRUE(same_bits(below, child.color));
            add(below);
        }
        for (const InspectRay::NotRecorded& n : r.not_recorded)
            if (n.kind == kind) add(n.color);
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

// A mirror box with two glass spheres in it: each hit on glass sends a reflected and a refracted
// ray, each of half the path weight, and the mirrors keep it, so the tree doubles at each glass
// hit until the weights fall below --cutoff: 7,195 rays for the pixel at --depth 256, a JSON of
// 14 MB nested 470 levels deep and 39 MB of text, whose indentation grew with the depth.
constexpr const char* kExplodingScene = R"(
#camera 0 0 0  0.3 0.1 -1  0 1 0  0.5
#light_point 1 1 1  0 0.9 0  1 0 0
#material 0 0 0  0 0 0  0 0 0  1 1 1  10  0 0 0  1  -1 !mirror!
#material 0 0 0  0 0 0  0 0 0  0.5 0.5 0.5  10  0.5 0.5 0.5  1.5  -1 !glass!
#shape_box 0  0 0 0  4 2 6
#shape_sphere 1  0.8 0 -1.5  0.5
#shape_sphere 1  -1 0.3 1.5  0.6
)";

// The rays not recorded, counted from the tree's lists: each entry is a ray and those below it.
size_t not_recorded_in_lists(const PixelTree& tree) {
    size_t n = 0;
    for (const InspectRay& r : tree.rays)
        for (const InspectRay::NotRecorded& x : r.not_recorded) n += x.rays;
    return n;
}

// The widest indentation of the text's lines.
size_t widest_indent(const std::string& text) {
    size_t widest = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        widest = std::max(widest, line.find_first_not_of(' '));
    return widest;
}

// The exploding scene's centre pixel of an 8x8 image at depth 256, within `limits`.
PixelTree exploding_tree(const RenderScene& scene, const InspectLimits& limits = {}) {
    RenderSettings s;
    s.width = 8;
    s.height = 8;
    s.max_depth = 256;
    return inspect_pixel(scene, make_render_plan(scene, s), s, 4, 4, 0, 1, limits);
}

TEST(Inspect, AnExplodingTreeRecordsItsLimitOfRays) {
    const RenderScene scene = test::compile(kExplodingScene);
    const PixelTree tree = exploding_tree(scene);
    EXPECT_EQ(tree.rays.size(), PixelTree::kMaxRays);
    EXPECT_GT(tree.rays_not_recorded, 1000u);
    EXPECT_EQ(not_recorded_in_lists(tree), tree.rays_not_recorded);
    // The rays past the limit are traced all the same: the colour is the pixel's, and the
    // terms, with the colours of the rays not recorded, still add up to it.
    EXPECT_TRUE(same_bits(tree.color, tree.pixel));
    EXPECT_TRUE(same_bits(sum_of_terms(tree, 0), tree.color));
}

// The tests of the text and the JSON record 300 rays of the tree (the first ones, down its
// first branches, 20 levels deep), for speed: a limit of 4096 is the same code.
constexpr InspectLimits kSomeRays{300, PixelTree::kMaxRecords};

TEST(Inspect, AnExplodingTreesTextIsIndentedSoFarAndSaysWhatIsLeftOut) {
    const RenderScene scene = test::compile(kExplodingScene);
    const PixelTree tree = exploding_tree(scene, kSomeRays);
    ASSERT_EQ(tree.rays.size(), 300u);
    const std::string text = inspect_text(tree, scene, {});
    // A ray's lines are 2 deeper than the ray, a shadow ray's surfaces 6 deeper.
    EXPECT_LE(widest_indent(text), static_cast<size_t>(kMaxTextIndent) + 8);
    EXPECT_LT(text.size(), 300u * 3000u) << "about 15 lines a ray, none indented past 72";
    EXPECT_NE(text.find(std::to_string(tree.rays_not_recorded) +
                        " more rays traced but not recorded: a tree records at most 300 rays"),
              std::string::npos);
    EXPECT_NE(text.find("not recorded (past the tree's limits): "), std::string::npos);
    // Past the indentation's limit, a ray's sum (after its children, at the same indentation)
    // names its ray.
    EXPECT_NE(text.find(std::string(kMaxTextIndent + 2, ' ') + "sum of the depth "),
              std::string::npos);
    // Every recorded ray has its line, in the order of PixelTree::rays (rayview's panel counts
    // them so), and no other line starts as a ray's does.
    size_t ray_lines = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        const std::string t = line.substr(std::min(line.size(), line.find_first_not_of(' ')));
        for (const char* kind : {"camera ray,", "reflected ray,", "refracted ray,"})
            ray_lines += t.rfind(kind, 0) == 0;
    }
    EXPECT_EQ(ray_lines, tree.rays.size());
}

TEST(Inspect, AnExplodingTreesJsonIsFlatAndCountsItsRays) {
    const RenderScene scene = test::compile(kExplodingScene);
    const PixelTree tree = exploding_tree(scene, kSomeRays);
    const std::string json = inspect_json(tree, scene, {});
    test::JsonValue v;
    std::string why;
    int depth = 0;
    ASSERT_TRUE(test::parse_strict_json(json, &v, &why, 64, &depth)) << why;
    EXPECT_LE(depth, 8) << "the nesting does not grow with the tree";
    const test::JsonValue& rays = v["rays"];
    EXPECT_EQ(rays.array.size(), 300u);
    ASSERT_TRUE(v.has("rays_recorded"));
    EXPECT_EQ(v["rays_recorded"].number, 300.0);
    EXPECT_EQ(v["limits"]["rays"].number, 300.0);
    ASSERT_TRUE(v.has("rays_not_recorded"));
    EXPECT_EQ(v["rays_not_recorded"].number, static_cast<double>(tree.rays_not_recorded));
    // Each ray names its parent, and its parent lists it among its children.
    for (size_t i = 1; i < rays.array.size(); ++i) {
        const test::JsonValue& r = rays.array[i];
        ASSERT_TRUE(r.has("parent"));
        const size_t parent = static_cast<size_t>(r["parent"].number);
        ASSERT_LT(parent, i);
        bool listed = false;
        for (const test::JsonValue& c : rays.array[parent]["children"].array)
            listed |= static_cast<size_t>(c.number) == i;
        EXPECT_TRUE(listed) << "ray " << i;
    }
}

// Lights are what the tree records most of at each hit: past the budget of records no further
// ray is recorded, so 200 lights do not multiply the memory of the 4,096 rays.
TEST(Inspect, ManyLightsEndTheRecordingSooner) {
    // The lights before the materials and shapes (spec §3): after the exploding scene's light.
    std::string text = kExplodingScene;
    std::string lights;
    for (int k = 0; k < 200; ++k)
        lights += "#light_point 0.01 0.01 0.01  " + std::to_string(-1.5 + 0.015 * k) + " 0.8 " +
                  std::to_string(-2.5 + 0.025 * k) + "  1 0 0\n";
    text.insert(text.find("#material"), lights);
    const RenderScene scene = test::compile(text);
    RenderSettings s;
    s.width = 8;
    s.height = 8;
    s.max_depth = 12;
    const PixelTree tree = inspect_pixel(scene, make_render_plan(scene, s), s, 4, 4);
    EXPECT_GT(tree.rays_not_recorded, 0u);
    EXPECT_LE(tree.records, PixelTree::kMaxRecords + 201);
    EXPECT_LE(tree.rays.size(), PixelTree::kMaxRecords / 201 + 2);
    EXPECT_TRUE(same_bits(sum_of_terms(tree, 0), tree.color));
}

// Names from the scene reach the text escaped as the parser's messages escape them (a control
// byte would move the terminal's cursor), and the JSON is strict UTF-8 JSON whatever the bytes.
TEST(Inspect, NamesAreEscapedInTheTextAndTheJson) {
    Diagnostics diag;
    const SceneDesc desc = test::parse(
        "#camera 0 0 5  0 0 -1  0 1 0  0.5\n"
        "#light_point 1 1 1  0 4 4  1 0 0\n"
        "#material 0 0 0  0.1 0.1 0.1  0.5 0.5 0.5  0 0 0  10  0 0 0  1  -1 "
        "!red\x1b[2J\xff\xc3\xa9!\n"
        "#shape_sphere 0  0 0 0  1\n",
        &diag);
    CompileReport report;
    report.record_locations = true;
    const RenderScene scene = compile_scene(desc, &report);
    RenderSettings s;
    s.width = 9;
    s.height = 9;
    const PixelTree tree = inspect_pixel(scene, make_render_plan(scene, s), s, 4, 4);
    ASSERT_TRUE(tree.rays.at(0).hit);
    const InspectNames names{&desc, &report.prim_locs, &report.material_names};
    const std::string text = inspect_text(tree, scene, names);
    EXPECT_EQ(text.find('\x1b'), std::string::npos);
    EXPECT_EQ(text.find('\xff'), std::string::npos);
    EXPECT_NE(text.find("material 0 !'red\\x1b[2J\\xff\xc3\xa9'!"), std::string::npos) << text;
    const std::string json = inspect_json(tree, scene, names);
    test::JsonValue v;
    std::string why;
    ASSERT_TRUE(test::parse_strict_json(json, &v, &why)) << why;
    EXPECT_NE(json.find("\"name\":\"red\\u001b[2J\\ufffd\xc3\xa9\""), std::string::npos) << json;
}

// Spec §7.6's worked example 1 seen by a camera at its eye (0 10 10) looking along its ray, so
// that the centre pixel of a 41x41 image is that ray; the plane y = 0 as two triangles. `extra`
// adds directives (an occluder, a second light).
std::string worked_example_1(
    const std::string& extra = "",
    const std::string& light = "#light_point 1 1 1  5 5 5  0.01 0.02 0.03") {
    return "#camera 0 10 10  3 -10 -4  0 1 0  0.5\n"
           "#ambient 0.5 0.5 0.5\n#background 0.2 0.2 0.2\n" +
           light +
           "\n#material 0 0 0  .3 .3 .3  .1 .1 .5  1 1 1  100  0 0 0  1  -1 !!\n"
           "#vertex -100 0 -100 0 0 0 0 0\n#vertex -100 0 100 0 0 0 0 0\n"
           "#vertex 100 0 100 0 0 0 0 0\n#vertex 100 0 -100 0 0 0 0 0\n"
           "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n" +
           extra;
}

PixelTree worked_tree(const RenderScene& scene, int x = 20, int y = 20, int depth = 5) {
    RenderSettings s;
    s.width = 41;
    s.height = 41;
    s.max_depth = depth;
    s.cutoff = 0.001;
    return inspect_pixel(scene, make_render_plan(scene, s), s, x, y);
}

// The 8 bits written for the pixel: §7.6's bytes (145, 145, 236), from its colour
// (0.566933 0.566933 0.925082) through floor(255 clamp(c) + 0.5).
TEST(Inspect, TheOutputBytesAreTheWorkedExamples) {
    const RenderScene scene = test::compile(worked_example_1());
    const PixelTree tree = worked_tree(scene);
    EXPECT_VEC_NEAR(tree.pixel, Vec3(0.566933, 0.566933, 0.925082), 1e-6);
    EXPECT_EQ(tree.output.bytes[0], 145);
    EXPECT_EQ(tree.output.bytes[1], 145);
    EXPECT_EQ(tree.output.bytes[2], 236);
    const std::string text = inspect_text(tree, scene, {});
    EXPECT_NE(text.find("written as 8 bits (145 145 236) = floor(255 x clamp(c, 0, 1) + 0.5)"),
              std::string::npos)
        << text;
    test::JsonValue v;
    std::string why;
    ASSERT_TRUE(test::parse_strict_json(inspect_json(tree, scene, {}), &v, &why)) << why;
    ASSERT_EQ(v["output"]["bytes"].array.size(), 3u);
    EXPECT_EQ(v["output"]["bytes"].array[0].number, 145.0);
    EXPECT_EQ(v["output"]["bytes"].array[2].number, 236.0);
}

// The camera's inputs (spec §6.1, §6.2), by hand: f = (3 -10 -4)/sqrt 125, r = f x up
// normalised = (0.8 0 0.6), up' = r x f = (6 5 -8)/sqrt 125, tan_h = tan 0.5 = tan_w (square);
// the centre pixel's (x, y) is (0, 0), pixel (0, 0)'s is (-40/41, 40/41) tan 0.5.
TEST(Inspect, TheCamerasInputsForThePixel) {
    const RenderScene scene = test::compile(worked_example_1());
    const PixelTree centre = worked_tree(scene);
    const InspectCamera& c = centre.camera;
    EXPECT_TRUE(c.from_file);
    EXPECT_DOUBLE_EQ(c.half_height_angle_rad, 0.5);
    EXPECT_NEAR(c.tan_h, 0.546302489843790, 1e-14);
    EXPECT_NEAR(c.tan_w, 0.546302489843790, 1e-14);
    const double s125 = std::sqrt(125.0);
    EXPECT_VEC_NEAR(c.forward, Vec3(3, -10, -4) / s125, 1e-15);
    EXPECT_VEC_NEAR(c.right, Vec3(0.8, 0, 0.6), 1e-15);
    EXPECT_VEC_NEAR(c.up, Vec3(6, 5, -8) / s125, 1e-15);
    EXPECT_VEC_NEAR(c.position, Vec3(0, 10, 10), 0);
    EXPECT_NEAR(c.image_point.x, 0.0, 1e-15);
    EXPECT_NEAR(c.image_point.y, 0.0, 1e-15);
    EXPECT_EQ(centre.position, Vec2(0.5));
    const PixelTree corner = worked_tree(scene, 0, 0);
    EXPECT_NEAR(corner.camera.image_point.x, -40.0 / 41.0 * std::tan(0.5), 1e-15);
    EXPECT_NEAR(corner.camera.image_point.y, 40.0 / 41.0 * std::tan(0.5), 1e-15);
    // The camera ray is normalize(f + x r + y up').
    const Vec3 d = glm::normalize(c.forward + corner.camera.image_point.x * c.right +
                                  corner.camera.image_point.y * c.up);
    EXPECT_VEC_NEAR(corner.rays.at(0).ray.d, d, 1e-15);
    const std::string text = inspect_text(corner, scene, {});
    EXPECT_NE(text.find("camera (the scene's): ha 28.6479 deg (the half-height angle), tan_h = "
                        "tan(ha) 0.546302, tan_w = tan_h x 41/41 0.546302"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("sample offset (sx sy) (0.5 0.5): x = (2 (i + sx) / w - 1) tan_w = "
                        "-0.532978, y = (1 - 2 (j + sy) / h) tan_h = 0.532978"),
              std::string::npos)
        << text;
    // Without a camera: §6.3's pi/6.
    const RenderScene no_camera = test::compile(
        "#light_point 1 1 1  5 5 5  1 0 0\n"
        "#material 0 0 0  .3 .3 .3  .1 .1 .5  0 0 0  1  0 0 0  1  -1 !!\n"
        "#shape_sphere 0  0 0 0  1\n");
    const PixelTree dflt = worked_tree(no_camera);
    EXPECT_FALSE(dflt.camera.from_file);
    EXPECT_NEAR(dflt.camera.half_height_angle_rad, kPi / 6, 1e-15);
}

// The shadow ray's origin offset (spec §7.5: P + s delta n_g, delta a bound on P's error). On
// §7.6's plane y = 0 the hit point is exact, delta is 0 and the text says the origin is the
// hit point itself; on a sphere the origin is moved along +n_g (the light's side) by an offset
// that is not zero and far below a fixed epsilon's 1e-4. §7.6's light terms on the way.
TEST(Inspect, TheShadowRaysOriginOffsetIsShown) {
    const RenderScene scene = test::compile(worked_example_1());
    const PixelTree tree = worked_tree(scene);
    const InspectRay& r = tree.rays.at(0);
    EXPECT_VEC_NEAR(r.point, Vec3(3, 0, 6), 1e-12);
    ASSERT_EQ(r.lights.size(), 1u);
    const InspectLight& l = r.lights[0];
    EXPECT_NEAR(l.n_dot_l, 0.912871, 1e-6);
    EXPECT_NEAR(l.denominator, 1.019545, 1e-6);
    EXPECT_VEC_NEAR(l.diffuse_term, Vec3(0.089537, 0.089537, 0.447686), 1e-6);
    EXPECT_VEC_NEAR(l.specular_term, Vec3(0.127396), 1e-6);
    ASSERT_EQ(l.shadow_rays.size(), 1u);
    const InspectShadowRay& flat = l.shadow_rays[0];
    EXPECT_VEC_NEAR(flat.hit, r.point, 0);
    EXPECT_EQ(flat.offset, Vec3(0.0));
    EXPECT_EQ(flat.ray.o, flat.hit);
    EXPECT_TRUE(l.no_shadow_ray.empty());
    const std::string text = inspect_text(tree, scene, {});
    EXPECT_NE(text.find("origin offset 0 (the hit point's error bound is 0 there, spec §7.5): the "
                        "origin is the hit point (3 0 6) itself"),
              std::string::npos)
        << text;

    const RenderScene ball = test::compile(R"(
#camera 0 0 5  0 0 -1  0 1 0  0.5
#light_point 1 1 1  0 4 4  1 0 0
#material 0 0 0  0 0 0  .5 .5 .5  0 0 0  1  0 0 0  1  -1 !!
#shape_sphere 0  0 0 0  1
)");
    const PixelTree bt = worked_tree(ball);
    const InspectRay& br = bt.rays.at(0);
    const InspectShadowRay& sr = br.lights.at(0).shadow_rays.at(0);
    EXPECT_VEC_NEAR(sr.hit, Vec3(0, 0, 1), 1e-12);
    const double len = glm::length(sr.offset);
    EXPECT_GT(len, 0.0);
    EXPECT_LT(len, 1e-12);
    EXPECT_GT(glm::dot(sr.offset, br.n_geometric) / len, 1.0 - 1e-9);  // along +n_g
    EXPECT_EQ(sr.ray.o, sr.hit + sr.offset);
    EXPECT_NE(sr.ray.o, sr.hit);
    const std::string btext = inspect_text(bt, ball, {});
    EXPECT_NE(btext.find(", along +n_g, spec §7.5): the origin is the hit point (0 0 1) + it"),
              std::string::npos)
        << btext;
    test::JsonValue v;
    std::string why;
    ASSERT_TRUE(test::parse_strict_json(inspect_json(bt, ball, {}), &v, &why)) << why;
    const test::JsonValue& js = v["rays"].array.at(0)["shadow_rays"].array.at(0);
    EXPECT_EQ(js["origin_offset"].array.at(2).number, sr.offset.z);
    EXPECT_EQ(js["hit_point"].array.at(2).number, sr.hit.z);
}

// A ball on the segment from P to the light: the light keeps §7.6's diffuse and specular terms
// (as computed before S_l) and adds 0; C = ambient 0.15 + reflection 0.2 = 0.35, byte 89.
TEST(Inspect, ALightInShadowKeepsItsTerms) {
    const RenderScene scene = test::compile(worked_example_1("#shape_sphere 0  4 2.5 5.5  0.4\n"));
    const PixelTree tree = worked_tree(scene);
    const InspectLight& l = tree.rays.at(0).lights.at(0);
    EXPECT_EQ(l.shadow, Vec3(0.0));
    EXPECT_EQ(l.note, "in shadow");
    EXPECT_TRUE(l.terms_known);
    EXPECT_VEC_NEAR(l.diffuse_term, Vec3(0.089537, 0.089537, 0.447686), 1e-6);
    EXPECT_VEC_NEAR(l.specular_term, Vec3(0.127396), 1e-6);
    EXPECT_EQ(l.value, Vec3(0.0));
    EXPECT_VEC_NEAR(tree.pixel, Vec3(0.35), 1e-12);
    EXPECT_EQ(tree.output.bytes[0], 89);
    EXPECT_TRUE(same_bits(sum_of_terms(tree, 0), tree.color));
    const std::string text = inspect_text(tree, scene, {});
    EXPECT_NE(text.find("x N.L 0.912871 = (0.0895371 0.0895371 0.447686)"), std::string::npos)
        << text;
    EXPECT_NE(text.find("adds S_l x (diffuse + specular) = (0 0 0): in shadow"), std::string::npos)
        << text;
    test::JsonValue v;
    std::string why;
    ASSERT_TRUE(test::parse_strict_json(inspect_json(tree, scene, {}), &v, &why)) << why;
    const test::JsonValue& jl = v["rays"].array.at(0)["terms"]["lights"].array.at(0);
    EXPECT_NEAR(jl["diffuse"].array.at(2).number, 0.447686, 1e-6);
    EXPECT_NEAR(jl["specular"].array.at(0).number, 0.127396, 1e-6);
    EXPECT_EQ(jl["value"].array.at(0).number, 0.0);
}

// A light below the plane: N.L < 0, so no shadow ray, and the tree says why; C = 0.15 + 0.2.
TEST(Inspect, ALightTheSurfaceFacesAwayFromSaysWhyNoShadowRay) {
    const RenderScene scene =
        test::compile(worked_example_1("", "#light_point 1 1 1  5 -5 5  0.01 0.02 0.03"));
    const PixelTree tree = worked_tree(scene);
    const InspectLight& l = tree.rays.at(0).lights.at(0);
    EXPECT_NEAR(l.n_dot_l, -5.0 / std::sqrt(30.0), 1e-12);
    EXPECT_EQ(l.shadow_ray_count, 0u);
    EXPECT_NE(l.no_shadow_ray.find("faces away from the light (N.L <= 0)"), std::string::npos)
        << l.no_shadow_ray;
    EXPECT_VEC_NEAR(tree.pixel, Vec3(0.35), 1e-12);
    const std::string text = inspect_text(tree, scene, {});
    EXPECT_NE(text.find("no shadow ray: the surface faces away from the light (N.L <= 0)"),
              std::string::npos)
        << text;
    test::JsonValue v;
    std::string why;
    ASSERT_TRUE(test::parse_strict_json(inspect_json(tree, scene, {}), &v, &why)) << why;
    EXPECT_EQ(v["rays"].array.at(0)["terms"]["lights"].array.at(0)["no_shadow_ray"].string,
              l.no_shadow_ray);
    // Lit, the field is null.
    const RenderScene lit = test::compile(worked_example_1());
    ASSERT_TRUE(test::parse_strict_json(inspect_json(worked_tree(lit), lit, {}), &v, &why));
    EXPECT_EQ(v["rays"].array.at(0)["terms"]["lights"].array.at(0)["no_shadow_ray"].type,
              test::JsonValue::Type::Null);
}

// Between two mirrors y = 0 and y = 2 a ray bounces until the depth ends it: --inspect-depth 2
// keeps the camera ray and its reflection, and counts the 3 rays below as left out (depth 5);
// the colour they brought back stays. --inspect-light 1 keeps light 1's terms only.
TEST(Inspect, FiltersLeaveOutDeepRaysAndOtherLights) {
    const RenderScene scene = test::compile(
        "#camera 0 1 0  1 -0.5 0  0 1 0  0.5\n"
        "#light_point 1 1 1  0 1 1  1 0 0\n#light_point 0.5 0.5 0.5  0 1 -1  1 0 0\n"
        "#material 0 0 0  0 0 0  .2 .2 .2  .5 .5 .5  10  0 0 0  1  -1 !!\n"
        "#vertex -100 0 -100 0 0 0 0 0\n#vertex -100 0 100 0 0 0 0 0\n"
        "#vertex 100 0 100 0 0 0 0 0\n#vertex 100 0 -100 0 0 0 0 0\n"
        "#vertex -100 2 -100 0 0 0 0 0\n#vertex -100 2 100 0 0 0 0 0\n"
        "#vertex 100 2 100 0 0 0 0 0\n#vertex 100 2 -100 0 0 0 0 0\n"
        "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n"
        "#shape_triangle 0 4 5 6\n#shape_triangle 0 4 6 7\n");
    const PixelTree tree = worked_tree(scene);
    ASSERT_EQ(tree.rays.size(), 5u);  // the camera ray and 4 reflections
    const PixelTree cut = filter_tree(tree, {2, -1});
    ASSERT_EQ(cut.rays.size(), 2u);
    EXPECT_EQ(cut.rays_left_out, 3u);
    EXPECT_EQ(cut.rays[1].parent, 0);
    EXPECT_EQ(cut.rays[0].children, std::vector<int>{1});
    EXPECT_TRUE(cut.rays[1].children.empty());
    ASSERT_EQ(cut.rays[1].left_out.size(), 1u);
    const InspectRay::NotRecorded& n = cut.rays[1].left_out[0];
    EXPECT_EQ(n.rays, 3u);
    EXPECT_EQ(n.depth, 3);
    EXPECT_TRUE(same_bits(n.color, tree.rays[2].color));
    EXPECT_TRUE(same_bits(cut.rays[1].reflected, tree.rays[1].reflected));
    const std::string text = inspect_text(cut, scene, {});
    EXPECT_NE(text.find("left out (--inspect-depth 2): reflected ray, depth 3, path weight (0.25 "
                        "0.25 0.25), with the 2 rays below it"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("3 rays deeper than level 2 left out (--inspect-depth 2"),
              std::string::npos);
    EXPECT_EQ(text.find("ray, depth 3, path weight (0.25 0.25 0.25): from"),
              std::string::npos);  // no ray line below level 2
    test::JsonValue v;
    std::string why;
    ASSERT_TRUE(test::parse_strict_json(inspect_json(cut, scene, {}), &v, &why)) << why;
    EXPECT_EQ(v["rays"].array.size(), 2u);
    EXPECT_EQ(v["filter"]["rays_left_out"].number, 3.0);
    EXPECT_EQ(v["rays"].array[1]["left_out"].array.at(0)["rays"].number, 3.0);

    const PixelTree one = filter_tree(tree, {0, 1});
    ASSERT_EQ(one.rays.size(), 5u);
    for (const InspectRay& r : one.rays) {
        ASSERT_EQ(r.lights.size(), 1u);
        EXPECT_EQ(r.lights[0].light, 1);
        EXPECT_EQ(r.lights_left_out, 1u);
    }
    EXPECT_TRUE(same_bits(one.rays[0].lights[0].value, tree.rays[0].lights[1].value));
    EXPECT_NE(inspect_text(one, scene, {}).find("1 other light term left out (--inspect-light 1"),
              std::string::npos);
}

// A V3 light (spec §13.9) in shadow, with worked example 3's colours (A_l 0.5, D_l (1 0.5 1),
// S_l (0.2 0.4 0.6)): its ambient term is added (never shadowed), its diffuse and specular
// terms are kept as §13.10's table gives them, and it adds nothing else.
TEST(Inspect, AV3LightInShadowKeepsItsTerms) {
    RenderScene scene = test::compile(worked_example_1("#shape_sphere 0  4 2.5 5.5  0.4\n"));
    Light& l = scene.lights.at(0);
    l.ambient = Vec3(0.5);
    l.diffuse = Vec3(1, 0.5, 1);
    l.specular = Vec3(0.2, 0.4, 0.6);
    ASSERT_FALSE(l.one_colour());
    const PixelTree tree = worked_tree(scene);
    const InspectLight& t = tree.rays.at(0).lights.at(0);
    EXPECT_EQ(t.shadow, Vec3(0.0));
    EXPECT_TRUE(t.terms_known);
    EXPECT_VEC_NEAR(t.ambient_term, Vec3(0.147125), 1e-6);
    EXPECT_VEC_NEAR(t.diffuse_term, Vec3(0.089537, 0.044769, 0.447686), 1e-6);
    EXPECT_VEC_NEAR(t.specular_term, Vec3(0.025479, 0.050958, 0.076438), 1e-6);
    EXPECT_EQ(t.value, Vec3(0.0));
    EXPECT_TRUE(same_bits(sum_of_terms(tree, 0), tree.color));
}

}  // namespace
}  // namespace rt
