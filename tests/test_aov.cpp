// AOVs (rt/render/aov.h): the first hit's depth, normal and albedo against the analytic sphere,
// misses, the normal facing the ray, the same camera rays as the render (jitter, progressive
// sequence, lens), samples and variance, and the EXR file that carries them.
#include <cmath>
#include <filesystem>
#include <set>

#include "rt/image/exr.h"
#include "rt/render/aov.h"
#include "test_util.h"

namespace rt {
namespace {

const char* kSphere =
    "#camera 0 0 5  0 0 -1  0 1 0  0.5\n#ambient .2 .2 .2\n#light_point 1 1 1  2 2 2  1 0 0\n"
    "#material 0 0 0  .2 .2 .2  .8 .3 .4  .5 .5 .5  20  0 0 0  1  -1 !!\n"
    "#shape_sphere 0  0 0 0  1\n";

RenderSettings small(int w, int h, int threads = 2) {
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.threads = threads;
    return s;
}

Vec3 at3(const std::vector<double>& v, int w, int x, int y) {
    const size_t i = (static_cast<size_t>(y) * w + x) * 3;
    return {v[i], v[i + 1], v[i + 2]};
}

TEST(Aov, DepthNormalAndAlbedoOfASphereAreAnalytic) {
    const RenderScene scene = test::compile(kSphere);
    const RenderSettings s = small(40, 30);
    const RenderPlan plan = make_render_plan(scene, s);
    const FirstHitAovs a = render_first_hit_aovs(scene, plan, s, std::vector<uint32_t>(1200, 1));
    ASSERT_EQ(a.width, 40);
    const Camera cam = make_camera(scene, 40, 30);
    int hits = 0;
    for (const auto& [x, y] : {std::pair{20, 15}, {17, 12}, {23, 17}, {24, 14}}) {
        // |o + t d| = 1 for the unit sphere at the origin, d unit: the nearer root.
        const Ray r = cam.generate(x, y, 0.5, 0.5);
        const double b = glm::dot(r.o, r.d), c = glm::dot(r.o, r.o) - 1.0;
        ASSERT_GT(b * b - c, 0.0) << x << "," << y;
        const double t = -b - std::sqrt(b * b - c);
        EXPECT_NEAR(a.depth[static_cast<size_t>(y) * 40 + x], t, 1e-9);
        EXPECT_GT(t, 3.9);
        EXPECT_VEC_NEAR(at3(a.normal, 40, x, y), r.o + t * r.d, 1e-9);  // outward, unit
        EXPECT_VEC_NEAR(at3(a.albedo, 40, x, y), Vec3(0.8, 0.3, 0.4), 1e-15);
        ++hits;
    }
    EXPECT_EQ(hits, 4);
    // A pixel that sees nothing: albedo and normal 0, depth +infinity.
    EXPECT_EQ(at3(a.albedo, 40, 0, 0), Vec3(0.0));
    EXPECT_EQ(at3(a.normal, 40, 0, 0), Vec3(0.0));
    EXPECT_EQ(a.depth[0], kInf);
    // The same for any thread count.
    const RenderSettings one = small(40, 30, 1);
    const FirstHitAovs b = render_first_hit_aovs(scene, make_render_plan(scene, one), one,
                                                 std::vector<uint32_t>(1200, 1));
    EXPECT_EQ(a.albedo, b.albedo);
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.depth, b.depth);
}

TEST(Aov, TheNormalFacesTheRay) {
    // From inside a sphere of radius 3 every ray hits its inside at distance 3, where the outward
    // normal points along the ray: the shading turns it toward the camera (spec §5).
    const RenderScene scene = test::compile(
        "#camera 0 0 0  0 0 -1  0 1 0  0.6\n"
        "#material 0 0 0  .2 .2 .2  .1 .6 .9  0 0 0  1  0 0 0  1  -1 !!\n"
        "#shape_sphere 0  0 0 0  3\n");
    const RenderSettings s = small(12, 9);
    const FirstHitAovs a =
        render_first_hit_aovs(scene, make_render_plan(scene, s), s, std::vector<uint32_t>(108, 1));
    const Camera cam = make_camera(scene, 12, 9);
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 12; ++x) {
            EXPECT_NEAR(a.depth[static_cast<size_t>(y) * 12 + x], 3.0, 1e-9);
            EXPECT_VEC_NEAR(at3(a.normal, 12, x, y), -cam.generate(x, y, 0.5, 0.5).d, 1e-9);
            EXPECT_VEC_NEAR(at3(a.albedo, 12, x, y), Vec3(0.1, 0.6, 0.9), 1e-15);
        }
}

