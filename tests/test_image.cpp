// Image output: byte conversion of spec §9, PFM round trip, formats by extension, no partial file.
#include <filesystem>
#include <fstream>

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

}  // namespace
}  // namespace rt
