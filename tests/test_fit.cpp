// The diagnosis's global fits (rt/image/fit.h): each names the change that made a mistaken image
// from its reference, with its parameter, and a correct image gets none. The mistaken images
// are made here from a continuous pattern and the formulas of the mistakes, not by apply_fit().
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>

#include "rt/image/fit.h"

namespace rt {
namespace fit_test {

constexpr int kW = 80, kH = 60;

// A smooth pattern with detail everywhere (so a zoom or flip changes every region), no symmetry,
// distinct channels, values in [0, 1.2] (some clamped); (u, v) in [-1, 1] from the centre.
Vec3 pattern(double u, double v) {
    const double r = std::hypot(u - 0.3, v + 0.2);
    return {0.6 + 0.6 * std::sin(6 * r), 0.5 + 0.4 * std::cos(4 * u + 1.0) * std::sin(3 * v),
            0.3 + 0.3 * (u + 1) * (v + 1) / 2};
}

// The image of `f` at the pixel centres, (u, v) in [-1, 1] times `zoom` (< 1: magnified).
Image image_of(const std::function<Vec3(double, double)>& f, double zoom = 1.0) {
    Image im(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double u = (2 * (x + 0.5) / kW - 1) * zoom, v = (1 - 2 * (y + 0.5) / kH) * zoom;
            im.set(x, y, f(u, v));
        }
    return im;
}

// As a student's 8-bit file holds it, read back (the bytes / 255).
Image as_file(const Image& im) {
    Image out = im;
    for (double& c : out.rgb) c = to_byte(c) / 255.0;
    return out;
}

FitResult best(const std::vector<FitResult>& fits) {
    if (fits.empty()) throw std::runtime_error("no fit");
    return fits.front();
}

TEST(Fit, ACorrectImageGetsNoFit) {
    const Image ref = image_of(pattern);
    EXPECT_TRUE(fit_global(ref, as_file(ref)).empty());
    EXPECT_EQ(mean_squared_bytes(ref, as_file(ref)), 0.0);
}

TEST(Fit, GammaIsNamedWithItsExponent) {
    const Image ref = image_of(pattern);
    const Image student = as_file(image_of([](double u, double v) {
        return glm::pow(glm::clamp(pattern(u, v), 0.0, 1.0), Vec3(1 / 2.2));
    }));
    const FitResult f = best(fit_global(ref, student));
    EXPECT_EQ(f.name, "gamma");
    EXPECT_NEAR(f.fit.value, 2.2, 0.05);
    EXPECT_GT(f.explained(), 0.99);
}

TEST(Fit, BrightnessIsNamedWithItsScale) {
    const Image ref = image_of(pattern);
    const Image student = as_file(image_of([](double u, double v) { return 0.5 * pattern(u, v); }));
    const FitResult f = best(fit_global(ref, student));
    EXPECT_EQ(f.name, "brightness");
    EXPECT_NEAR(f.fit.value, 0.5, 0.01);
    EXPECT_GT(f.explained(), 0.99);
}

TEST(Fit, FlipsAndChannelSwapsAreExact) {
    const Image ref = image_of(pattern);
    const Image flipped = as_file(image_of([](double u, double v) { return pattern(u, -v); }));
    const FitResult f = best(fit_global(ref, flipped));
    EXPECT_EQ(f.name, "flip-vertical");
    EXPECT_EQ(f.error_after, 0.0);
    const Image mirrored = as_file(image_of([](double u, double v) { return pattern(-u, v); }));
    EXPECT_EQ(best(fit_global(ref, mirrored)).name, "flip-horizontal");
    const Image bgr = as_file(image_of([](double u, double v) {
        const Vec3 c = pattern(u, v);
        return Vec3(c.z, c.y, c.x);
    }));
    const FitResult s = best(fit_global(ref, bgr));
    EXPECT_EQ(s.name, "bgr");
    EXPECT_EQ(s.error_after, 0.0);
    EXPECT_EQ(s.detail, "red, green, blue written as bgr");
}

// The camera's half-height angle read as the full angle: the student's view is narrower by
// tan(ha / 2) / tan(ha), so the picture is magnified about its centre.
TEST(Fit, AZoomFindsTheCameraAngleMistake) {
    const double ha = 0.5, aspect = double(kW) / kH;
    const double k = std::tan(ha) / std::tan(ha / 2);
    const Image ref = image_of(pattern);
    const Image student = as_file(image_of(pattern, 1 / k));
    const FitResult f = best(fit_global(ref, student));
    EXPECT_EQ(f.name, "zoom");
    EXPECT_NEAR(f.fit.value, k, 0.02 * k);
    EXPECT_GT(f.explained(), 0.8);
    EXPECT_EQ(zoom_mistake(f.fit.value, ha, aspect), "full-angle");
    EXPECT_EQ(zoom_mistake(aspect * 1.01, ha, aspect), "angle-on-width");
    EXPECT_EQ(zoom_mistake(1.7, ha, aspect), "");
}

TEST(Fit, ImagesOfDifferentSizesAreRefused) {
    EXPECT_THROW(fit_global(Image(4, 3), Image(3, 4)), std::invalid_argument);
}

}  // namespace fit_test
}  // namespace rt
