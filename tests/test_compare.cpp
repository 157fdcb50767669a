// Comparing an image with the reference (rt/image/compare.h): equal images differ by nothing, a
// shift by one pixel is off at the edges unless each pixel is compared with its neighbourhood,
// 8-bit images compare as raytrace writes them, linear ones unclamped, and the heat map runs from
// black to red.
#include "rt/image/compare.h"
#include "test_util.h"

namespace rt {
namespace {

// A white disc on grey, w x h.
Image disc(int w, int h, double cx) {
    Image im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double dx = x + 0.5 - cx, dy = y + 0.5 - h / 2.0;
            im.set(x, y, dx * dx + dy * dy < 64 ? Vec3(1.0) : Vec3(0.25));
        }
    return im;
}

TEST(Compare, EqualImagesDifferByNothing) {
    const Image a = disc(32, 24, 16);
    const ImageComparison c = compare_images(a, a, {});
    EXPECT_EQ(c.mean(), 0.0);
    EXPECT_EQ(c.share_off, 0.0);
    EXPECT_EQ(c.max_diff, 0.0);
    EXPECT_EQ(c.error.size(), 32u * 24u);
}

TEST(Compare, AShiftIsOffAtTheEdgesUnlessNeighboursCount) {
    const Image a = disc(32, 24, 16), b = disc(32, 24, 17);
    const ImageComparison plain = compare_images(b, a, {});
    EXPECT_GT(plain.share_off, 0.01);
    EXPECT_NEAR(plain.max_diff, 191.0, 0.5);  // white against 0.25 grey: 255 - 64
    // The largest difference is on the disc's edge.
    const double dx = plain.max_x + 0.5 - 16.5, dy = plain.max_y + 0.5 - 12;
    EXPECT_NEAR(std::sqrt(dx * dx + dy * dy), 8.0, 1.5);
    CompareSettings n;
    n.neighbourhood = true;
    const ImageComparison near = compare_images(b, a, n);
    EXPECT_EQ(near.share_off, 0.0);
    EXPECT_EQ(near.max_diff, 0.0);
}

TEST(Compare, EightBitAndLinearImages) {
    Image a(1, 1), b(1, 1);
    a.set(0, 0, Vec3(1.5, 0.5, 0.0));  // over white: an 8-bit file holds 255
    b.set(0, 0, Vec3(1.0, 0.5, 0.0));
    EXPECT_EQ(compare_images(a, b, {}).max_diff, 0.0);
    CompareSettings linear;
    linear.linear = true;
    const ImageComparison c = compare_images(a, b, linear);
    EXPECT_NEAR(c.max_diff, 127.5, 1e-9);
    EXPECT_NEAR(c.mean_abs.x, 127.5, 1e-9);
    EXPECT_EQ(c.mean_abs.y, 0.0);
    // Off by more than the tolerance: 8 steps by default, 127.5 > 8.
    EXPECT_EQ(c.share_off, 1.0);
    linear.tolerance = 200;
    EXPECT_EQ(compare_images(a, b, linear).share_off, 0.0);
    EXPECT_THROW(compare_images(Image(2, 1), Image(1, 2), {}), std::invalid_argument);
    // Brighter than white, the difference is relative to the reference: 21 against 20 is off
    // by 1/20 of white, 12.75 steps, where 1.5 against a reference of 0.5 (not brighter than
    // white) is the full 255.
    Image hi(1, 1), ref(1, 1);
    hi.set(0, 0, Vec3(21.0, 1.5, 0.0));
    ref.set(0, 0, Vec3(20.0, 0.5, 0.0));
    linear.tolerance = 8;
    const ImageComparison r = compare_images(hi, ref, linear);
    EXPECT_NEAR(r.mean_abs.x, 12.75, 1e-9);
    EXPECT_NEAR(r.mean_abs.y, 255.0, 1e-9);
}

TEST(Compare, TheHeatMapRunsFromBlackToRed) {
    EXPECT_EQ(heat_colour(0.0), Vec3(0.0));
    EXPECT_EQ(heat_colour(1.0), Vec3(1.0, 0.0, 0.0));
    EXPECT_EQ(heat_colour(7.0), Vec3(1.0, 0.0, 0.0));
    const Image a = disc(32, 24, 16), b = disc(32, 24, 17);
    const ImageComparison c = compare_images(b, a, {});
    const Image h = heat_map(c);
    EXPECT_EQ(h.at(c.max_x, c.max_y), Vec3(1.0, 0.0, 0.0));  // the largest: red
    EXPECT_EQ(h.at(0, 0), Vec3(0.0));                        // equal: black
}

TEST(Compare, TheThresholdViewMarksThePixelsOff) {
    const Image a = disc(32, 24, 16), b = disc(32, 24, 17);
    const ImageComparison c = compare_images(b, a, {});
    const Image t = threshold_map(c, a, 8);
    int red = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            const bool off = c.error[static_cast<size_t>(y) * 32 + x] > 8;
            red += off;
            EXPECT_EQ(t.at(x, y).x == 1.0, off) << x << "," << y;
        }
    EXPECT_EQ(red, static_cast<int>(std::lround(c.share_off * 32 * 24)));
    EXPECT_GT(red, 0);
    // Elsewhere the reference, dimmed to grey: the disc brighter than the ground.
    EXPECT_GT(t.at(16, 12).y, t.at(1, 1).y);
}

}  // namespace
}  // namespace rt
