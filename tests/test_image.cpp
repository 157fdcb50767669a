// Image output: byte conversion of spec §9, PFM and EXR round trips, formats by extension, no
// partial file.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "rt/image/exr.h"
#include "rt/image/image.h"
#include "test_util.h"

namespace rt {
namespace {

TEST(Image, ByteConversionRoundsAndClamps) {
    EXPECT_EQ(to_byte(0.0), 0);
    EXPECT_EQ(to_byte(1.0), 255);
    EXPECT_EQ(to_byte(1.7), 255);
    EXPECT_EQ(to_byte(-0.2), 0);
    EXPECT_EQ(to_byte(0.566933), 145);  // floor(255 c + 0.5)
    EXPECT_EQ(to_byte(0.5 / 255), 1);
    EXPECT_EQ(to_byte(0.49 / 255), 0);
    EXPECT_EQ(to_byte(std::nan("")), 0);
}

TEST(Image, DisplayTransformScalesAndTonemaps) {
    Image im(2, 1);
    im.set(0, 0, Vec3(0.25, 1.0, 3.0));
    im.set(1, 0, Vec3(0.0, -1.0, 100.0));
    const Image same = display_transform(im, 0, Tonemap::Clamp);
    EXPECT_EQ(same.rgb, im.rgb);
    const Image brighter = display_transform(im, 1, Tonemap::Clamp);
    EXPECT_EQ(brighter.at(0, 0), Vec3(0.5, 2.0, 6.0));
    const Image reinhard = display_transform(im, 0, Tonemap::Reinhard);
    EXPECT_DOUBLE_EQ(reinhard.at(0, 0).y, 0.5);
    EXPECT_DOUBLE_EQ(reinhard.at(0, 0).z, 0.75);
    EXPECT_EQ(reinhard.at(1, 0).y, 0.0);
    const Image aces = display_transform(im, 0, Tonemap::Aces);
    EXPECT_EQ(aces.at(1, 0).x, 0.0);
    EXPECT_GT(aces.at(1, 0).z, 0.99);  // highlights roll off below 1
    EXPECT_LE(aces.at(1, 0).z, 1.0);
    EXPECT_LT(aces.at(0, 0).x, aces.at(0, 0).y);  // monotonic
}

TEST(Image, PfmKeepsFloatsAndRowOrder) {
    Image img(3, 2);
    img.set(0, 0, Vec3(2.5, -1, 0.125));  // top-left, unclamped
    img.set(2, 1, Vec3(1e6, 0, 3));
    const std::string path = ::testing::TempDir() + "/rt_image.pfm";
    save_image(img, path);
    const Image back = load_pfm(path);
    EXPECT_EQ(back.rgb, img.rgb);
    std::filesystem::remove(path);
}

TEST(Image, NonFiniteValuesAreWrittenAsZero) {
    Image img(2, 1);
    img.set(0, 0, Vec3(std::nan(""), kInf, 0.5));
    const std::string path = ::testing::TempDir() + "/rt_nonfinite.pfm";
    save_image(img, path);
    const Image back = load_pfm(path);
    EXPECT_EQ(back.at(0, 0), Vec3(0, 0, 0.5));
    std::filesystem::remove(path);
}

TEST(Image, WritesPngBmpPpmAndRejectsUnknown) {
    Image img(4, 3);
    img.set(1, 0, Vec3(1, 0.5, 0));
    for (const char* ext : {".png", ".bmp", ".ppm"}) {
        const std::string path = ::testing::TempDir() + "/rt_image" + ext;
        save_image(img, path);
        TextureImage t;
        std::string err;
        ASSERT_TRUE(load_texture_image(path, &t, &err)) << ext << err;
        EXPECT_EQ(t.width, 4);
        EXPECT_EQ(t.rgb[3], 255);  // pixel (1, 0): row 0 is the top
        EXPECT_EQ(t.rgb[4], 128);
        std::filesystem::remove(path);
    }
    EXPECT_EQ(image_format_from_path("x.PNG"), ImageFormat::Png);
    EXPECT_THROW(save_image(img, ::testing::TempDir() + "/x.tiff"), std::runtime_error);
}

TEST(Image, FailedWriteLeavesNoFile) {
    Image img(2, 2);
    const std::string path = "/nonexistent_dir_rt/out.png";
    EXPECT_THROW(save_image(img, path), std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(path));
}

// A value as a half channel stores it: finite values clamped to +-65504, rounded to the nearest
// half (11 significant bits; below 2^-14 multiples of 2^-24), ties to even.
double as_half(double v) {
    if (!std::isfinite(v) || v == 0) return v;
    v = std::clamp(v, -65504.0, 65504.0);
    int e = 0;
    std::frexp(v, &e);  // |v| in [2^(e-1), 2^e)
    const double quantum = std::ldexp(1.0, std::max(e, -13) - 11);
    return std::nearbyint(v / quantum) * quantum;
}

std::vector<std::string> names(const ExrImage& e) {
    std::vector<std::string> n;
    for (const ExrChannel& c : e.channels) n.push_back(c.name);
    return n;
}

// An image with unclamped, negative, tiny, huge and non-finite values; pixel (1, 0) is the top row.
Image exr_test_image() {
    Image img(3, 2);
    img.set(0, 0, Vec3(2.5, -1, 0.1));
    img.set(1, 0, Vec3(1, 0.5, 1e-5));
    img.set(2, 0, Vec3(1e6, 65519.0, 1.0 / 3));
    img.set(0, 1, Vec3(std::nan(""), kInf, -kInf));
    img.set(2, 1, Vec3(0.7, 0.2, 3));
    return img;
}

TEST(Image, ExrHalfRgbRoundTrip) {
    const Image img = exr_test_image();
    const std::string path = ::testing::TempDir() + "/rt_half.exr";
    EXPECT_EQ(image_format_from_path("x.EXR"), ImageFormat::Exr);
    save_image(img, path);  // half R, G, B
    const ExrImage e = load_exr(path);
    EXPECT_EQ(e.width, 3);
    EXPECT_EQ(e.height, 2);
    EXPECT_EQ(names(e), (std::vector<std::string>{"B", "G", "R"}));  // the file sorts them
    for (const ExrChannel& c : e.channels) EXPECT_EQ(c.type, ExrPixel::Half) << c.name;
    const Image back = e.rgb();
    // Row order: the top-left pixel first; values as half stores them.
    EXPECT_EQ(back.at(0, 0), Vec3(2.5, -1, as_half(0.1)));
    EXPECT_EQ(back.at(1, 0), Vec3(1, 0.5, as_half(1e-5)));
    EXPECT_NE(as_half(0.1), 0.1);  // half rounds
    // Beyond half's range: its largest value, not infinity.
    EXPECT_EQ(back.at(2, 0), Vec3(65504, 65504, as_half(1.0 / 3)));
    EXPECT_EQ(back.at(0, 1), Vec3(0, 0, 0));  // non-finite values are written as 0 (spec §9)
    EXPECT_EQ(back.at(2, 1), Vec3(as_half(0.7), as_half(0.2), 3));
    EXPECT_EQ(load_image(path).rgb, back.rgb);
    std::filesystem::remove(path);
}

TEST(Image, ExrFloatEqualsThePfm) {
    const Image img = exr_test_image();
    const std::string exr = ::testing::TempDir() + "/rt_float.exr";
    const std::string pfm = ::testing::TempDir() + "/rt_float.pfm";
    save_exr(img, {}, true, exr);
    save_image(img, pfm);
    const ExrImage e = load_exr(exr);
    for (const ExrChannel& c : e.channels) EXPECT_EQ(c.type, ExrPixel::Float) << c.name;
    EXPECT_EQ(e.rgb().rgb, load_pfm(pfm).rgb);
    EXPECT_EQ(e.rgb().at(2, 0), Vec3(1e6, 65519, static_cast<double>(1.0f / 3)));
    EXPECT_EQ(e.rgb().at(0, 1), Vec3(0, 0, 0));
    std::filesystem::remove(exr);
    std::filesystem::remove(pfm);
}

TEST(Image, ExrExtraChannelsKeepNamesTypesAndValues) {
    const Image img = exr_test_image();
    const std::vector<double> v = {0.1, -2, std::nan(""), kInf, 1e6, 4e9};
    const std::vector<ExrChannel> extra = {{"Albedo.R", ExrPixel::Half, v},
                                           {"depth.Z", ExrPixel::Float, v},
                                           {"Samples.N", ExrPixel::Uint, v}};
    for (const bool full_float : {false, true}) {
        const std::string path = ::testing::TempDir() + "/rt_extra.exr";
        save_exr(img, extra, full_float, path);
        const ExrImage e = load_exr(path);
        EXPECT_EQ(names(e),
                  (std::vector<std::string>{"Albedo.R", "B", "G", "R", "Samples.N", "depth.Z"}));
        const ExrChannel* albedo = e.find("Albedo.R");
        const ExrChannel* depth = e.find("depth.Z");
        const ExrChannel* samples = e.find("Samples.N");
        ASSERT_TRUE(albedo && depth && samples);
        EXPECT_EQ(e.find("Albedo.G"), nullptr);
        // Half follows the file's precision; Float and Uint are what they say.
        EXPECT_EQ(albedo->type, full_float ? ExrPixel::Float : ExrPixel::Half);
        EXPECT_EQ(depth->type, ExrPixel::Float);
        EXPECT_EQ(samples->type, ExrPixel::Uint);
        EXPECT_EQ(albedo->values[0], full_float ? static_cast<double>(0.1f) : as_half(0.1));
        EXPECT_EQ(albedo->values[4], full_float ? 1e6 : 65504);
        EXPECT_EQ(depth->values,
                  (std::vector<double>{static_cast<double>(0.1f), -2, 0, kInf, 1e6, 4e9}));
        // Unsigned: rounded, negative and NaN as 0, exact above float's 2^24.
        EXPECT_EQ(samples->values, (std::vector<double>{0, 0, 0, 4294967295.0, 1e6, 4e9}));
        std::filesystem::remove(path);
    }
}

TEST(Image, ExrRefusesBadChannelsAndLeavesNoFile) {
    const Image img(2, 2);
    const std::string path = ::testing::TempDir() + "/rt_bad.exr";
    std::filesystem::remove(path);
    EXPECT_THROW(save_exr(img, {{"A", ExrPixel::Half, {1, 2, 3}}}, false, path),
                 std::runtime_error);  // 3 values for 4 pixels
    EXPECT_THROW(save_exr(img, {{"G", ExrPixel::Half, {1, 2, 3, 4}}}, false, path),
                 std::runtime_error);  // R, G and B are the image's
    EXPECT_THROW(
        save_exr(img, {{"A", ExrPixel::Half, {1, 2, 3, 4}}, {"A", ExrPixel::Half, {1, 2, 3, 4}}},
                 false, path),
        std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(path));
    const std::string nodir = "/nonexistent_dir_rt/out.exr";
    EXPECT_THROW(save_image(img, nodir), std::runtime_error);
    EXPECT_THROW(save_exr(img, {{"A", ExrPixel::Half, {1, 2, 3, 4}}}, true, nodir),
                 std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(nodir));
    EXPECT_FALSE(std::filesystem::exists(nodir + ".part"));
    // A file that is not an EXR, and one cut short, are errors, not crashes.
    const std::string junk = ::testing::TempDir() + "/rt_junk.exr";
    std::ofstream(junk) << "not an EXR file";
    EXPECT_THROW(load_exr(junk), std::runtime_error);
    save_exr(exr_test_image(), {}, true, path);
    std::filesystem::resize_file(path, std::filesystem::file_size(path) - 10);
    EXPECT_THROW(load_exr(path), std::runtime_error);
    EXPECT_THROW(load_exr(::testing::TempDir() + "/rt_none.exr"), std::runtime_error);
    std::filesystem::remove(junk);
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace rt
