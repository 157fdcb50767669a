// render_samples(): pixel centres at 1 spp, identical images for any thread count, stratified
// supersampling, stop requests, plans of another size refused, sphere lights' estimates.
#include <chrono>
#include <stdexcept>
#include <thread>

#include "test_util.h"

namespace rt {
namespace {

const char* kScene =
    "#camera 0 0 5  0 0 -1  0 1 0  0.5\n#light_point 1 1 1  2 2 2  1 0 0\n#ambient .2 .2 .2\n"
    "#material 0 0 0  .2 .2 .2  .8 .3 .3  .5 .5 .5  20  0 0 0  1  -1 !!\n"
    "#material 0 0 0  .2 .2 .2  .3 .3 .8  0 0 0  1  .5 .5 .5  1.3  -1 !!\n"
    "#shape_sphere 0  -0.6 0 0  0.5\n#shape_box 1  0.6 0 0  0.8 0.8 0.8\n"
    "#shape_cone 0  0 -0.8 0  0.3 0.6\n";

Image render_with(int threads, int spp, int w = 64, int h = 48) {
    const RenderScene s = test::compile(kScene);
    RenderSettings settings;
    settings.width = w;
    settings.height = h;
    settings.threads = threads;
    RenderState state;
    render_samples(state, s, make_render_plan(s, settings), settings, spp);
    return state.image();
}

TEST(Render, OneSampleIsThePixelCentre) {
    const RenderScene s = test::compile(kScene);
    const Image img = render_with(1, 1);
    const Camera cam = make_camera(s, 64, 48);
    for (int y = 0; y < 48; y += 7)
        for (int x = 0; x < 64; x += 5)
            EXPECT_VEC_NEAR(img.at(x, y), test::shade(s, cam.generate(x, y, 0.5, 0.5)), 1e-6);
}

TEST(Render, APlanForAnotherSizeIsRefused) {
    const RenderScene s = test::compile(kScene);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    const RenderPlan plan = make_render_plan(s, settings);
    settings.width = 32;  // the plan's camera maps 64 x 48 pixels
    RenderState state;
    EXPECT_THROW(render_samples(state, s, plan, settings, 1), std::invalid_argument);
    EXPECT_THROW(render_coarse(s, plan, settings, 4), std::invalid_argument);
    EXPECT_EQ(state.passes, 0);
}

// Two facing mirrors, emissive 1 and reflecting all: every level of a ray adds 1. At kMaxDepth
// the recursion fits the worker threads' stacks, specialized or generic (the largest frames) and
// under AddressSanitizer too; one level more is refused before anything is traced (30000 levels
// overflowed the stack).
TEST(Render, FacingMirrorsRenderAtTheMaximumDepthAndNoDeeper) {
    const RenderScene s = test::compile(
        "#camera 0 0 0  0 0 -1  0 1 0  0.1\n"
        "#material 1 1 1  0 0 0  0 0 0  1 1 1  1  0 0 0  1  -1 !!\n"
        "#shape_box 0  0 0 -1  1000 1000 0.1\n#shape_box 0  0 0 1  1000 1000 0.1\n");
    RenderSettings settings;
    settings.width = 32, settings.height = 16, settings.threads = 2;  // two tiles, two threads
    settings.max_depth = kMaxDepth, settings.cutoff = 0;
    for (const bool specialize : {true, false}) {
        settings.specialize = specialize;
        RenderState state;
        render_samples(state, s, make_render_plan(s, settings), settings, 1);
        EXPECT_EQ(state.image().at(0, 0), Vec3(kMaxDepth)) << specialize;
        EXPECT_EQ(state.image().at(31, 15), Vec3(kMaxDepth)) << specialize;
        EXPECT_EQ(state.rays.reflected, 32u * 16u * (kMaxDepth - 1)) << specialize;
    }
    settings.max_depth = kMaxDepth + 1;
    const RenderPlan plan = make_render_plan(s, settings);
    RenderState state;
    EXPECT_THROW(render_samples(state, s, plan, settings, 1), std::invalid_argument);
    EXPECT_THROW(render_coarse(s, plan, settings, 4), std::invalid_argument);
    RayCounters rays;
    EXPECT_THROW(
        trace_ray(s, plan, settings, {{0, 0, 0}, {0, 0, -1}}, kMaxDepth + 1, Vec3(1.0), rays),
        std::invalid_argument);
    EXPECT_EQ(rays.total(), 0u);
}

TEST(Render, SameImageForAnyThreadCount) {
    for (int spp : {1, 4}) {
        const Image a = render_with(1, spp), b = render_with(2, spp), c = render_with(5, spp);
        EXPECT_EQ(a.rgb, b.rgb);
        EXPECT_EQ(a.rgb, c.rgb);
    }
}

TEST(Render, SupersamplingAveragesAndDiffersFromCentre) {
    const Image one = render_with(2, 1), many = render_with(2, 16);
    double diff = 0;
    for (size_t i = 0; i < one.rgb.size(); ++i) diff += std::abs(one.rgb[i] - many.rgb[i]);
    EXPECT_GT(diff, 0.0);  // edges are anti-aliased
    // Flat background regions stay exactly the same.
    EXPECT_EQ(one.at(0, 0), many.at(0, 0));  // NOLINT
}

TEST(Render, StopLeavesTheStateUnchanged) {
    const RenderScene s = test::compile(kScene);
    RenderSettings settings;
    settings.width = 32;
    settings.height = 32;
    RenderState state;
    std::atomic<bool> stop{true};
    EXPECT_FALSE(render_samples(state, s, make_render_plan(s, settings), settings, 1, {}, &stop));
    EXPECT_EQ(state.samples[0], 0u);
    EXPECT_TRUE(render_samples(state, s, make_render_plan(s, settings), settings, 2));
    EXPECT_EQ(state.samples[0], 2u);
    EXPECT_GT(state.rays.camera, 0u);
}

TEST(Render, StopRequestedDuringARenderEndsIt) {
    // A render far too long to finish (4096 samples per pixel) is stopped from another thread.
    const RenderScene s = test::compile(kScene);
    RenderSettings settings;
    settings.width = 200;
    settings.height = 200;
    RenderState state;
    std::atomic<bool> stop{false};
    std::thread stopper([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        stop = true;
    });
    EXPECT_FALSE(
        render_samples(state, s, make_render_plan(s, settings), settings, 4096, {}, &stop));
    stopper.join();
    EXPECT_EQ(state.samples[0], 0u);
}

// The first pass of a fresh state writes its sums in place, later passes go through the scratch
// buffer: a pass stopped half way leaves the sums exactly as they were in both cases, and a
// pixel that an adaptive pass skips keeps its sums although the scratch holds an earlier pass.
TEST(Render, StoppedPassesAndSkippedPixelsLeaveTheSumsExactlyAsTheyWere) {
    // (A background that is not black: every pixel's sum changes with a sample.)
    const RenderScene s = test::compile(std::string("#background .2 .3 .4\n") + kScene);
    RenderSettings settings;
    settings.width = 120;
    settings.height = 90;
    settings.threads = 2;
    settings.centre_first_sample = false;
    std::atomic<bool> stop{false};
    int calls = 0;
    // Stops once some rows are done (the progress callback runs on the worker threads).
    const ProgressFn stop_half_way = [&](int done, int total) {
        if (++calls > 1 && done > 0 && done < total) stop = true;
    };
    RenderState state;
    EXPECT_FALSE(render_samples(state, s, make_render_plan(s, settings), settings, 64,
                                stop_half_way, &stop));
    EXPECT_GT(calls, 1);
    EXPECT_EQ(state.passes, 0);
    for (double v : state.sum) ASSERT_EQ(v, 0.0);
    for (double v : state.sum_sq) ASSERT_EQ(v, 0.0);

    ASSERT_TRUE(render_samples(state, s, make_render_plan(s, settings), settings, 2));
    const std::vector<double> sum = state.sum, sum_sq = state.sum_sq;
    stop = false;
    calls = 0;
    EXPECT_FALSE(render_samples(state, s, make_render_plan(s, settings), settings, 64,
                                stop_half_way, &stop));
    EXPECT_EQ(state.sum, sum);
    EXPECT_EQ(state.sum_sq, sum_sq);
    EXPECT_EQ(state.passes, 1);

    // A full pass fills the scratch; then every other pixel is skipped.
    ASSERT_TRUE(render_samples(state, s, make_render_plan(s, settings), settings, 1));
    const std::vector<double> before = state.sum;
    state.active.assign(state.samples.size(), 0);
    for (size_t p = 0; p < state.active.size(); p += 2) state.active[p] = 1;
    ASSERT_TRUE(render_samples(state, s, make_render_plan(s, settings), settings, 1));
    size_t changed = 0;
    for (size_t p = 0; p < state.samples.size(); ++p) {
        EXPECT_EQ(state.samples[p], p % 2 == 0 ? 4u : 3u);
        for (size_t c = 0; c < 3; ++c) {
            if (p % 2 == 1) {
                EXPECT_EQ(state.sum[p * 3 + c], before[p * 3 + c]) << p;
            }
            changed += state.sum[p * 3 + c] != before[p * 3 + c];
        }
    }
    EXPECT_EQ(changed, 3 * ((state.samples.size() + 1) / 2));  // the active pixels got samples
}

TEST(Render, ImageIsFinite) { EXPECT_EQ(count_non_finite(render_with(2, 4, 80, 60)), 0u); }

// A floor in the penumbra of a V3 sphere light (centre (0, 10, 0), radius 2) past an opaque ball,
// seen from above through a narrow view (each pixel nearly one point).
RenderScene sphere_light_scene() {
    RenderScene s = test::compile(
        "#camera 1.2 4 0  0 -1 0  0 0 -1  0.05\n"
        "#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0 0 0  1  -1 !!\n"
        "#vertex -100 0 -100 0 0 0 0 0\n#vertex -100 0 100 0 0 0 0 0\n"
        "#vertex 100 0 100 0 0 0 0 0\n#vertex 100 0 -100 0 0 0 0 0\n"
        "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n#shape_sphere 0  0 5 0  1\n");
    Light l;
    l.kind = LightKind::Sphere;
    l.ambient = Vec3(0.0);
    l.diffuse = Vec3(1.0);
    l.specular = Vec3(0.5);
    l.position = Vec3(0, 10, 0);
    l.radius = 2.0;
    s.lights = {l};
    s.texture_all_terms = true;
    return s;
}

TEST(Render, SphereLightsSinglePassIsDeterministicAndProgressiveConverges) {
    const RenderScene scene = sphere_light_scene();
    RenderSettings s;
    s.width = s.height = 4;
    s.light_samples = 4096;
    s.threads = 1;
    RenderState single;
    test::render_samples(single, scene, s, 1);
    s.threads = 3;
    RenderState again;
    test::render_samples(again, scene, s, 1);
    EXPECT_EQ(single.sum, again.sum);  // the same points everywhere, whatever the threads
    // Progressive passes: one random point per sample; the mean converges to the single pass.
    s.light_samples = 64;
    s.centre_first_sample = false;
    RenderState progressive;
    for (int pass = 0; pass < 8; ++pass) test::render_samples(progressive, scene, s, 64);
    const Image ref = single.image(), mean = progressive.image();
    double lo = 1, hi = 0;
    for (size_t i = 0; i < ref.rgb.size(); ++i) {
        const double n = progressive.samples[i / 3];
        const double m = mean.rgb[i];
        const double se = std::sqrt(std::max(0.0, progressive.sum_sq[i] / n - m * m) / n);
        EXPECT_GT(se, 0.0) << i;  // random indeed
        EXPECT_NEAR(m, ref.rgb[i], 5 * se + 0.005) << i;
        lo = std::min(lo, ref.rgb[i]), hi = std::max(hi, ref.rgb[i]);
    }
    EXPECT_GT(lo, 0.05);  // the view is in the penumbra: not black and not fully lit
    EXPECT_LT(hi, 0.8);
}

}  // namespace
}  // namespace rt