// scenes/textures.ray lit by ambient light alone, with K_A = K_D, ambient 1 and a black
// background: every sample's colour is its first hit's albedo (K_D times the texel), so the
// render's mean is the albedo AOV exactly when both trace the same camera rays.
RenderScene albedo_scene() {
    Diagnostics diag;
    RenderScene scene =
        compile_scene(parse_scene_file(RT_SOURCE_DIR "/scenes/textures.ray", diag, {}));
    for (Material& m : scene.materials) {
        m.ambient = m.diffuse;
        m.emissive = m.specular = m.transparent = Vec3(0.0);
    }
    scene.lights.clear();
    scene.ambient = Vec3(1.0);
    scene.background = Vec3(0.0);
    return scene;
}

TEST(Aov, TheAlbedoPassTracesTheRendersCameraRays) {
    const RenderScene scene = albedo_scene();
    struct Case {
        const char* what;
        int spp1, spp2;  // two render_samples() calls (0: none)
        bool progressive;
        double aperture;
    };
    std::vector<double> centre_albedo;
    for (const Case& c : {Case{"1 spp: pixel centres", 1, 0, false, 0.0},
                          Case{"5 spp: jittered strata", 5, 0, false, 0.0},
                          Case{"progressive: 1 + 3 samples", 1, 3, true, 0.0},
                          Case{"3 spp through a lens", 3, 0, false, 0.2},
                          Case{"progressive through a lens", 2, 2, true, 0.2}}) {
        SCOPED_TRACE(c.what);
        RenderSettings s = small(48, 36);
        s.seed = 7;
        s.centre_first_sample = !c.progressive;
        s.aperture = c.aperture;
        const RenderPlan plan = make_render_plan(scene, s);
        RenderState state;
        render_samples(state, scene, plan, s, c.spp1);
        if (c.spp2) render_samples(state, scene, plan, s, c.spp2);
        const FirstHitAovs a = render_first_hit_aovs(scene, plan, s, state.samples);
        const Image img = state.image();
        ASSERT_EQ(a.albedo.size(), img.rgb.size());
        double max_diff = 0.0;
        std::set<double> values;
        for (size_t i = 0; i < img.rgb.size(); ++i) {
            max_diff = std::max(max_diff, std::abs(a.albedo[i] - img.rgb[i]));
            values.insert(a.albedo[i]);
        }
        EXPECT_LT(max_diff, 1e-12);
        EXPECT_GT(values.size(), 200u);  // textures and edges: many values, not a few flat ones
        if (centre_albedo.empty()) {
            centre_albedo = a.albedo;
        } else {
            double diff = 0;  // jitter moves the samples off the centres
            for (size_t i = 0; i < a.albedo.size(); ++i)
                diff += std::abs(a.albedo[i] - centre_albedo[i]);
            EXPECT_GT(diff, 1.0);
        }
    }
}

TEST(Aov, SampleVarianceIsUnbiasedAndZeroBelowTwoSamples) {
    RenderState state;
    state.reset(3, 1);
    // Pixel 0: samples 1, 2, 4 in red, 5, 5, 5 in green; pixel 1: one sample; pixel 2: none.
    state.samples = {3, 1, 0};
    state.sum = {7, 15, 0, 2, 2, 2, 0, 0, 0};
    state.sum_sq = {21, 75, 0, 4, 4, 4, 0, 0, 0};
    const std::vector<double> v = sample_variance(state);
    ASSERT_EQ(v.size(), 9u);
    EXPECT_NEAR(v[0], (21 - 49.0 / 3) / 2, 1e-12);  // 7/3: divided by n - 1
    EXPECT_EQ(v[1], 0.0);
    EXPECT_EQ(v[2], 0.0);
    for (size_t i = 3; i < 9; ++i) EXPECT_EQ(v[i], 0.0);
}

