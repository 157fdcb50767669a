// Images: byte conversion of spec §9, PFM and EXR round trips, formats by extension, no partial
// file; the decoders (rt/image/decode.h) on real files and on damaged or lying ones.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>

#include "rt/image/decode.h"
#include "rt/image/exr.h"
#include "rt/image/image.h"
#include "rt/util/file_io.h"
#include "rt/util/limits.h"
#include "rt/util/sanitizers.h"
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

// ---- decoding -----------------------------------------------------------------------------------

// The small real files of the image fuzz corpus: the 16x12 grid in every format and variant.
std::string fixture(const std::string& name) {
    std::string data, why;
    EXPECT_TRUE(
        read_file(std::string(RT_SOURCE_DIR) + "/tests/fuzz/corpus/image/" + name, &data, &why))
        << why;
    return data;
}

// The reference pixels: grid.ppm's raw RGB (a 13-byte header, then the samples).
std::vector<uint8_t> reference_grid() {
    const std::string ppm = fixture("grid.ppm");
    EXPECT_EQ(ppm.substr(0, 13), "P6\n16 12\n255\n");
    return {ppm.begin() + 13, ppm.end()};
}

std::string write_temp(const std::string& name, std::string_view data) {
    const std::string path = ::testing::TempDir() + "/" + name;
    std::ofstream(path, std::ios::binary)
        .write(data.data(), static_cast<std::streamsize>(data.size()));
    return path;
}

// Decodes through decode_texture(): the image, or a failure with the decoder's message.
TextureImage decoded(std::string_view data) {
    TextureImage t;
    std::string error;
    EXPECT_TRUE(decode_texture(data, &t, &error)) << error;
    return t;
}

std::string decode_error(std::string_view data) {
    TextureImage t;
    std::string error;
    EXPECT_FALSE(decode_texture(data, &t, &error));
    EXPECT_TRUE(t.rgb.empty());  // no partial image
    return error;
}

// The budget of max_image_pixels(), set for one test.
struct BudgetScope {
    explicit BudgetScope(uint64_t pixels) { set_max_image_pixels(pixels); }
    ~BudgetScope() { set_max_image_pixels(kDefaultMaxImagePixels); }
};

TEST(ImageDecode, LosslessFilesDecodeToTheirPixels) {
    const std::vector<uint8_t> ref = reference_grid();
    // 24- and 32-bit BMPs (bottom-up, top-down, OS/2, V5 bit fields), PNGs (RGB, RGBA with its
    // alpha dropped, 16-bit, interlaced), binary and ASCII PPM, 16-bit PPM.
    for (const char* name : {"grid.bmp", "grid_topdown.bmp", "grid_os2.bmp", "grid_bgra.bmp",
                             "grid_v5.bmp", "grid.png", "grid_rgba.png", "grid48.png",
                             "grid_interlaced.png", "grid.ppm", "grid_ascii.ppm", "grid16.ppm"}) {
        const TextureImage t = decoded(fixture(name));
        EXPECT_EQ(t.width, 16) << name;
        EXPECT_EQ(t.height, 12) << name;
        EXPECT_EQ(t.rgb, ref) << name;
    }
}

TEST(ImageDecode, GreyAndPalettesAreReplicated) {
    const std::vector<uint8_t> ref = reference_grid();
    // Grey: the same values in 8-bit and 16-bit PGM and 16-bit PNG, replicated (spec §7.3).
    const TextureImage grey = decoded(fixture("grid.pgm"));
    EXPECT_EQ(decoded(fixture("grid16.pgm")).rgb, grey.rgb);
    EXPECT_EQ(decoded(fixture("grid_gray16.png")).rgb, grey.rgb);
    for (size_t i = 0; i < grey.rgb.size(); i += 3) {
        EXPECT_EQ(grey.rgb[i], grey.rgb[i + 1]);
        EXPECT_EQ(grey.rgb[i], grey.rgb[i + 2]);
    }
    // An ASCII PGM of maxval 15 (green / 17) and a 4-bit BMP of 16 greys (green / 16 * 17).
    const TextureImage ascii = decoded(fixture("grid_ascii.pgm"));
    const TextureImage four = decoded(fixture("grid_4bit.bmp"));
    for (size_t i = 0; i < ref.size(); ++i) {
        const int g = ref[i / 3 * 3 + 1];
        EXPECT_EQ(ascii.rgb[i], (g * 15 / 255 * 255 + 7) / 15) << i;
        EXPECT_EQ(four.rgb[i], g / 16 * 17) << i;
    }
    // 8-bit palettes: the BMP and the PNG made from it agree; 1 bit is black or white.
    EXPECT_EQ(decoded(fixture("grid_pal8.bmp")).rgb, decoded(fixture("grid_pal8.png")).rgb);
    for (const uint8_t v : decoded(fixture("grid_1bit.bmp")).rgb) EXPECT_TRUE(v == 0 || v == 255);
}

