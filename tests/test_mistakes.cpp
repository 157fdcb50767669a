// The catalogue of mistakes (rt/render/mistakes.h, docs/mistakes.md): each switch changes the
// image where its formula says and nowhere else. Where the mistake amounts to a changed input of
// the right formula (half the camera angle, no attenuation, a spot's cut-off halved, one bounce
// more...), the mistaken render must equal the right render of the scene with that input changed;
// elsewhere the pixels that change are named by the scene (the shadow, the highlight, the back
// face) and every other pixel keeps its bits.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "rt/render/mistakes.h"
#include "rt/render/plan.h"
#include "test_util.h"

namespace rt {
namespace {

using test::compile;

constexpr int kW = 48, kH = 36;

RenderSettings settings(int depth = 5, double cutoff = 0.001, bool shadows = true) {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.max_depth = depth;
    s.cutoff = cutoff;
    s.shadows = shadows;
    s.threads = 2;
    return s;
}

Image right(const RenderScene& scene, const RenderSettings& rs = settings()) {
    RenderState state;
    render_samples(state, scene, make_render_plan(scene, rs), rs, 1);
    return state.image();
}

Image wrong(const RenderScene& scene, const MistakeSet& m, const RenderSettings& rs = settings()) {
    return render_with_mistakes(scene, make_render_plan(scene, rs), rs, m);
}

bool same_pixel(const Image& a, const Image& b, int x, int y) { return a.at(x, y) == b.at(x, y); }

int changed_pixels(const Image& a, const Image& b) {
    int n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) n += same_pixel(a, b, x, y) ? 0 : 1;
    return n;
}

// Every pixel the same, bit for bit.
void expect_same(const Image& a, const Image& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (!same_pixel(a, b, x, y)) {
                ADD_FAILURE() << "pixel " << x << "," << y << " differs: (" << a.at(x, y).x << ", "
                              << a.at(x, y).y << ", " << a.at(x, y).z << ") against ("
                              << b.at(x, y).x << ", " << b.at(x, y).y << ", " << b.at(x, y).z
                              << ")";
                return;
            }
}

// The pixels where `where` holds are changed (every one, or at least `at_least` of them when
// every is false), the others keep their bits.
void expect_changed_only(const Image& right_img, const Image& wrong_img,
                         const std::function<bool(int, int)>& where, int at_least,
                         bool every = false) {
    int changed = 0, outside = 0, unchanged_inside = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool same = same_pixel(right_img, wrong_img, x, y);
            if (where(x, y))
                changed += same ? 0 : 1, unchanged_inside += same ? 1 : 0;
            else
                outside += same ? 0 : 1;
        }
    EXPECT_EQ(outside, 0) << "pixels changed where the formula does not reach";
    EXPECT_GE(changed, at_least);
    if (every) {
        EXPECT_EQ(unchanged_inside, 0);
    }
}

bool darker_or_same(const Vec3& a, const Vec3& b) { return a.x <= b.x && a.y <= b.y && a.z <= b.z; }

// A camera on the z axis looking at the wall z = 0 (its normal toward the camera, texture
// coordinates 0..1 over it, vertices 0..3); `extra` adds lights, materials, vertices (from 4)
// and, from its first "#shape_" on, shapes (material 0: the wall's).
std::string wall_scene(const std::string& wall_material, const std::string& extra,
                       const std::string& ha = "0.5") {
    const size_t shapes = std::min(extra.find("#shape_"), extra.size());
    return "#camera 0 0 10  0 0 -1  0 1 0  " + ha +
           "\n#background 0.1 0.2 0.3\n#ambient 0.2 0.2 0.2\n#material " + wall_material +
           " !!\n#vertex -6 -6 0  0 0 0  0 0\n#vertex 6 -6 0  0 0 0  1 0\n"
           "#vertex 6 6 0  0 0 0  1 1\n#vertex -6 6 0  0 0 0  0 1\n" +
           extra.substr(0, shapes) + "#shape_triangle 0 0 1 2\n#shape_triangle 0 0 2 3\n" +
           extra.substr(shapes);
}
const char* kMatte = "0 0 0  .5 .5 .5  .6 .6 .6  0 0 0  1  0 0 0  1  -1";

// Pixel (x, y)'s camera ray meets the wall at z = 0 (camera at z = 10, up y, angle ha).
Vec2 wall_point(int x, int y, double ha = 0.5) {
    const double th = std::tan(ha), tw = th * kW / kH;
    return Vec2((2.0 * (x + 0.5) / kW - 1.0) * tw, (1.0 - 2.0 * (y + 0.5) / kH) * th) * 10.0;
}