TEST(Aov, ChannelsHaveTheirNamesTypesAndValues) {
    const RenderScene scene = test::compile(kSphere);
    RenderSettings s = small(20, 15);
    s.light_radius = 0.5;  // soft shadows: samples differ, the variance is not 0
    const RenderPlan plan = make_render_plan(scene, s);
    RenderState state;
    render_samples(state, scene, plan, s, 4);
    AovSet all;
    for (const char* n : {"albedo", "normal", "depth", "samples", "variance"})
        ASSERT_TRUE(add_aov(n, &all)) << n;
    EXPECT_FALSE(add_aov("Albedo", &all));
    EXPECT_FALSE(add_aov("", &all));
    EXPECT_EQ(aov_list(all), "albedo,normal,depth,samples,variance");
    const std::vector<ExrChannel> ch = aov_channels(all, state, scene, plan, s);
    std::vector<std::string> names;
    std::vector<ExrPixel> types;
    for (const ExrChannel& c : ch) {
        names.push_back(c.name);
        types.push_back(c.type);
        EXPECT_EQ(c.values.size(), 300u);
    }
    EXPECT_EQ(names, (std::vector<std::string>{"Albedo.R", "Albedo.G", "Albedo.B", "Ns.X", "Ns.Y",
                                               "Ns.Z", "depth.Z", "Samples.N", "Variance.R",
                                               "Variance.G", "Variance.B"}));
    using P = ExrPixel;
    EXPECT_EQ(types, (std::vector<P>{P::Half, P::Half, P::Half, P::Half, P::Half, P::Half, P::Float,
                                     P::Uint, P::Half, P::Half, P::Half}));
    const FirstHitAovs a = render_first_hit_aovs(scene, plan, s, state.samples);
    const std::vector<double> var = sample_variance(state);
    double max_var = 0;
    for (size_t p = 0; p < 300; ++p) {
        EXPECT_EQ(ch[0].values[p], a.albedo[p * 3]);
        EXPECT_EQ(ch[5].values[p], a.normal[p * 3 + 2]);
        EXPECT_EQ(ch[6].values[p], a.depth[p]);
        EXPECT_EQ(ch[7].values[p], 4.0);  // spp
        EXPECT_EQ(ch[9].values[p], var[p * 3 + 1]);
        max_var = std::max(max_var, ch[8].values[p]);
    }
    EXPECT_GT(max_var, 1e-4);
    // Only what is asked for; a deterministic single sample has no variance.
    RenderState one;
    render_samples(one, scene, plan, s, 1);
    AovSet some;
    some.variance = some.depth = true;
    const std::vector<ExrChannel> few = aov_channels(some, one, scene, plan, s);
    ASSERT_EQ(few.size(), 4u);
    EXPECT_EQ(few[0].name, "depth.Z");
    for (const ExrChannel& c : few) {
        if (c.name == "depth.Z") continue;
        for (double v : c.values) EXPECT_EQ(v, 0.0);
    }
    EXPECT_TRUE(aov_channels({}, one, scene, plan, s).empty());
}

TEST(Aov, TheExrFileEqualsThePfmAndCarriesTheAovs) {
    const RenderScene scene = test::compile(kSphere);
    const RenderSettings s = small(24, 18);
    const RenderPlan plan = make_render_plan(scene, s);
    RenderState state;
    render_samples(state, scene, plan, s, 2);
    AovSet all;
    all.albedo = all.normal = all.depth = all.samples = all.variance = true;
    const std::vector<ExrChannel> ch = aov_channels(all, state, scene, plan, s);
    const std::string dir = ::testing::TempDir();
    save_image(state.image(), dir + "/rt_aov.pfm");
    save_exr(state.image(), ch, true, dir + "/rt_aov.exr");
    save_exr(state.image(), ch, false, dir + "/rt_aov_half.exr");
    const ExrImage e = load_exr(dir + "/rt_aov.exr");
    EXPECT_EQ(e.rgb().rgb, load_pfm(dir + "/rt_aov.pfm").rgb);
    EXPECT_EQ(e.channels.size(), 14u);
    for (const ExrChannel& c : ch) {
        const ExrChannel* back = e.find(c.name);
        ASSERT_TRUE(back) << c.name;
        EXPECT_EQ(back->type, c.type == ExrPixel::Half ? ExrPixel::Float : c.type) << c.name;
        for (size_t p = 0; p < c.values.size(); ++p) {
            ASSERT_EQ(back->values[p], static_cast<double>(static_cast<float>(c.values[p])))
                << c.name << " pixel " << p;
        }
    }
    EXPECT_EQ(e.find("depth.Z")->values[0], kInf);  // the corner sees nothing
    const ExrImage h = load_exr(dir + "/rt_aov_half.exr");
    EXPECT_EQ(h.find("R")->type, ExrPixel::Half);
    EXPECT_EQ(h.find("Albedo.G")->type, ExrPixel::Half);
    EXPECT_EQ(h.find("depth.Z")->type, ExrPixel::Float);  // distances keep float's precision
    EXPECT_EQ(h.find("Samples.N")->type, ExrPixel::Uint);
    EXPECT_EQ(h.find("Samples.N")->values, std::vector<double>(24 * 18, 2.0));
    EXPECT_NEAR(h.find("Albedo.G")->values[9 * 24 + 12], 0.3, 1e-3);
    for (const char* f : {"/rt_aov.pfm", "/rt_aov.exr", "/rt_aov_half.exr"})
        std::filesystem::remove(dir + f);
}

}  // namespace
}  // namespace rt
