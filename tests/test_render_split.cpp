// A render split across processes: parts of any tiles and sample ranges merge into
// the very bits of the whole render, and a split that misses or repeats samples is refused.
#include <algorithm>
#include <cstring>

#include "test_util.h"

namespace rt {
namespace {

constexpr const char* kScene =
    "#camera 0 1 6  0 -0.2 -1  0 1 0  0.5\n"
    "#light_point 1 1 1  3 4 5  1 0 0\n#light_dir .4 .4 .5  -1 -1 -0.5\n"
    "#material 0 0 0  .1 .1 .1  .7 .2 .2  .6 .6 .6  40  0 0 0  1  -1 !!\n"
    "#material 0 0 0  .1 .1 .1  .1 .1 .1  .3 .3 .3  80  .8 .8 .8  1.5  -1 !glass!\n"
    "#shape_sphere 0  -1 0 0  1\n#shape_sphere 1  1.2 0.2 0.5  0.8\n"
    "#shape_box 0  0 -1.2 0  8 0.2 8\n";

RenderSettings settings(int spp_stochastic) {
    RenderSettings s;
    s.width = 37;  // not a multiple of the 16-pixel tiles
    s.height = 29;
    s.threads = 2;
    s.light_radius = spp_stochastic ? 0.3 : 0.0;
    return s;
}

RenderPart part(int x0, int y0, int x1, int y1, uint32_t first, uint32_t count, uint32_t total) {
    RenderPart p;
    p.x0 = x0, p.y0 = y0, p.x1 = x1, p.y1 = y1;
    p.first = first, p.count = count, p.total = total;
    return p;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(RenderSplit, AnySplitMergesIntoTheWholeRendersBits) {
    const RenderScene scene = test::compile(kScene);
    for (const bool stochastic : {false, true}) {
        const RenderSettings s = settings(stochastic);
        const RenderPlan plan = make_render_plan(scene, s);
        const uint32_t n = 6;  // not a power of two: two maximal blocks, [0, 4) and [4, 6)
        RenderState whole;
        render_samples(whole, scene, plan, s, static_cast<int>(n));
        const std::vector<std::vector<RenderPart>> splits = {
            {part(0, 0, 37, 29, 0, n, n)},                                // one part
            {part(0, 0, 20, 29, 0, n, n), part(20, 0, 37, 29, 0, n, n)},  // tiles
            {part(0, 0, 37, 29, 0, 1, n), part(0, 0, 37, 29, 1, 4, n),    // samples 0, 1..4,
             part(0, 0, 37, 29, 5, 1, n)},                                // 5
            {part(0, 0, 37, 10, 0, 3, n), part(0, 0, 37, 10, 3, 3, n),    // both at once
             part(0, 10, 11, 29, 0, n, n), part(11, 10, 37, 29, 0, 2, n),
             part(11, 10, 37, 29, 2, 4, n)},
        };
        for (size_t k = 0; k < splits.size(); ++k) {
            std::vector<RenderPart> parts = splits[k];
            std::vector<const RenderPart*> ptrs;
            for (RenderPart& p : parts) {
                ASSERT_TRUE(render_part(p, scene, plan, s));
                ptrs.push_back(&p);
            }
            const RenderState merged = merge_parts(ptrs, s.width, s.height, n);
            EXPECT_TRUE(same_bits(merged.image().rgb, whole.image().rgb))
                << "split " << k << (stochastic ? " with soft shadows" : "");
            EXPECT_TRUE(same_bits(merged.sum_sq, whole.sum_sq)) << "split " << k;
            EXPECT_EQ(merged.samples, whole.samples);
        }
    }
}

TEST(RenderSplit, ProgressivePassesSumAsOneCall) {
    // Passes of 1, 1, 2, 4 samples cover dyadic blocks: the same bits as 8 samples at once.
    const RenderScene scene = test::compile(kScene);
    RenderSettings s = settings(true);
    s.centre_first_sample = false;
    const RenderPlan plan = make_render_plan(scene, s);
    RenderState passes, once;
    for (int spp : {1, 1, 2, 4}) render_samples(passes, scene, plan, s, spp);
    render_samples(once, scene, plan, s, 8);
    EXPECT_TRUE(same_bits(passes.sum, once.sum));
}

TEST(RenderSplit, ProgressivePassesOfTilesAddAsTheWholePasses) {
    // The MPI mode's progressive run: each pass's tiles added to the state, ++passes.
    const RenderScene scene = test::compile(kScene);
    RenderSettings s = settings(true);
    s.centre_first_sample = false;
    const RenderPlan plan = make_render_plan(scene, s);
    RenderState whole, tiled;
    tiled.reset(s.width, s.height);
    uint32_t done = 0;
    for (uint32_t spp : {1u, 1u, 2u, 3u}) {  // the last pass is not a dyadic block
        render_samples(whole, scene, plan, s, static_cast<int>(spp));
        for (RenderPart p : {part(0, 0, 20, 29, done, spp, done + spp),
                             part(20, 0, 37, 29, done, spp, done + spp)}) {
            ASSERT_TRUE(render_part(p, scene, plan, s));
            add_part_samples(tiled, p);
        }
        ++tiled.passes;
        done += spp;
    }
    EXPECT_TRUE(same_bits(whole.sum, tiled.sum));
    EXPECT_TRUE(same_bits(whole.sum_sq, tiled.sum_sq));
    EXPECT_EQ(whole.samples, tiled.samples);
}

TEST(RenderSplit, TilesCoverTheImageOnceRowByRowAndMergeIntoTheWhole) {
    const std::vector<RenderPart> tiles = tile_parts(37, 29, 16, 16, 3, 2, 5);
    ASSERT_EQ(tiles.size(), 6u);  // 16 + 16 + 5 across, 16 + 13 down
    std::vector<int> covered(37 * 29, 0);
    for (size_t i = 0; i < tiles.size(); ++i) {
        const RenderPart& t = tiles[i];
        EXPECT_EQ(t.x0, 16 * static_cast<int>(i % 3));
        EXPECT_EQ(t.y0, 16 * static_cast<int>(i / 3));
        EXPECT_EQ(t.x1 - t.x0, i % 3 == 2 ? 5 : 16);
        EXPECT_EQ(t.y1 - t.y0, i / 3 == 1 ? 13 : 16);
        EXPECT_EQ(t.first, 3u);
        EXPECT_EQ(t.count, 2u);
        EXPECT_EQ(t.total, 5u);
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) ++covered[static_cast<size_t>(y * 37 + x)];
    }
    EXPECT_EQ(std::count(covered.begin(), covered.end(), 1), 37 * 29);
    EXPECT_TRUE(tile_parts(0, 29, 16, 16, 0, 1, 1).empty());
    EXPECT_EQ(tile_parts(37, 29, 64, 64, 0, 1, 1).size(), 1u);  // one tile, clipped to the image

    // Rendered, they are the whole render.
    const RenderScene scene = test::compile(kScene);
    const RenderSettings s = settings(true);
    const RenderPlan plan = make_render_plan(scene, s);
    RenderState whole;
    render_samples(whole, scene, plan, s, 3);
    std::vector<RenderPart> parts = tile_parts(s.width, s.height, 8, 8, 0, 3, 3);
    std::vector<const RenderPart*> ptrs;
    for (RenderPart& p : parts) {
        ASSERT_TRUE(render_part(p, scene, plan, s));
        ptrs.push_back(&p);
    }
    EXPECT_TRUE(same_bits(merge_parts(ptrs, s.width, s.height, 3).image().rgb, whole.image().rgb));
}

TEST(RenderSplit, MissingAndRepeatedSamplesAreRefused) {
    const RenderScene scene = test::compile(kScene);
    const RenderSettings s = settings(false);
    const RenderPlan plan = make_render_plan(scene, s);
    std::vector<RenderPart> parts = {part(0, 0, 37, 29, 0, 3, 4), part(0, 0, 20, 29, 3, 1, 4),
                                     part(0, 0, 37, 29, 2, 2, 4)};
    for (RenderPart& p : parts) ASSERT_TRUE(render_part(p, scene, plan, s));
    auto error = [&](std::vector<const RenderPart*> ptrs) {
        try {
            merge_parts(ptrs, s.width, s.height, 4);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(error({&parts[0], &parts[1]}),
              "pixel (20, 0): samples 3..3 are in no part");  // the second covers x < 20 only
    EXPECT_EQ(error({&parts[0], &parts[2]}),
              "pixel (0, 0): sample 2 is in two parts (part 0 and part 1)");
    EXPECT_EQ(error({}), "pixel (0, 0): samples 0..3 are in no part");
    RenderPart outside = part(30, 0, 40, 29, 0, 4, 4);
    EXPECT_THROW(render_part(outside, scene, plan, s), std::invalid_argument);
    RenderPart past = part(0, 0, 37, 29, 3, 2, 4);
    EXPECT_THROW(render_part(past, scene, plan, s), std::invalid_argument);
}

}  // namespace
}  // namespace rt