TEST(Mistakes, CatalogueHasTwentyUniqueNamesThatRoundTrip) {
    const std::vector<MistakeInfo>& c = mistake_catalogue();
    EXPECT_GE(c.size(), 20u);
    EXPECT_EQ(static_cast<int>(c.size()), kMistakeCount);
    std::set<std::string> names;
    for (const MistakeInfo& m : c) {
        SCOPED_TRACE(m.name);
        EXPECT_TRUE(names.insert(m.name).second) << "duplicate name";
        ASSERT_TRUE(find_mistake(m.name).has_value());
        EXPECT_EQ(*find_mistake(m.name), m.mistake);
        EXPECT_EQ(std::string(mistake_info(m.mistake).name), m.name);
        EXPECT_EQ(std::string(m.section).rfind("§", 0), 0u);
        EXPECT_STRNE(m.formula, "");
        EXPECT_STRNE(m.instead, "");
        EXPECT_STRNE(m.description, "");
    }
    EXPECT_FALSE(find_mistake("no-such-mistake").has_value());
    EXPECT_FALSE(find_mistake("").has_value());
    EXPECT_EQ(mistake_info(Mistake::Gamma).stage, MistakeStage::Output);
    EXPECT_EQ(mistake_info(Mistake::FullAngle).stage, MistakeStage::Camera);
    EXPECT_EQ(mistake_info(Mistake::NoShadows).stage, MistakeStage::Shading);
}

TEST(Mistakes, ParseNamesListsAndUnknownNames) {
    const MistakeSet s = parse_mistakes({"gamma,no-shadows", "bgr"});
    EXPECT_EQ(s.list(), (std::vector<Mistake>{Mistake::Gamma, Mistake::Bgr, Mistake::NoShadows}));
    EXPECT_EQ(s.names(), "gamma, bgr, no-shadows");
    EXPECT_TRUE(s.touches(MistakeStage::Output));
    EXPECT_TRUE(s.touches(MistakeStage::Shading));
    EXPECT_FALSE(s.touches(MistakeStage::Camera));
    try {
        parse_mistakes({"gamma,shadowz"});
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("unknown mistake 'shadowz'"), std::string::npos);
    }
    EXPECT_THROW(parse_mistakes({"gamma,"}), std::invalid_argument);
}

// No mistake: the generic shading of the teaching render gives the normal render's bits.
TEST(Mistakes, NoMistakeIsTheNormalRender) {
    for (const std::string& extra :
         {std::string("#light_point 1 1 1  2 3 6  1 0.05 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  "
                      ".5 .5 .5  40  0 0 0  1  -1 !!\n#shape_sphere 1  0 0 2  1.5\n"),
          std::string("#light_spot 1 1 1  0 0 8  0 0 -1  1 0 0  0.4 2\n#material 0 0 0  0 0 0  0 "
                      "0 0  0 0 0  1  .8 .8 .8  1.5  -1 !!\n#shape_sphere 1  1 1 2  1.5\n")}) {
        const RenderScene s = compile(wall_scene(kMatte, extra));
        expect_same(wrong(s, {}), right(s));
    }
}

// --- the camera (§6.1) ---

TEST(Mistakes, FullAngleIsTheRightRenderAtHalfTheAngle) {
    const std::string extra =
        "#light_point 1 1 1  2 3 6  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  1  0 0 0  "
        "1  -1 !!\n#shape_sphere 1  1 0.5 2  1.5\n";
    const RenderScene s = compile(wall_scene(kMatte, extra, "0.5"));
    const Image w = wrong(s, {Mistake::FullAngle});
    expect_same(w, right(compile(wall_scene(kMatte, extra, "0.25"))));
    EXPECT_GT(changed_pixels(w, right(s)), kW * kH / 4);
}

TEST(Mistakes, AngleDegreesIsTheRightRenderAtHaTimesPiOver180) {
    const std::string extra =
        "#light_point 1 1 1  2 3 6  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  1  0 0 0  "
        "1  -1 !!\n#shape_sphere 1  0.2 0.1 2  1.5\n";
    const RenderScene s = compile(wall_scene(kMatte, extra, "1.2"));
    const Image w = wrong(s, {Mistake::AngleDegrees});
    char ha[64];
    std::snprintf(ha, sizeof ha, "%.17g", 1.2 * kPi / 180.0);
    expect_same(w, right(compile(wall_scene(kMatte, extra, ha))));
    EXPECT_GT(changed_pixels(w, right(s)), kW * kH / 4);
}

TEST(Mistakes, AngleOnWidthPutsTanHaOnTheWidth) {
    CameraPose pose;
    pose.direction = Vec3(0, 0, -1);
    pose.up = Vec3(0, 1, 0);
    pose.half_height_angle_rad = 0.5;
    const Camera ok = make_camera(pose, 400, 200);
    const Camera c = make_camera(pose, 400, 200, {Mistake::AngleOnWidth});
    EXPECT_DOUBLE_EQ(ok.tan_h, std::tan(0.5));
    EXPECT_DOUBLE_EQ(c.tan_w, std::tan(0.5));
    EXPECT_DOUBLE_EQ(c.tan_h, std::tan(0.5) / 2);
    const Camera f = make_camera(pose, 400, 200, {Mistake::FullAngle});
    EXPECT_DOUBLE_EQ(f.tan_h, std::tan(0.25));
    EXPECT_DOUBLE_EQ(f.tan_w, 2 * std::tan(0.25));
    // The image: a wide frame zoomed in by the aspect, the wall's checker seen larger.
    const std::string extra =
        "#light_point 1 1 1  2 3 6  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  1  0 0 0  "
        "1  -1 !!\n#shape_sphere 1  1 0.5 2  1.5\n";
    const RenderScene s = compile(wall_scene(kMatte, extra));
    const Image w = wrong(s, {Mistake::AngleOnWidth});
    const double ha = std::atan(std::tan(0.5) * kH / kW);
    const Image r = right(compile(wall_scene(kMatte, extra, std::to_string(ha))));
    // The same rays up to the rounding of ha's text: all but a few edge pixels agree closely.
    int close = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) close += glm::length(w.at(x, y) - r.at(x, y)) < 1e-4 ? 1 : 0;
    EXPECT_GE(close, kW * kH * 97 / 100);
    EXPECT_GT(changed_pixels(w, right(s)), kW * kH / 4);
}