TEST(ImageDecode, SixteenBitBmpFieldsRepeatTheirBitsToEight) {
    // 5-5-5 without compression, 5-6-5 in bit fields: each field v of n bits reads as its bits
    // repeated to fill 8 (v << (8 - n) | v >> (2n - 8)), as stb_image read them before.
    const std::vector<uint8_t> ref = reference_grid();
    const auto scaled = [](int v, int bits) {
        const int field = v >> (8 - bits);
        return (field << (8 - bits)) | (field >> (2 * bits - 8));
    };
    const TextureImage t555 = decoded(fixture("grid_555.bmp"));
    const TextureImage t565 = decoded(fixture("grid_565.bmp"));
    ASSERT_EQ(t555.rgb.size(), ref.size());
    ASSERT_EQ(t565.rgb.size(), ref.size());
    for (size_t i = 0; i < ref.size(); ++i) {
        EXPECT_EQ(t555.rgb[i], scaled(ref[i], 5)) << i;
        EXPECT_EQ(t565.rgb[i], scaled(ref[i], i % 3 == 1 ? 6 : 5)) << i;
    }
}

TEST(ImageDecode, JpegsDecodeNearTheirPixels) {
    const std::vector<uint8_t> ref = reference_grid();
    for (const char* name : {"grid.jpg", "grid_444.jpg", "grid_progressive.jpg"}) {
        const TextureImage t = decoded(fixture(name));
        ASSERT_EQ(t.rgb.size(), ref.size()) << name;
        double error = 0;
        for (size_t i = 0; i < ref.size(); ++i) error += std::abs(t.rgb[i] - ref[i]);
        // Lossy, and the grid's one-pixel lines lose their colour in 4:2:0 chroma; an image
        // decoded wrong (shifted, mirrored, garbage) is off by 60 or more on average.
        EXPECT_LT(error / static_cast<double>(ref.size()), 20.0) << name;
    }
    const TextureImage grey = decoded(fixture("grid_grey.jpg"));  // one component: replicated
    for (size_t i = 0; i < grey.rgb.size(); i += 3) {
        EXPECT_EQ(grey.rgb[i], grey.rgb[i + 1]);
        EXPECT_NEAR(grey.rgb[i], ref[i + 1], 24);  // written from the green channel
    }
}

TEST(ImageDecode, TheCheckedStbPathAgreesWithLibpngAndLibjpeg) {
    for (const char* name : {"grid.png", "grid_rgba.png", "grid48.png", "grid_interlaced.png",
                             "grid_pal8.png", "grid_gray16.png"}) {
        TextureImage t;
        std::string error;
        ASSERT_TRUE(decode_png_jpeg_stb(fixture(name), &t, &error)) << name << error;
        EXPECT_EQ(t.rgb, decoded(fixture(name)).rgb) << name;
    }
    for (const char* name : {"grid.jpg", "grid_444.jpg", "grid_progressive.jpg", "grid_grey.jpg"}) {
        TextureImage t;
        std::string error;
        ASSERT_TRUE(decode_png_jpeg_stb(fixture(name), &t, &error)) << name << error;
        const TextureImage lib = decoded(fixture(name));
        ASSERT_EQ(t.rgb.size(), lib.rgb.size());
        for (size_t i = 0; i < t.rgb.size(); ++i)  // two IDCTs and upsamplers
            EXPECT_NEAR(t.rgb[i], lib.rgb[i], 12) << name << " " << i;
    }
}

TEST(ImageDecode, TheScenesTexturesDecodeToWhatMakeTexturesWrote) {
    // scenes/textures/make_textures.py: the checker's top-left square is light, the grid's red
    // grows to the right and its green to the top, with dark lines every 16 pixels.
    TextureImage checker, grid;
    std::string error;
    const std::string dir = std::string(RT_SOURCE_DIR) + "/scenes/textures/";
    ASSERT_TRUE(load_texture_image(dir + "checker.bmp", &checker, &error)) << error;
    ASSERT_TRUE(load_texture_image(dir + "grid.png", &grid, &error)) << error;
    ASSERT_EQ(checker.width, 64);
    EXPECT_EQ(std::vector<uint8_t>(checker.rgb.begin(), checker.rgb.begin() + 3),
              (std::vector<uint8_t>{230, 225, 210}));
    EXPECT_EQ(std::vector<uint8_t>(checker.rgb.begin() + 8 * 3, checker.rgb.begin() + 9 * 3),
              (std::vector<uint8_t>{60, 70, 90}));
    ASSERT_EQ(grid.width, 128);
    for (const auto& [x, y] : {std::pair{5, 7}, std::pair{100, 120}, std::pair{17, 60}}) {
        const uint8_t* p = &grid.rgb[(static_cast<size_t>(y) * 128 + x) * 3];
        EXPECT_EQ(p[0], 255 * x / 127);
        EXPECT_EQ(p[1], 255 * (127 - y) / 127);
        EXPECT_EQ(p[2], 90);
    }
    EXPECT_EQ(grid.rgb[0], 20);  // a grid line
}

