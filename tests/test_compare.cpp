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

// A smooth highlight on grey, w x h: a bump of the given sharpness (a specular exponent).
Image highlight(int w, int h, double exponent) {
    Image im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double dx = (x + 0.5 - w / 2.0) / w, dy = (y + 0.5 - h / 2.0) / h;
            const double c = std::max(0.0, 1.0 - std::sqrt(dx * dx + dy * dy));
            im.set(x, y, Vec3(0.2 + 0.7 * std::pow(c, exponent)));
        }
    return im;
}

TEST(Compare, TheNeighbourhoodExcusesOnlyTheReferencesEdges) {
    // A broader highlight (exponent 20 for 40) moves its flank outward and makes it less steep:
    // a pixel's neighbourhood alone would excuse most of it, no move of the reference fits the
    // whole 3x3 block, so every pixel off stays off.
    const Image ref = highlight(64, 48, 40), wrong = highlight(64, 48, 20);
    CompareSettings n;
    n.neighbourhood = true;
    const ImageComparison plain = compare_images(wrong, ref, {});
    const ImageComparison near = compare_images(wrong, ref, n);
    EXPECT_GT(plain.share_off, 0.02);
    EXPECT_EQ(near.share_off, plain.share_off);
    // A smooth ramp (5 steps over the block: no edge at tolerance 8): a pixel whose
    // neighbourhood holds a nearer value keeps its own difference.
    Image ramp(3, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) ramp.set(x, y, Vec3(0.5 + 0.01 * x));
    Image probe = ramp;
    probe.set(0, 1, Vec3(0.5 + 0.02 + 10.0 / 255.0));  // 15 steps off its own, 10 off (2,1)'s
    EXPECT_NEAR(compare_images(probe, ramp, n).max_diff, to_byte(probe.at(0, 1).x) - to_byte(0.5),
                1e-9);
}

TEST(Compare, TheLossyRuleTakesBlockNoiseButNotARegion) {
    // Noise of +-6 steps alternating pixel by pixel (a JPEG's ringing): off under the exact rule
    // at tolerance 4, averaged out by the lossy rule's 3x3 means.
    const Image ref = highlight(48, 32, 8);
    Image noisy = ref, region = ref;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 48; ++x) {
            const double s = ((x + y) % 2 ? 6.0 : -6.0) / 255.0;
            noisy.set(x, y, ref.at(x, y) + Vec3(s));
            // A region 12 steps darker (a missing light): a real mistake.
            if (x >= 8 && x < 24 && y >= 8 && y < 20)
                region.set(x, y, ref.at(x, y) - Vec3(12 / 255.0));
        }
    CompareSettings exact, lossy;
    exact.tolerance = lossy.tolerance = 4;
    lossy.lossy = true;
    EXPECT_GT(compare_images(noisy, ref, exact).share_off, 0.4);
    EXPECT_LT(compare_images(noisy, ref, lossy).max_diff, 4.0);
    const ImageComparison c = compare_images(region, ref, lossy);
    EXPECT_GT(c.share_off, 0.1);
    EXPECT_NEAR(c.max_diff, 12.0, 1.0);
}

TEST(Compare, TheSignedViewSaysBrighterOrDarker) {
    Image ref(2, 1), img(2, 1);
    ref.set(0, 0, Vec3(0.5));
    ref.set(1, 0, Vec3(0.5));
    img.set(0, 0, Vec3(0.5 + 30 / 255.0));  // added light
    img.set(1, 0, Vec3(0.5 - 30 / 255.0));  // missing light
    const ImageComparison c = compare_images(img, ref, {});
    ASSERT_EQ(c.signed_error.size(), 2u);
    EXPECT_NEAR(c.signed_error[0], 30.0, 1.0);
    EXPECT_NEAR(c.signed_error[1], -30.0, 1.0);
    const Image s = signed_map(c, 30);
    EXPECT_GT(s.at(0, 0).x, s.at(0, 0).z);  // orange: added light
    EXPECT_GT(s.at(1, 0).z, s.at(1, 0).x);  // blue: missing light
    EXPECT_EQ(signed_colour(0.0), Vec3(0.0));
    EXPECT_EQ(signed_colour(-5.0), signed_colour(-1.0));
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