// --- the output (§9) ---

// A rendered image with values in (0, 1), above 1 and below 0.
Image output_test_image() {
    const RenderScene s =
        compile(wall_scene("0 0 0  .1 .1 .1  .9 .6 .3  0 0 0  1  0 0 0  1  -1",
                           "#light_point 3 2 1  0 0 4  1 0 0\n#light_dir 1 1 1  0 0 -1\n"));
    Image img = right(s);
    img.set(0, 0, Vec3(-0.5, 1.5, 2.0));  // out of range both ways
    return img;
}

std::vector<uint8_t> pixel_bytes(const std::vector<uint8_t>& b, int x, int y) {
    const size_t i = (static_cast<size_t>(y) * kW + x) * 3;
    return {b[i], b[i + 1], b[i + 2]};
}

TEST(Mistakes, FlipVerticalWritesRowJAsRowHMinus1MinusJ) {
    const Image img = output_test_image();
    const std::vector<uint8_t> ok = to_bytes(img), flipped = to_bytes(img, {Mistake::FlipVertical});
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            ASSERT_EQ(pixel_bytes(flipped, x, y), pixel_bytes(ok, x, kH - 1 - y)) << x << "," << y;
    EXPECT_NE(flipped, ok);
    // The output's mistakes leave the linear render alone.
    const RenderScene s = compile(wall_scene(kMatte, "#light_point 1 1 1  0 3 6  1 0 0\n"));
    expect_same(wrong(s, {Mistake::FlipVertical, Mistake::Gamma}), right(s));
    // as_written: the bytes read back.
    const Image back = as_written(img, {Mistake::FlipVertical});
    EXPECT_EQ(to_bytes(back), flipped);
}

TEST(Mistakes, BgrSwapsRedAndBlueOnly) {
    const Image img = output_test_image();
    const std::vector<uint8_t> ok = to_bytes(img), bgr = to_bytes(img, {Mistake::Bgr});
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::vector<uint8_t> a = pixel_bytes(ok, x, y), b = pixel_bytes(bgr, x, y);
            ASSERT_EQ(b, (std::vector<uint8_t>{a[2], a[1], a[0]})) << x << "," << y;
        }
    EXPECT_NE(bgr, ok);
}

TEST(Mistakes, GammaBrightensEveryValueStrictlyBetween0And255) {
    const Image img = output_test_image();
    const std::vector<uint8_t> ok = to_bytes(img), g = to_bytes(img, {Mistake::Gamma});
    int brighter = 0;
    for (size_t i = 0; i < ok.size(); ++i) {
        if (ok[i] == 0 || ok[i] == 255) {
            EXPECT_EQ(g[i], ok[i]) << i;  // 0^(1/2.2) = 0, 1^(1/2.2) = 1
        } else {
            EXPECT_GE(g[i], ok[i]) << i;  // equal only just below 1 (byte 254)
            brighter += g[i] > ok[i] ? 1 : 0;
        }
    }
    EXPECT_GT(brighter, 100);
    EXPECT_EQ(g[0], 0);  // -0.5 clamps to 0
    // 0.5 -> 0.5^(1/2.2) = 0.7297: byte 186 instead of 128.
    Image half(1, 1);
    half.set(0, 0, Vec3(0.5));
    EXPECT_EQ(to_bytes(half)[0], 128);
    EXPECT_EQ(to_bytes(half, {Mistake::Gamma})[0], 186);
}

TEST(Mistakes, WrapOverflowChangesOnlyValuesOutside0To1) {
    const Image img = output_test_image();
    const std::vector<uint8_t> ok = to_bytes(img), w = to_bytes(img, {Mistake::WrapOverflow});
    int wrapped = 0;
    for (size_t i = 0; i < ok.size(); ++i) {
        const double c = img.rgb[i];
        if (c >= 0.0 && c <= 1.0) {
            EXPECT_EQ(w[i], ok[i]) << i;
        } else if (c >= 256.5 / 255.0) {  // the rounded byte is 257 or more
            EXPECT_EQ(w[i],
                      static_cast<uint8_t>(static_cast<int>(std::floor(255 * c + 0.5)) % 256));
            wrapped += w[i] != ok[i] ? 1 : 0;  // 255 only where the byte was 511, 767...
        }
    }
    EXPECT_GT(wrapped, 10);
    EXPECT_EQ(pixel_bytes(w, 0, 0), (std::vector<uint8_t>{129, 127, 254}));  // -127, 383, 510
}