// 19 bytes: a 16-bit PGM header and no pixels (stb read past its buffer).
TEST(ImageDecode, AHeaderWithoutPixelsIsTruncated) {
    const std::string path = write_temp("rt_header_only.pgm", "P5 4096 4096 65535\n");
    TextureImage t;
    std::string error;
    EXPECT_FALSE(load_texture_image(path, &t, &error));
    EXPECT_EQ(error,
              "truncated PNM: 4096x4096 pixels need 33554432 bytes of pixel data, the file has 0");
    std::filesystem::remove(path);
}

// Issue 29: a JPEG whose first Huffman table claims 16 x 255 codes (stb wrote past its table);
// the rest is the grid's JPEG.
TEST(ImageDecode, AHuffmanTableBeyondItsCodeSpaceIsAnError) {
    std::string jpeg = "\xFF\xD8\xFF\xC4";
    const size_t length = 2 + 17 + 16 * 255;
    jpeg += static_cast<char>(length >> 8);
    jpeg += static_cast<char>(length & 0xFF);
    jpeg += '\0';  // DC table 0
    jpeg += std::string(16, '\xFF');
    jpeg += std::string(16 * 255, '\0');
    jpeg += fixture("grid.jpg").substr(2);
    const std::string path = write_temp("rt_bad_huffman.jpg", jpeg);
    TextureImage t;
    std::string error;
    EXPECT_FALSE(load_texture_image(path, &t, &error));
    EXPECT_NE(error.find("Huffman"), std::string::npos) << error;
    EXPECT_FALSE(decode_png_jpeg_stb(jpeg, &t, &error));
    EXPECT_EQ(error, "JPEG Huffman table with more codes than fit their lengths");
    std::filesystem::remove(path);
}

// Found by fuzz_image: a scan using an AC table the file never defined (stb decoded with its
// uninitialised memory). libjpeg says so too.
TEST(ImageDecode, AScanUsingAnUndefinedHuffmanTableIsAnError) {
    // The second: a baseline frame's scan of Ss = Se = 0, whose AC table stb uses all the same.
    for (const char* name : {"jpeg_undefined_ac_table.jpg", "jpeg_baseline_dc_only_scan.jpg"}) {
        std::string jpeg;
        ASSERT_TRUE(
            read_file(std::string(RT_SOURCE_DIR) + "/tests/fuzz/crashers/image/" + name, &jpeg));
        TextureImage t;
        std::string error;
        EXPECT_FALSE(decode_png_jpeg_stb(jpeg, &t, &error)) << name;
        EXPECT_EQ(error, "JPEG scan using a Huffman table it has not defined") << name;
        EXPECT_FALSE(decode_error(jpeg).empty()) << name;
    }
}

TEST(ImageDecode, TruncatedFilesAreErrorsNotGarbage) {
    // Half of each file, and each cut just before its end (PNG's IEND, JPEG's EOI, the binary
    // formats' last pixel; an ASCII file cut in its last number still holds a number).
    for (const char* name :
         {"grid.bmp", "grid_pal8.bmp", "grid.png", "grid_interlaced.png", "grid.jpg",
          "grid_progressive.jpg", "grid.ppm", "grid_ascii.ppm", "grid16.pgm"}) {
        const std::string data = fixture(name);
        const std::string ext = std::filesystem::path(name).extension().string();
        std::vector<size_t> keep = {data.size() / 2};
        if (name != std::string("grid_ascii.ppm"))
            keep.push_back(data.size() - (ext == ".png" ? 12 : 2));
        for (const size_t n : keep) {
            const std::string cut = data.substr(0, n);
            SCOPED_TRACE(std::string(name) + " cut to " + std::to_string(n));
            EXPECT_FALSE(decode_error(cut).empty());
            const std::string path = write_temp("rt_truncated" + ext, cut);
            TextureImage t;
            std::string error;
            EXPECT_FALSE(load_texture_image(path, &t, &error));
            std::filesystem::remove(path);
            if (ext == ".png" || ext == ".jpg") {
                EXPECT_FALSE(decode_png_jpeg_stb(cut, &t, &error));
            }
        }
    }
    EXPECT_EQ(decode_error(fixture("grid.bmp").substr(0, 315)),
              "truncated BMP: 16x12 pixels need 576 bytes of pixel data, the file has 261");
    EXPECT_EQ(decode_error(fixture("grid.ppm").substr(0, 300)),
              "truncated PNM: 16x12 pixels need 576 bytes of pixel data, the file has 287");
}

