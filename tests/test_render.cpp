// render_samples(): pixel centres at 1 spp, identical images for any thread count, stratified
// supersampling, stop requests.
#include <chrono>
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
    render_samples(state, s, settings, spp);
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
    EXPECT_FALSE(render_samples(state, s, settings, 1, {}, &stop));
    EXPECT_EQ(state.samples[0], 0u);
    EXPECT_TRUE(render_samples(state, s, settings, 2));
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
    EXPECT_FALSE(render_samples(state, s, settings, 4096, {}, &stop));
    stopper.join();
    EXPECT_EQ(state.samples[0], 0u);
}

TEST(Render, ImageIsFinite) { EXPECT_EQ(count_non_finite(render_with(2, 4, 80, 60)), 0u); }

}  // namespace
}  // namespace rt