// --- the shading equation (§7.1) ---

TEST(Mistakes, NoAmbientTakesKaTimesAOffEverySurfacePixel) {
    const RenderScene s = compile(wall_scene(
        kMatte,
        "#light_point 1 1 1  0 3 6  1 0 0\n#material 0 0 0  .3 .4 .5  .5 .5 .5  0 0 0  1  "
        "0 0 0  1  -1 !!\n#shape_sphere 1  0 0 2  1.5\n"));
    const Image r = right(s), w = wrong(s, {Mistake::NoAmbient});
    int surface = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const Vec2 p = wall_point(x, y);
            if (std::max(std::abs(p.x), std::abs(p.y)) > 6) {  // the background
                EXPECT_TRUE(same_pixel(r, w, x, y)) << x << "," << y;
                continue;
            }
            ++surface;
            const Vec3 d = r.at(x, y) - w.at(x, y);  // K_A * A: the wall's or the sphere's
            const bool wall = glm::length(d - Vec3(0.1)) < 1e-12;
            const bool sphere = glm::length(d - Vec3(0.06, 0.08, 0.1)) < 1e-12;
            EXPECT_TRUE(wall || sphere) << x << "," << y << ": " << d.x << " " << d.y << " " << d.z;
        }
    EXPECT_GT(surface, kW * kH / 3);
}

TEST(Mistakes, NoEmissiveDarkensOnlyTheGlowingObject) {
    const RenderScene s = compile(wall_scene(
        kMatte,
        "#light_point 1 1 1  0 3 6  1 0 0\n#material .4 .2 .1  .1 .1 .1  .5 .5 .5  0 0 0  1  "
        "0 0 0  1  -1 !!\n#shape_sphere 1  0 0 2  1.5\n"));
    const Image r = right(s), w = wrong(s, {Mistake::NoEmissive});
    // The sphere's pixels: those where the render without the sphere's K_E differs... every
    // changed pixel is darker by exactly K_E.
    int changed = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (same_pixel(r, w, x, y)) continue;
            ++changed;
            EXPECT_LT(glm::length(r.at(x, y) - w.at(x, y) - Vec3(.4, .2, .1)), 1e-12);
            // The sphere of radius 1.5 at z = 2 seen from z = 10: within 2.1 of the axis at z = 0.
            EXPECT_LT(glm::length(wall_point(x, y)), 1.5 * 10 / 8 + 0.5) << x << "," << y;
        }
    EXPECT_GT(changed, 20);
}

TEST(Mistakes, NoDiffuseClampLetsALightBehindTheWallDarkenIt) {
    // Light 0 in front of the wall, light 1 behind it (N.L < 0 on the whole wall).
    const std::string front = "#light_point 1 1 1  0 3 6  1 0 0\n";
    const RenderScene s =
        compile(wall_scene(kMatte, front + "#light_point 0.5 0.5 0.5  0 0 -3  1 0 0\n"));
    const Image r = right(s), w = wrong(s, {Mistake::NoDiffuseClamp});
    expect_same(r, right(compile(wall_scene(kMatte, front))));  // the spec: light 1 adds nothing
    int darker = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const Vec2 p = wall_point(x, y);
            if (std::max(std::abs(p.x), std::abs(p.y)) > 6) {
                EXPECT_TRUE(same_pixel(r, w, x, y));
            } else {
                EXPECT_TRUE(darker_or_same(w.at(x, y), r.at(x, y)));
                darker += w.at(x, y).x < r.at(x, y).x ? 1 : 0;
            }
        }
    EXPECT_GT(darker, kW * kH / 3);
}

TEST(Mistakes, OneSidedLeavesABackFaceUnlit) {
    // Two small triangles in front of the wall, lit from the camera's side: the left one faces
    // the camera, the right one faces away (its vertices in the other order).
    const std::string extra =
        "#light_dir 1 1 1  0 0 -1\n#vertex -4 -2 3  0 0 0  0 0\n#vertex -1 -2 3  0 0 0  0 0\n"
        "#vertex -2.5 2 3  0 0 0  0 0\n#vertex 1 -2 3  0 0 0  0 0\n#vertex 4 -2 3  0 0 0  0 0\n"
        "#vertex 2.5 2 3  0 0 0  0 0\n#shape_triangle 0 4 5 6\n#shape_triangle 0 7 9 8\n";
    const RenderScene s = compile(wall_scene(kMatte, extra));
    const Image r = right(s), w = wrong(s, {Mistake::OneSided});
    int darker = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (same_pixel(r, w, x, y)) continue;
            // Only the back face: right of the axis (x > 0 at z = 3, so at z = 0 too).
            EXPECT_GT(wall_point(x, y).x, 0.0) << x << "," << y;
            EXPECT_LT(glm::length(w.at(x, y) - Vec3(0.1)), 1e-12);  // K_A A only
            ++darker;
        }
    EXPECT_GT(darker, 20);
}