// Issue 29: a BMP header of 54 bytes claiming a large image rendered as a 192 MB texture.
std::string bmp_header(int32_t w, int32_t h, uint16_t bpp = 24, uint32_t compression = 0) {
    std::string b(54, '\0');
    const auto put = [&](size_t at, uint32_t v, int bytes) {
        for (int k = 0; k < bytes; ++k) b[at + k] = static_cast<char>(v >> (8 * k));
    };
    b[0] = 'B';
    b[1] = 'M';
    put(10, 54, 4);
    put(14, 40, 4);
    put(18, static_cast<uint32_t>(w), 4);
    put(22, static_cast<uint32_t>(h), 4);
    put(26, 1, 2);
    put(28, bpp, 2);
    put(30, compression, 4);
    return b;
}

TEST(ImageDecode, SizesAreCheckedAgainstTheFileAndTheBudgetBeforeAllocating) {
    EXPECT_EQ(decode_error(bmp_header(8000, 8000)),
              "truncated BMP: 8000x8000 pixels need 192000000 bytes of pixel data, the file has 0");
    EXPECT_EQ(decode_error(bmp_header(100000, -100000)),
              "BMP image of 100000x100000 pixels (10000000000) is larger than the budget of "
              "67108864 pixels (8192x8192); --max-pixels raises it");
    EXPECT_EQ(decode_error("P6 30000 30000 255\n"), image_size_error(30000, 30000, "PNM image"));
    // ASCII: a sample takes at least two bytes.
    EXPECT_EQ(decode_error("P3 100 100 255\n1 2 3\n"),
              "truncated PNM: 100x100 pixels need 30000 samples, the file has room for at most 3");
    // A lower budget refuses the grid in every format, naming its size and the flag.
    const BudgetScope budget(100);
    for (const char* name : {"grid.bmp", "grid.png", "grid.jpg", "grid.ppm", "grid_ascii.ppm"}) {
        const std::string e = decode_error(fixture(name));
        EXPECT_NE(e.find("of 16x12 pixels (192) is larger than the budget of 100 pixels"),
                  std::string::npos)
            << e;
    }
    for (const char* name : {"grid.png", "grid.jpg"}) {
        TextureImage t;
        std::string error;
        EXPECT_FALSE(decode_png_jpeg_stb(fixture(name), &t, &error));
        EXPECT_NE(error.find("of 16x12 pixels (192) is larger"), std::string::npos) << error;
    }
    Image image;
    std::string error;
    EXPECT_FALSE(decode_pfm(fixture("grid.pfm"), &image, &error));
    EXPECT_EQ(error, image_size_error(16, 12, "PFM image"));
    EXPECT_THROW(
        {
            try {
                decode_exr(fixture("grid.exr"));
            } catch (const std::runtime_error& e) {
                EXPECT_EQ(std::string(e.what()), image_size_error(16, 12, "EXR image"));
                throw;
            }
        },
        std::runtime_error);
}

// Issue 29: a 20-byte PFM claiming 8192x8192 allocated 1.5 GB.
TEST(ImageDecode, APfmIsCheckedAgainstItsBytes) {
    const std::string path = write_temp("rt_lying.pfm", "PF\n8192 8192\n-1.0\n");
    try {
        load_pfm(path);
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "cannot read '" + path +
                      "': truncated PFM: 8192x8192 pixels need 805306368 bytes of pixel data, the "
                      "file has 0");
    }
    std::filesystem::remove(path);
    // The grid as floats, little-endian, rows from the bottom.
    const std::vector<uint8_t> ref = reference_grid();
    Image image;
    std::string error;
    ASSERT_TRUE(decode_pfm(fixture("grid.pfm"), &image, &error)) << error;
    ASSERT_EQ(image.width, 16);
    for (size_t i = 0; i < ref.size(); ++i) EXPECT_NEAR(image.rgb[i] * 255, ref[i], 1e-3) << i;
    // Big-endian (a positive scale) reads the same.
    std::string be = "PF\n16 12\n1.0\n";
    const std::string le = fixture("grid.pfm");
    const size_t at = le.size() - 16 * 12 * 12;
    for (size_t i = at; i < le.size(); i += 4)
        for (size_t k = 0; k < 4; ++k) be += le[i + 3 - k];
    Image big;
    ASSERT_TRUE(decode_pfm(be, &big, &error)) << error;
    EXPECT_EQ(big.rgb, image.rgb);
    EXPECT_FALSE(decode_pfm("PF\n16 12\n0\n", &big, &error));
    EXPECT_EQ(error, "bad PFM header");
}

