// The diagnosis (rt/image/diagnose.h) over a stand-in renderer: each "mistake" changes a part of
// a pattern image the way a real one changes a render (a region brighter, a disc darker, a
// transfer curve), so the ranking, the pairs, the threshold and the render cache are tested
// without the ray tracer. The real catalogue is tested against an independent renderer's images
// (tests/diagnose).
#include <gtest/gtest.h>

#include <cmath>

#include "rt/image/diagnose.h"

namespace rt {
namespace diagnose_test {

constexpr int kW = 64, kH = 48;

Vec3 base(int x, int y) {
    return {0.2 + 0.5 * x / kW, 0.3 + 0.4 * y / kH, 0.5 + 0.2 * std::sin(0.3 * x + 0.2 * y)};
}

// The stand-in render: the pattern, with each named change on.
Image fake_render(const std::vector<std::string>& mistakes) {
    auto on = [&](const char* m) {
        return std::find(mistakes.begin(), mistakes.end(), m) != mistakes.end();
    };
    Image im(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            Vec3 c = base(x, y);
            const bool shadow = x > 8 && x < 30 && y > 28 && y < 44;
            const bool highlight = std::hypot(x - 45.0, y - 14.0) < 7;
            if (shadow && !on("no-shadows")) c *= 0.3;
            if (highlight && !on("no-specular")) c += Vec3(0.4);
            if (on("gamma")) c = glm::pow(glm::clamp(c, 0.0, 1.0), Vec3(1 / 2.2));
            im.set(x, y, c);
        }
    return im;
}

Image as_file(const Image& im) {
    Image out = im;
    for (double& c : out.rgb) c = to_byte(c) / 255.0;
    return out;
}

const std::vector<std::string> kCatalogue = {"no-shadows", "no-specular", "gamma", "no-ambient"};

TEST(Diagnose, TheMistakeThatMadeTheImageRanksFirst) {
    MutantRenders renders(fake_render);
    const Diagnosis d = diagnose(as_file(fake_render({"no-shadows"})), renders, kCatalogue, {});
    ASSERT_FALSE(d.ranked.empty()) << d.summary();
    EXPECT_EQ(d.ranked[0].name(), "no-shadows");
    EXPECT_GT(d.ranked[0].explained, 0.99);
    EXPECT_EQ(d.summary().rfind("1. no-shadows (explains 100%)", 0), 0u) << d.summary();
}

TEST(Diagnose, TwoMistakesAtOnceAreNamedTogether) {
    MutantRenders renders(fake_render);
    const Diagnosis d =
        diagnose(as_file(fake_render({"no-shadows", "no-specular"})), renders, kCatalogue, {});
    ASSERT_FALSE(d.ranked.empty()) << d.summary();
    EXPECT_EQ(d.ranked[0].mistakes.size(), 2u) << d.summary();
    EXPECT_GT(d.ranked[0].explained, 0.99);
    std::vector<std::string> names = d.ranked[0].mistakes;
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"no-shadows", "no-specular"}));
}

// A render mistake and an output transfer on top: the pair is the mutant with the fit.
TEST(Diagnose, AMistakeUnderAGammaIsFoundThroughTheFit) {
    MutantRenders renders(fake_render);
    Image student = fake_render({"no-specular"});
    for (double& c : student.rgb) c = std::pow(std::clamp(c, 0.0, 1.0), 1 / 2.2);
    const Diagnosis d = diagnose(as_file(student), renders, {"no-shadows", "no-specular"}, {});
    ASSERT_FALSE(d.ranked.empty()) << d.summary();
    EXPECT_EQ(d.ranked[0].mistakes, (std::vector<std::string>{"no-specular", "gamma"}))
        << d.summary();
    EXPECT_GT(d.ranked[0].explained, 0.98);
}

TEST(Diagnose, AnImageNoMistakeExplainsGetsNoGuess) {
    MutantRenders renders(fake_render);
    Image other(kW, kH);  // stripes that no change of the pattern makes
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) other.set(x, y, Vec3((x / 4) % 2 ? 0.9 : 0.05));
    const Diagnosis d = diagnose(as_file(other), renders, kCatalogue, {});
    EXPECT_TRUE(d.ranked.empty()) << d.summary();
    EXPECT_EQ(d.summary(), "none of the known mistakes explains this image");
}

TEST(Diagnose, ACorrectImageGetsNone) {
    MutantRenders renders(fake_render);
    const Diagnosis d = diagnose(as_file(fake_render({})), renders, kCatalogue, {});
    EXPECT_TRUE(d.ranked.empty());
    EXPECT_EQ(d.error_before, 0.0);
}

// Each set of mistakes is rendered once for a class, whatever the order it is asked in.
TEST(Diagnose, EachMutantIsRenderedOnce) {
    int calls = 0;
    MutantRenders renders([&](const std::vector<std::string>& m) {
        ++calls;
        return fake_render(m);
    });
    renders.get({"no-shadows", "gamma"});
    renders.get({"gamma", "no-shadows"});
    EXPECT_EQ(calls, 1);
    for (int i = 0; i < 3; ++i)
        diagnose(as_file(fake_render({"no-specular"})), renders, kCatalogue, {});
    const int after_class = calls;
    EXPECT_EQ(size_t(after_class), renders.renders());
    diagnose(as_file(fake_render({"no-shadows"})), renders, kCatalogue, {});
    EXPECT_EQ(calls, after_class);  // the same mutants again
}

}  // namespace diagnose_test
}  // namespace rt