// A shiny sphere before a black background: its highlight, and nothing it reflects.
std::string shiny_sphere(const std::string& exponent) {
    return "#camera 0 0 10  0 0 -1  0 1 0  0.3\n#ambient 0.2 0.2 0.2\n"
           "#light_point 1 1 1  3 3 8  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  .5 .5 .5  " +
           exponent + "  0 0 0  1  -1 !!\n#shape_sphere 0  0 0 0  2\n";
}

TEST(Mistakes, NoSpecularIsTheSphereWithoutItsHighlight) {
    const RenderScene s = compile(shiny_sphere("40"));
    const Image w = wrong(s, {Mistake::NoSpecular});
    // The right render of the same sphere with K_S = 0 (it reflects only the black background).
    const Image matte = right(compile(
        "#camera 0 0 10  0 0 -1  0 1 0  0.3\n#ambient 0.2 0.2 0.2\n"
        "#light_point 1 1 1  3 3 8  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  40  0 0 0  "
        "1  -1 !!\n#shape_sphere 0  0 0 0  2\n"));
    expect_same(w, matte);
    const Image r = right(s);
    const int highlight = changed_pixels(r, w);
    EXPECT_GT(highlight, 5);
    EXPECT_LT(highlight, kW * kH / 8);  // the highlight, not the sphere
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) EXPECT_TRUE(darker_or_same(w.at(x, y), r.at(x, y)));
}

TEST(Mistakes, BlinnChangesOnlyTheHighlight) {
    const RenderScene s = compile(shiny_sphere("40"));
    const Image r = right(s), w = wrong(s, {Mistake::Blinn});
    const Image none = wrong(s, {Mistake::NoSpecular});
    // Only the sphere's pixels change (the black background keeps its bits), and only by the
    // highlight term: never below the sphere without it.
    int changed = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (same_pixel(r, w, x, y)) continue;
            ++changed;
            EXPECT_NE(none.at(x, y), Vec3(0.0)) << x << "," << y;  // on the sphere
            EXPECT_TRUE(darker_or_same(none.at(x, y), w.at(x, y))) << x << "," << y;
        }
    EXPECT_GT(changed, 5);
    EXPECT_TRUE(same_pixel(r, w, 0, 0));
}

// --- lights (§7.2) ---

TEST(Mistakes, LightDirReversedLightsFromTheOtherSide) {
    const std::string tail =
        "#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  1  0 0 0  1  -1 !!\n"
        "#shape_sphere 1  0 0 2  1.5\n";
    const RenderScene s = compile(wall_scene(kMatte, "#light_dir 1 1 1  -1 -0.5 -1\n" + tail));
    const Image w = wrong(s, {Mistake::LightDirReversed});
    expect_same(w, right(compile(wall_scene(kMatte, "#light_dir 1 1 1  1 0.5 1\n" + tail))));
    // Light travelling away from the camera lights the wall; reversed, only the sphere's far
    // side would see it: the wall goes dark (K_A A) everywhere.
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const Vec2 p = wall_point(x, y);
            if (std::max(std::abs(p.x), std::abs(p.y)) > 6 || glm::length(p) < 2.5) continue;
            EXPECT_LT(glm::length(w.at(x, y) - Vec3(0.1)), 1e-12) << x << "," << y;
        }
}

TEST(Mistakes, NoAttenuationIsTheLightWithCoefficients100) {
    const std::string tail =
        "#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  1  0 0 0  1  -1 !!\n"
        "#shape_sphere 1  0 0 2  1.5\n";
    const RenderScene s =
        compile(wall_scene(kMatte, "#light_point 4 4 4  2 3 6  1 0.5 0.1\n" + tail));
    const Image w = wrong(s, {Mistake::NoAttenuation});
    expect_same(w, right(compile(wall_scene(kMatte, "#light_point 4 4 4  2 3 6  1 0 0\n" + tail))));
    const Image r = right(s);
    EXPECT_GT(changed_pixels(r, w), kW * kH / 3);
    // Coefficients 1 0 0 divide by 1: the mistake changes nothing.
    const RenderScene unit =
        compile(wall_scene(kMatte, "#light_point 4 4 4  2 3 6  1 0 0\n" + tail));
    expect_same(wrong(unit, {Mistake::NoAttenuation}), right(unit));
}

std::string spot_scene(const std::string& cutoff, const std::string& dropoff) {
    return wall_scene(kMatte,
                      "#light_spot 1 1 1  0 0 6  0 0 -1  1 0 0  " + cutoff + " " + dropoff + "\n");
}

TEST(Mistakes, SpotNoDropoffIsTheSpotWithExponent0) {
    const RenderScene s = compile(spot_scene("0.5", "8"));
    const Image r = right(s), w = wrong(s, {Mistake::SpotNoDropoff});
    expect_same(w, right(compile(spot_scene("0.5", "0"))));
    // Inside the cone brighter, outside (angle > 0.5 from the axis, seen from z = 6) the same.
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double angle = std::atan(glm::length(wall_point(x, y)) / 6);
            if (angle > 0.5 + 1e-6) {
                EXPECT_TRUE(same_pixel(r, w, x, y)) << x << "," << y;
            }
            if (angle < 0.49) {
                EXPECT_GT(w.at(x, y).x, r.at(x, y).x) << x << "," << y;
            }
        }
}