TEST(ImageDecode, ExrFromMemoryEqualsTheFile) {
    const std::string path = ::testing::TempDir() + "/rt_decode.exr";
    save_exr(exr_test_image(), {}, true, path);
    std::string data;
    ASSERT_TRUE(read_file(path, &data));
    EXPECT_EQ(decode_exr(data).rgb().rgb, load_exr(path).rgb().rgb);
    EXPECT_THROW(decode_exr(data.substr(0, data.size() / 2)), std::exception);
    std::filesystem::remove(path);
    // ffmpeg's grid (no compression, and ZIP with alpha): the grid's values, but for ffmpeg's
    // conversion to linear floats.
    const std::vector<uint8_t> ref = reference_grid();
    // And ours, written with OpenEXR (float): tiled in one level, mipmaps and ripmaps, PIZ from
    // the bottom, two parts (the first is read).
    for (const char* name : {"grid.exr", "grid_zip.exr", "grid_tiled.exr", "grid_mipmap.exr",
                             "grid_ripmap.exr", "grid_piz_decreasing.exr", "grid_multipart.exr"}) {
        const Image rgb = decode_exr(fixture(name)).rgb();
        ASSERT_EQ(rgb.rgb.size(), ref.size()) << name;
        for (size_t i = 0; i < ref.size(); ++i)
            EXPECT_NEAR(rgb.rgb[i] * 255, ref[i], 2.0) << name << " " << i;
        // R, G and B alone read the same values.
        EXPECT_EQ(decode_exr_rgb(fixture(name)).rgb, rgb.rgb) << name;
    }
    // 32-bit unsigned R, G and B keep every bit (not through float).
    EXPECT_EQ(decode_exr_rgb(fixture("rgb_uint.exr")).rgb,
              (std::vector<double>{16777217, 0, 4294967295.0, 1, 2, 3}));
    EXPECT_EQ(decode_exr(fixture("rgb_uint.exr")).rgb().rgb,
              decode_exr_rgb(fixture("rgb_uint.exr")).rgb);
}

// ---- what a hostile file costs ------------------------------------------------------------------

// What a run of `f` in a child process answered, and how far its resident memory rose above
// what it had at its start, in KB (-1 where Linux cannot tell).
struct ChildRun {
    std::string message;
    long grown_kb = -1;
};

long status_kb(const char* field) {  // a field of /proc/self/status (VmRSS, VmHWM), in KB
    std::ifstream status("/proc/self/status");
    for (std::string key; status >> key;) {
        long kb = 0;
        if (key == std::string(field) + ":" && status >> kb) return kb;
    }
    return -1;
}

// Runs `f` in a child process whose address space is capped at 256 MB more than it maps (not
// under the sanitizers, whose shadow memory needs room), so that a decoder allocating what a
// header claims fails there (std::bad_alloc) instead of filling the machine's memory. The peak
// is reset at the child's start (clear_refs 5), so VmHWM is what the run itself touched.
ChildRun in_child(const std::function<std::string()>& f) {
    int fds[2];
    if (pipe(fds) != 0) return {"no pipe"};
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
#if !defined(RT_ASAN) && !defined(RT_TSAN)
        uint64_t pages = 0;
        std::ifstream("/proc/self/statm") >> pages;
        const uint64_t limit =
            pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE)) + (uint64_t{256} << 20);
        const rlimit cap{limit, limit};
        setrlimit(RLIMIT_AS, &cap);
#endif
        const bool reset = static_cast<bool>(std::ofstream("/proc/self/clear_refs") << "5");
        const long start = status_kb("VmRSS");
        std::string message;
        try {
            message = f();
        } catch (const std::bad_alloc&) {
            message = "std::bad_alloc";
        } catch (const std::exception& e) {
            message = e.what();
        }
        const std::string out =
            std::to_string(reset && start >= 0 ? status_kb("VmHWM") - start : -1) + "\n" + message;
        if (write(fds[1], out.data(), out.size()) < 0) _exit(1);
        _exit(0);
    }
    close(fds[1]);
    std::string out;
    char buf[4096];
    for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;)
        out.append(buf, static_cast<size_t>(n));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    const size_t nl = out.find('\n');
    if (nl == std::string::npos) return {"no answer from the child"};
    return {out.substr(nl + 1), std::stol(out.substr(0, nl))};
}

// The message of decoding `data` as EXR, through both readers (all channels, and R, G and B),
// which must agree.
std::string exr_error(const std::string& data) {
    std::string all, rgb;
    try {
        (void)decode_exr(data);
        all = "no error";
    } catch (const std::exception& e) {
        all = e.what();
    }
    try {
        (void)decode_exr_rgb(data);
        rgb = "no error";
    } catch (const std::exception& e) {
        rgb = e.what();
    }
    EXPECT_EQ(all, rgb);
    return all;
}

