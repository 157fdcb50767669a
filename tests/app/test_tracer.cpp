// The viewer's trace (app/rayview/state/tracer.h): with threads, and pumped on the caller's thread
// as the web page's single-thread build runs it, tile by tile between frames: the same passes, the
// same image.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "rt/compile/compile.h"
#include "rt/format/parser.h"
#include "rt/render/render.h"
#include "state/tracer.h"

namespace rt::view {
namespace {

RenderScene lights_scene() {
    Diagnostics diag;
    const SceneDesc desc = parse_scene_file(RT_SOURCE_DIR "/scenes/lights.ray", diag);
    return compile_scene(desc);
}

RenderSettings small(int w, int h) {
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.threads = 2;
    return s;
}

TEST(Tracer, PumpedOnOneThreadItMakesTheThreadedImage) {
    const RenderScene scene = lights_scene();
    const RenderSettings settings = small(70, 45);  // tiles cut at the right and the bottom
    Image threaded, pumped;
    {
        Tracer t(true);
        t.restart(scene, settings, 4);
        for (int i = 0; i < 5000 && t.status().spp < 4; ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // no fifth pass
        ASSERT_EQ(t.status().spp, 4);
        ASSERT_TRUE(t.take_image(&threaded));
    }
    Tracer t(false);
    EXPECT_FALSE(t.threaded());
    t.restart(scene, settings, 4);
    EXPECT_FALSE(t.take_image(&pumped)) << "nothing is traced before the first pump";
    int pumps = 0;
    // A pump of no time renders one tile (the loop runs once): the count does not depend on the
    // machine's speed, as it did with 2 ms pumps, which a fast run finished in whole passes.
    for (; pumps < 10000 && t.status().spp < 4; ++pumps) t.pump(0.0);
    t.pump(0.0);  // the target is reached: nothing more
    EXPECT_EQ(t.status().spp, 4);
    EXPECT_GT(pumps, 4) << "a pass was not split over pumps";
    ASSERT_TRUE(t.take_image(&pumped));
    ASSERT_EQ(pumped.width, 70);
    EXPECT_EQ(pumped.rgb, threaded.rgb);  // bit for bit
}

TEST(Tracer, APumpReturnsAfterItsTimeAndAStopEndsTheTrace) {
    const RenderScene scene = lights_scene();
    Tracer t(false);
    t.restart(scene, small(640, 480), 0);
    t.pump(0.001);  // the coarse pass
    Image image;
    EXPECT_TRUE(t.take_image(&image));
    EXPECT_EQ(image.width, 640);  // blocks of 8 pixels, at the full size
    const auto start = std::chrono::steady_clock::now();
    t.pump(0.001);  // a few tiles of the first pass, not the whole pass
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(250));
    EXPECT_EQ(t.status().spp, 0);
    t.stop();
    t.pump(1.0);  // stopped: nothing more
    EXPECT_EQ(t.status().spp, 0);
    EXPECT_FALSE(t.take_image(&image));
}

// The reference mode (the comparison pane's): raytrace's image, with threads and pumped alike,
// bit for bit: the pixel centre first, then the jittered samples, in one pass of `spp`.
TEST(Tracer, TheReferenceIsRaytracesImage) {
    const RenderScene scene = lights_scene();
    const int spp = 2;
    RenderSettings settings = small(70, 45);
    settings.centre_first_sample = true;  // raytrace's
    RenderState state;
    ASSERT_TRUE(render_samples(state, scene, make_render_plan(scene, settings), settings, spp));
    const Image raytrace = state.image();
    for (bool threaded : {true, false}) {
        Tracer t(threaded);
        RenderSettings jittered = settings;
        jittered.centre_first_sample = false;  // what the viewer passes: the mode decides
        t.restart(scene, jittered, spp, 1e-3, true);
        Image image;
        int got_spp = -1;
        for (int i = 0; i < 10000 && got_spp < spp; ++i) {
            threaded ? std::this_thread::sleep_for(std::chrono::milliseconds(2)) : t.pump(0.0);
            if (!t.take_image(&image, &got_spp)) continue;
            EXPECT_TRUE(got_spp == 0 || got_spp == spp) << "one pass of every sample";
        }
        ASSERT_EQ(got_spp, spp) << (threaded ? "threaded" : "pumped");
        EXPECT_EQ(image.rgb, raytrace.rgb) << (threaded ? "threaded" : "pumped");
        if (!threaded) t.pump(0.0);  // done: no second pass
        EXPECT_EQ(t.status().spp, spp);
    }
}

}  // namespace
}  // namespace rt::view