TEST(Mistakes, SpotCutoffFullAngleIsTheSpotWithHalfTheCutoff) {
    const RenderScene s = compile(spot_scene("0.5", "1"));
    const Image r = right(s), w = wrong(s, {Mistake::SpotCutoffFullAngle});
    expect_same(w, right(compile(spot_scene("0.25", "1"))));
    // Only the ring between the half and the whole cut-off goes dark.
    expect_changed_only(
        r, w,
        [](int x, int y) {
            const double angle = std::atan(glm::length(wall_point(x, y)) / 6);
            return angle > 0.25 - 1e-3 && angle < 0.5 + 1e-3;
        },
        40);
}

// --- shadows (§7.2) ---

// The wall, a light before it and a sphere between them; `sphere_t` its transparency.
std::string shadow_scene(const std::string& sphere_t) {
    return wall_scene(kMatte,
                      "#light_point 1 1 1  0 0 8  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 "
                      ".2  0 0 0  1  " +
                          sphere_t + "  1  -1 !!\n#shape_sphere 1  2 1 4  1\n");
}

TEST(Mistakes, NoShadowsBrightensOnlyTheShadow) {
    const RenderScene s = compile(shadow_scene("0 0 0"));
    const Image r = right(s), w = wrong(s, {Mistake::NoShadows});
    expect_same(w, right(s, settings(5, 0.001, false)));  // S_l = 1: shadows turned off
    // The shadow: wall points whose segment to the light (0, 0, 8) meets the sphere (2, 1, 4) r 1.
    auto in_shadow = [](int x, int y) {
        const Vec2 p = wall_point(x, y);
        const Vec3 a(p.x, p.y, 0), d = glm::normalize(Vec3(0, 0, 8) - a), c(2, 1, 4);
        const double b = glm::dot(c - a, d);
        return std::max(std::abs(p.x), std::abs(p.y)) < 6 && glm::length(c - a - b * d) < 1 + 1e-3;
    };
    expect_changed_only(r, w, in_shadow, 15);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) EXPECT_TRUE(darker_or_same(r.at(x, y), w.at(x, y)));
}

TEST(Mistakes, OpaqueShadowsBlackenATransparentSpheresShadow) {
    const RenderScene s = compile(shadow_scene("0.6 0.6 0.6"));
    const RenderSettings rs = settings(1);  // no refraction: the sphere's own pixels stay local
    const Image r = right(s, rs), w = wrong(s, {Mistake::OpaqueShadows}, rs);
    const Image lit = right(s, settings(1, 0.001, false));
    int blackened = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (same_pixel(r, lit, x, y)) {  // no shadow: no change
                EXPECT_TRUE(same_pixel(r, w, x, y)) << x << "," << y;
            } else {  // the shadow: T = 0.6 of the light before, none now (K_A A)
                EXPECT_LT(glm::length(w.at(x, y) - Vec3(0.1)), 1e-12) << x << "," << y;
                ++blackened;
            }
        }
    EXPECT_GT(blackened, 15);
    // An opaque sphere's shadow is the same either way.
    const RenderScene opaque = compile(shadow_scene("0 0 0"));
    expect_same(wrong(opaque, {Mistake::OpaqueShadows}), right(opaque));
}

TEST(Mistakes, ShadowPastLightLetsAnObjectBeyondTheLightShadowTheWall) {
    // The light at z = 2 between the wall and a sphere at z = 4, off to the right: the sphere
    // is beyond the light, so it shadows nothing; with the mistake it shadows the wall on the
    // left, where the ray from the wall through the light goes on to the sphere.
    const RenderScene s = compile(wall_scene(
        kMatte,
        "#light_point 1 1 1  0 0 2  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  1  "
        "0 0 0  1  -1 !!\n#shape_sphere 1  3 0 4  1\n",
        "0.6"));
    const Image r = right(s), w = wrong(s, {Mistake::ShadowPastLight});
    expect_same(r, right(s, [] {
                    RenderSettings rs = settings();
                    rs.shadows = false;
                    return rs;
                }()));  // the spec: no shadow at all
    // The wall on the left (the line from it through the light meets the sphere for x in about
    // (-6, -1.7)), and the sphere itself (seen about x = 5 on the wall), whose rays to the light
    // go on to the wall.
    expect_changed_only(
        r, w,
        [](int x, int y) {
            const Vec2 p = wall_point(x, y, 0.6);
            return (p.x < -1.5 && p.x > -6.5 && std::abs(p.y) < 2.5) ||
                   glm::length(p - Vec2(5, 0)) < 2.5;
        },
        10);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (!same_pixel(r, w, x, y)) {  // in shadow: K_A A of the wall or the sphere
                EXPECT_TRUE(glm::length(w.at(x, y) - Vec3(0.1)) < 1e-12 ||
                            glm::length(w.at(x, y) - Vec3(0.02)) < 1e-12)
                    << x << "," << y;
            }
}

// --- spawned rays (§7.5) ---