// An EXR of `w`x`h` pixels in R, G, B and 13 more channels (16, as the issue's file), all 0.
std::string sixteen_channels(int w, int h) {
    std::vector<ExrChannel> extra;
    for (int i = 0; i < 13; ++i) {
        std::string name = "X";  // (GCC 12 -O3 warns of "X" + std::to_string as an overflow)
        name += std::to_string(i);
        extra.push_back(
            {name, ExrPixel::Half, std::vector<double>(static_cast<size_t>(w) * h, 0.0)});
    }
    const std::string path = ::testing::TempDir() + "/rt_sixteen.exr";
    save_exr(Image(w, h), extra, false, path);
    std::string data;
    EXPECT_TRUE(read_file(path, &data));
    std::filesystem::remove(path);
    return data;
}

uint32_t le32(std::string_view d, size_t at) {
    uint32_t v = 0;
    for (size_t i = 0; i < 4; ++i) v |= uint32_t{static_cast<uint8_t>(d[at + i])} << (8 * i);
    return v;
}

void put_le(std::string& d, size_t at, uint64_t v, size_t bytes) {
    for (size_t i = 0; i < bytes; ++i) d[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
}

// The header's data window made 0..w-1 x 0..h-1 (its box2i after "dataWindow\0box2i\0" and
// the size).
void set_data_window(std::string& exr, int w, int h) {
    const std::string key("dataWindow\0box2i\0", 17);
    const size_t at = exr.find(key);
    ASSERT_NE(at, std::string::npos);
    put_le(exr, at + key.size() + 4 + 8, static_cast<uint32_t>(w - 1), 4);
    put_le(exr, at + key.size() + 4 + 12, static_cast<uint32_t>(h - 1), 4);
}

// Where a single-part scan-line file's offset table starts: the first entry holds the offset
// just past a one-chunk table.
size_t offset_table(std::string_view exr) {
    for (size_t p = 8; p + 8 <= exr.size(); ++p)
        if (le32(exr, p) == p + 8 && le32(exr, p + 4) == 0) return p;
    ADD_FAILURE() << "no one-chunk offset table";
    return 0;
}

// Issue 49: an 835-byte EXR claiming 8192x8192 in 16 channels zero-filled 4.3 GB before
// reading a pixel. Here DWAB's 256 rows a chunk make its table 32 entries, which fit; they
// point into the header, and the chunks are not there. Refused from the table.
TEST(ImageDecode, AnExrClaimingMoreThanItHoldsIsRefusedWithoutAllocating) {
    const std::string real = sixteen_channels(16, 16);
    const size_t table = offset_table(real);
    std::string exr = real.substr(0, table);
    set_data_window(exr, 8192, 8192);
    const std::string key("compression\0compression\0", 24);
    ASSERT_NE(exr.find(key), std::string::npos);
    exr[exr.find(key) + key.size() + 4] = 9;  // DWAB
    exr.resize(table + 32 * 8);
    for (size_t i = 0; i < 32; ++i) put_le(exr, table + i * 8, 8 + i, 8);
    exr += real.substr(table + 8);  // the one real chunk
    const ChildRun run = in_child([&] { return exr_error(exr); });
    EXPECT_EQ(run.message, "EXR chunk 0 points at byte 8, outside the chunks' bytes " +
                               std::to_string(table + 32 * 8) + " to " +
                               std::to_string(exr.size()) +
                               " (a damaged offset table or a truncated file)");
    EXPECT_LT(run.grown_kb, 16 * 1024);
    std::cout << "[ measured ] " << exr.size() << "-byte EXR of 8192x8192x16: the decode grew "
              << run.grown_kb << " KB\n";
}

// An image of 8192x8192 with every chunk in its place, the first real and the other 511
// damaged: the image grows as its bands decode, so the 0.8 GB (1.6 GB as doubles) the header
// claims are never allocated; the first damaged chunk ends the read.
TEST(ImageDecode, AnExrWhoseChunksAreDamagedCostsWhatDecoded) {
    std::string real;  // one ZIP chunk of 16 rows
    {
        const std::string path = ::testing::TempDir() + "/rt_wide.exr";
        save_exr(Image(8192, 16), {}, false, path);
        ASSERT_TRUE(read_file(path, &real));
        std::filesystem::remove(path);
    }
    const size_t table = offset_table(real);
    const std::string_view chunk = std::string_view(real).substr(table + 8);
    std::string exr = real.substr(0, table);
    set_data_window(exr, 8192, 8192);
    const size_t first = exr.size() + 512 * 8;
    std::string chunks(chunk);
    exr.resize(first);
    put_le(exr, table, first, 8);
    for (uint64_t i = 1; i < 512; ++i) {
        put_le(exr, table + i * 8, first + chunks.size(), 8);
        std::string junk(8 + 64, '\x5a');
        put_le(junk, 0, i * 16, 4);  // its rows
        put_le(junk, 4, 64, 4);      // 64 bytes that are no zlib stream
        chunks += junk;
    }
    exr += chunks;
    const ChildRun run = in_child([&] { return exr_error(exr); });
    EXPECT_NE(run.message.find("zlib"), std::string::npos) << run.message;
    EXPECT_LT(run.grown_kb, 64 * 1024);
    std::cout << "[ measured ] " << exr.size() << "-byte EXR, 8192x8192 with 511 damaged "
              << "chunks: the decode grew " << run.grown_kb << " KB: " << run.message << "\n";
}

// The offset table is checked against the file: an entry beyond the end, or two chunks at the
// same place, are named before OpenEXR reads the table.
TEST(ImageDecode, AnExrOffsetTableIsCheckedAgainstTheFile) {
    const std::string real = sixteen_channels(4, 64);  // four ZIP chunks of 16 rows
    size_t table = 0;
    for (size_t p = 8; p + 32 <= real.size() && table == 0; ++p)
        if (le32(real, p) == p + 32 && le32(real, p + 4) == 0) table = p;
    ASSERT_NE(table, 0u);
    ASSERT_EQ(exr_error(real), "no error");
    std::string beyond = real;
    put_le(beyond, table + 24, real.size() + 100, 8);
    EXPECT_EQ(exr_error(beyond), "EXR chunk 3 points at byte " + std::to_string(real.size() + 100) +
                                     ", outside the chunks' bytes " + std::to_string(table + 32) +
                                     " to " + std::to_string(real.size()) +
                                     " (a damaged offset table or a truncated file)");
    std::string twice = real;
    put_le(twice, table + 16, le32(real, table + 8), 8);
    EXPECT_EQ(exr_error(twice), "EXR chunks overlap at byte " +
                                    std::to_string(le32(real, table + 8)) +
                                    " (a damaged offset table)");
    // The header's data window made 8192x8192: its 512 chunks' offsets alone would be 4 KB.
    std::string claims = real;
    set_data_window(claims, 8192, 8192);
    EXPECT_EQ(exr_error(claims),
              "the EXR header's 8192x8192 pixels are 512 chunks, whose offset "
              "table alone is larger than the " +
                  std::to_string(real.size()) + "-byte file (truncated or damaged)");
    // A table cut short (the file truncated after its header).
    EXPECT_EQ(exr_error(real.substr(0, table + 8)),
              "the EXR header's 4x64 pixels are 4 chunks, whose offset table alone is larger "
              "than the " +
                  std::to_string(table + 8) + "-byte file (truncated or damaged)");
}

// Issue 49: a 282-byte JPEG claiming 8192x8192 (grid.jpg, its frame header patched) cost
// 203 MB: the image was allocated before the data showed it. Its 1.5M blocks need at least
// 1.5M bits of Huffman-coded data; the file is refused from its headers, as is the progressive
// one (whose coefficients libjpeg allocated and zeroed for the whole image too).
TEST(ImageDecode, AJpegClaimingMoreThanItHoldsIsRefusedWithoutAllocating) {
    for (const char* name : {"jpeg_sof_8192_baseline.jpg", "jpeg_sof_8192_progressive.jpg"}) {
        std::string jpeg;
        ASSERT_TRUE(
            read_file(std::string(RT_SOURCE_DIR) + "/tests/fuzz/crashers/image/" + name, &jpeg));
        // The bytes after the first scan's header (FF DA, then its length).
        const size_t sos = jpeg.find("\xff\xda");
        ASSERT_NE(sos, std::string::npos);
        const size_t after = jpeg.size() - (sos + 2 +
                                            (static_cast<uint8_t>(jpeg[sos + 2]) << 8 |
                                             static_cast<uint8_t>(jpeg[sos + 3])));
        const ChildRun run = in_child([&] {
            TextureImage t;
            std::string error;
            return decode_texture(jpeg, &t, &error) ? std::string("no error") : error;
        });
        EXPECT_EQ(run.message,
                  "truncated JPEG image: 8192x8192 pixels need at least 196608 "
                  "bytes of compressed data, the file has " +
                      std::to_string(after) + " after its headers")
            << name;
        EXPECT_LT(run.grown_kb, 16 * 1024) << name;
        std::cout << "[ measured ] " << name << " (" << jpeg.size() << " bytes): the decode grew "
                  << run.grown_kb << " KB\n";
    }
    // The real files still decode (the check counts their blocks as libjpeg does).
    for (const char* name : {"grid.jpg", "grid_444.jpg", "grid_grey.jpg", "grid_progressive.jpg"})
        EXPECT_EQ(decoded(fixture(name)).width, 16) << name;
}

// Found by fuzz_image: OpenEXR allocated the 1.8 GB a string attribute declared before reading it.
TEST(ImageDecode, AnExrAttributeLongerThanTheFileIsRefused) {
    std::string exr;
    ASSERT_TRUE(read_file(
        std::string(RT_SOURCE_DIR) + "/tests/fuzz/crashers/image/exr_huge_string_attribute.exr",
        &exr));
    try {
        decode_exr(exr);
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "EXR attribute 'writer' of 1811939328 bytes beyond the file's end");
    }
}

// Issue 29: a FIFO named as a texture or a reference blocked the reader forever.
TEST(ImageDecode, AFifoIsRefusedWithoutWaiting) {
    const std::string fifo = ::testing::TempDir() + "/rt_image_fifo.pfm";
    std::filesystem::remove(fifo);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    TextureImage t;
    std::string error;
    EXPECT_FALSE(load_texture_image(fifo, &t, &error));
    EXPECT_EQ(error, "'" + fifo + "' is a FIFO, not a regular file");
    for (const auto& load : {+[](const std::string& p) { (void)load_pfm(p); },
                             +[](const std::string& p) { (void)load_exr(p); },
                             +[](const std::string& p) { (void)load_image(p); }}) {
        try {
            load(fifo);
            ADD_FAILURE() << "no error";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("is a FIFO, not a regular file"),
                      std::string::npos)
                << e.what();
        }
    }
    std::filesystem::remove(fifo);
}

TEST(ImageDecode, BadBmpFieldsAreNamed) {
    EXPECT_EQ(decode_error(bmp_header(4, 4, 8, 1)), "unsupported BMP compression (RLE8)");
    EXPECT_EQ(decode_error(bmp_header(4, 4, 4, 2)), "unsupported BMP compression (RLE4)");
    EXPECT_EQ(decode_error(bmp_header(4, 4, 24, 9)), "unknown BMP compression 9");
    EXPECT_EQ(decode_error(bmp_header(4, 4, 7)), "unsupported BMP depth of 7 bits");
    EXPECT_EQ(decode_error(bmp_header(0, 4)), "bad BMP size 0x4");
    EXPECT_EQ(decode_error(bmp_header(4, 4).substr(0, 30)), "truncated BMP header");
    // An index past a 2-colour table.
    std::string b = fixture("grid_4bit.bmp");
    b[46] = 2;  // two colours
    EXPECT_EQ(decode_error(b), "BMP pixel index 3 outside its colour table of 2");
    EXPECT_EQ(decode_error("P5 2 1 100\n\x10\x70"), "PNM sample 112 above its maximum 100");
    EXPECT_EQ(decode_error("P4 2 1\n\x10"), "unsupported PNM kind P4 (P2, P3, P5 and P6 are read)");
    EXPECT_EQ(decode_error("GIF89a"), "not a BMP, PNG, JPEG or PPM/PGM file");
}