TEST(Mistakes, NoOffsetGivesAcneOnLitSurfacesOnly) {
    const RenderScene s = compile(wall_scene(
        kMatte,
        "#light_point 1 1 1  1 2 8  1 0 0\n#material 0 0 0  .1 .1 .1  .5 .2 .2  0 0 0  1  "
        "0 0 0  1  -1 !!\n#shape_sphere 1  0 0 2  1.5\n"));
    const Image r = right(s), w = wrong(s, {Mistake::NoOffset});
    int acne = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            // Only self-shadowing: a pixel can only lose its direct light, down to K_A A.
            EXPECT_TRUE(darker_or_same(w.at(x, y), r.at(x, y))) << x << "," << y;
            if (same_pixel(r, w, x, y)) continue;
            ++acne;
            const Vec3 ambient = w.at(x, y);
            EXPECT_TRUE(glm::length(ambient - Vec3(0.1)) < 1e-12 ||
                        glm::length(ambient - Vec3(0.02)) < 1e-12)
                << x << "," << y;
        }
    EXPECT_GT(acne, 10);
}

// --- reflection, refraction, depth and cutoff (§7.4, §8) ---

// A mirror sphere (K_S `ks`) or a glass one (T 0.9, index `index`) before the wall.
std::string mirror_scene(const std::string& ks) {
    return wall_scene(kMatte, "#light_point 1 1 1  1 2 8  1 0 0\n#material 0 0 0  0 0 0  0 0 0  " +
                                  ks + "  1000  0 0 0  1  -1 !!\n#shape_sphere 1  0 0 3  2\n");
}
std::string glass_scene(const std::string& index) {
    return wall_scene("0 0 0  .2 .2 .2  .6 .6 .6  0 0 0  1  0 0 0  1  -1",
                      "#light_point 1 1 1  1 2 8  1 0 0\n#material 0 0 0  0 0 0  0 0 0  0 0 0  1  "
                      ".9 .9 .9  " +
                          index + "  -1 !!\n#shape_sphere 1  0 0 3  2\n");
}

// A 4x4 checker of red and blue for the wall (material 0), so refraction shows.
RenderScene with_checker(RenderScene s) {
    auto tex = std::make_shared<TextureImage>();
    tex->width = tex->height = 4;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const bool red = (x + y) % 2 == 0;
            tex->rgb.insert(tex->rgb.end(), {static_cast<uint8_t>(red ? 255 : 0), 40,
                                             static_cast<uint8_t>(red ? 0 : 255)});
        }
    s.textures.push_back(tex);
    s.materials[0].texture = static_cast<int>(s.textures.size()) - 1;
    return s;
}

TEST(Mistakes, NoReflectionIsTheMirrorAtDepth1) {
    const RenderScene s = compile(mirror_scene(".8 .8 .8"));
    const Image r = right(s), w = wrong(s, {Mistake::NoReflection});
    const Image depth1 = right(s, settings(1));
    expect_same(w, depth1);
    EXPECT_GT(changed_pixels(r, w), 50);
}

TEST(Mistakes, NoRefractionIsTheGlassAtDepth1) {
    const RenderScene s = with_checker(compile(glass_scene("1.5")));
    const Image r = right(s), w = wrong(s, {Mistake::NoRefraction});
    expect_same(w, right(s, settings(1)));
    EXPECT_GT(changed_pixels(r, w), 50);
}

TEST(Mistakes, IorInvertedChangesOnlyWhatIsSeenThroughTheGlass) {
    const RenderScene s = with_checker(compile(glass_scene("1.5")));
    const Image r = right(s), w = wrong(s, {Mistake::IorInverted});
    const Image depth1 = right(s, settings(1));
    // Only pixels with a refracted ray (those that change at depth 1) may change.
    expect_changed_only(
        r, w, [&](int x, int y) { return !same_pixel(r, depth1, x, y); }, 30);
    // An index of 1 bends nothing either way.
    const RenderScene air = with_checker(compile(glass_scene("1")));
    expect_same(wrong(air, {Mistake::IorInverted}), right(air));
}

TEST(Mistakes, DepthOffByOneIsTheRenderOneLevelDeeper) {
    // Two mirror spheres facing each other: every level adds to the image.
    const RenderScene s = compile(wall_scene(
        kMatte,
        "#light_point 1 1 1  1 2 8  1 0 0\n#material 0 0 0  .1 0 0  .2 0 0  .8 .8 .8  "
        "1000  0 0 0  1  -1 !!\n#shape_sphere 1  -1.6 0 3  1.5\n#shape_sphere 1  1.6 0 3  1.5\n"));
    for (const int depth : {1, 2, 3}) {
        SCOPED_TRACE(depth);
        const Image w = wrong(s, {Mistake::DepthOffByOne}, settings(depth));
        expect_same(w, right(s, settings(depth + 1)));
        EXPECT_GT(changed_pixels(w, right(s, settings(depth))), 0);
    }
}

TEST(Mistakes, NoCutoffIsTheRenderWithCutoff0) {
    const RenderScene s = compile(mirror_scene(".3 .3 .3"));
    const RenderSettings rs = settings(5, 0.5);  // K_S 0.3 < 0.5: the spec traces no reflection
    const Image r = right(s, rs), w = wrong(s, {Mistake::NoCutoff}, rs);
    expect_same(w, right(s, settings(5, 0.0)));
    EXPECT_GT(changed_pixels(r, w), 50);
    // Weights above the cutoff: nothing changes.
    expect_same(wrong(s, {Mistake::NoCutoff}, settings(5, 0.1)), right(s, settings(5, 0.1)));
}

// --- textures (§7.3) ---

// A texture of 3 rows, red at the top, green, blue at the bottom.
RenderScene striped_wall(const std::string& material, bool upside_down) {
    RenderScene s = compile(wall_scene(material, "#light_point 1 1 1  0 0 8  1 0 0\n"));
    auto tex = std::make_shared<TextureImage>();
    tex->width = 1;
    tex->height = 3;
    tex->rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255};
    if (upside_down) tex->rgb = {0, 0, 255, 0, 255, 0, 255, 0, 0};
    s.textures.push_back(tex);
    s.materials[0].texture = 0;
    return s;
}

TEST(Mistakes, TextureVFlippedIsTheTextureUpsideDown) {
    const char* m = "0 0 0  .2 .2 .2  .6 .6 .6  0 0 0  1  0 0 0  1  -1";
    const RenderScene s = striped_wall(m, false);
    const Image r = right(s), w = wrong(s, {Mistake::TextureVFlipped});
    const Image flipped = right(striped_wall(m, true));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            EXPECT_LT(glm::length(w.at(x, y) - flipped.at(x, y)), 1e-9) << x << "," << y;
    EXPECT_GT(changed_pixels(r, w), kW * kH / 2);
    // The top of the wall is red in the right render, blue in the mistaken one.
    const Vec3 top_r = r.at(kW / 2, kH / 2 - 6), top_w = w.at(kW / 2, kH / 2 - 6);
    EXPECT_GT(top_r.x, top_r.z);
    EXPECT_GT(top_w.z, top_w.x);
}

TEST(Mistakes, TextureDiffuseOnlyLeavesTheAmbientTermUntextured) {
    // K_D = 0: the wall shows only K_A (x t) A.
    const RenderScene ambient_only =
        striped_wall("0 0 0  .5 .5 .5  0 0 0  0 0 0  1  0 0 0  1  -1", false);
    RenderScene untextured = ambient_only;
    untextured.materials[0].texture = -1;
    const Image w = wrong(ambient_only, {Mistake::TextureDiffuseOnly});
    expect_same(w, right(untextured));
    EXPECT_GT(changed_pixels(w, right(ambient_only)), kW * kH / 3);
    // K_A = 0: the texel still multiplies K_D, nothing changes.
    const RenderScene diffuse_only =
        striped_wall("0 0 0  0 0 0  .6 .6 .6  0 0 0  1  0 0 0  1  -1", false);
    expect_same(wrong(diffuse_only, {Mistake::TextureDiffuseOnly}), right(diffuse_only));
}

TEST(Mistakes, RenderWrittenIsTheFileReadBack) {
    const RenderScene s = compile(shadow_scene("0 0 0"));
    const RenderSettings rs = settings();
    const RenderPlan plan = make_render_plan(s, rs);
    // No mistake: the right render as its 8-bit file holds it.
    const Image ok = render_written(s, plan, rs, {});
    EXPECT_EQ(to_bytes(ok), to_bytes(right(s)));
    for (double v : ok.rgb) EXPECT_EQ(v * 255, std::round(v * 255));
    // A shading and an output mistake: the shading's render, through the output's bytes.
    const MistakeSet both{Mistake::NoShadows, Mistake::FlipVertical};
    const Image w = render_written(s, plan, rs, both);
    EXPECT_EQ(to_bytes(w), to_bytes(wrong(s, {Mistake::NoShadows}), {Mistake::FlipVertical}));
    EXPECT_NE(to_bytes(w), to_bytes(ok));
}

// --- two at once ---

TEST(Mistakes, TwoMistakesAtOnce) {
    const RenderScene s = compile(shadow_scene("0 0 0"));
    const MistakeSet both{Mistake::NoShadows, Mistake::Bgr};
    const Image w = wrong(s, both);
    expect_same(w, wrong(s, {Mistake::NoShadows}));  // bgr is the output's
    EXPECT_EQ(to_bytes(w, both), to_bytes(w, {Mistake::Bgr}));
    // Two shading mistakes: no shadows and no ambient, each where its formula says.
    const Image two = wrong(s, {Mistake::NoShadows, Mistake::NoAmbient});
    const Image no_ambient = wrong(s, {Mistake::NoAmbient});
    const Image no_shadows = wrong(s, {Mistake::NoShadows});
    int both_changed = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (same_pixel(no_ambient, no_shadows, x, y)) continue;
            both_changed +=
                !same_pixel(two, no_ambient, x, y) && !same_pixel(two, no_shadows, x, y);
        }
    EXPECT_GT(both_changed, 15);  // the shadow: brighter and without its ambient term
}

}  // namespace
}  // namespace rt