// Issue 29: 30 #texture lines naming one 8192x8192 PNG decoded it 30 times (4 GB).
TEST(ImageDecode, ATextureFileIsDecodedOncePerScene) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(::testing::TempDir()) / "rt_texture_cache";
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    std::ofstream(dir / "tex.bmp", std::ios::binary) << fixture("grid.bmp");
    fs::create_symlink("tex.bmp", dir / "link.bmp");
    std::string top, inc;
    for (int i = 0; i < 30; ++i)
        top += "#texture " + std::string(i % 2 ? "tex.bmp\n" : "./tex.bmp\n");
    top += "#texture sub/../link.bmp\n#ray_file inc.ray\n";
    std::ofstream(dir / "top.ray") << top;
    std::ofstream(dir / "sub" / "inc.ray") << "#texture ../tex.bmp\n";
    std::ofstream(dir / "inc.ray") << "#texture tex.bmp\n";
    Diagnostics diag;
    const SceneDesc s = parse_scene_file((dir / "top.ray").string(), diag);
    ASSERT_EQ(s.files.size(), 2u);
    ASSERT_EQ(s.files[0].textures.size(), 31u);
    const TextureImage* first = s.files[0].textures[0].image.get();
    ASSERT_NE(first, nullptr);
    EXPECT_EQ(first->width, 16);
    for (const TextureDesc& t : s.files[0].textures) EXPECT_EQ(t.image.get(), first) << t.path;
    EXPECT_EQ(s.files[1].textures[0].image.get(), first);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace rt
