#include "rt/image/image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "rt/image/decode.h"
#include "rt/image/exr.h"
#include "rt/render/mistakes.h"
#include "rt/util/file_io.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
// GCC's -O3 sees stb's PNG writer index an allocation it cannot prove non-null (stb checks it).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace rt {

uint8_t to_byte(double c) {
    if (!std::isfinite(c)) return 0;
    c = std::clamp(c, 0.0, 1.0);
    return static_cast<uint8_t>(std::floor(255.0 * c + 0.5));
}

TextureFormat sniff_texture_format(std::string_view d) {
    const auto byte = [&](size_t i) { return i < d.size() ? static_cast<uint8_t>(d[i]) : 0; };
    if (byte(0) == 'B' && byte(1) == 'M') return TextureFormat::Bmp;
    if (byte(0) == 'P' && byte(1) >= '1' && byte(1) <= '7') return TextureFormat::Pnm;
    if (d.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) return TextureFormat::Png;
    if (byte(0) == 0xFF && byte(1) == 0xD8 && byte(2) == 0xFF) return TextureFormat::Jpeg;
    return TextureFormat::Unknown;
}

bool decode_texture(std::string_view data, TextureImage* out, std::string* error) {
    switch (sniff_texture_format(data)) {
        case TextureFormat::Bmp:
            return decode_bmp(data, out, error);
        case TextureFormat::Pnm:
            return decode_pnm(data, out, error);
        case TextureFormat::Png:
            return decode_png(data, out, error);
        case TextureFormat::Jpeg:
            return decode_jpeg(data, out, error);
        case TextureFormat::Unknown:
            break;
    }
    *error = "not a BMP, PNG, JPEG or PPM/PGM file";
    return false;
}

bool load_texture_image(const std::string& path, TextureImage* out, std::string* error) {
    std::string data;
    if (!read_file(path, &data, error)) return false;
    return decode_texture(data, out, error);
}

TextureImage checker_texture() {
    constexpr int kSize = 64, kSquare = 8;
    TextureImage t;
    t.width = t.height = kSize;
    t.rgb.resize(static_cast<size_t>(kSize) * kSize * 3);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const bool magenta = ((x / kSquare) + (y / kSquare)) % 2 == 0;
            uint8_t* p = &t.rgb[(static_cast<size_t>(y) * kSize + x) * 3];
            p[0] = magenta ? 255 : 128;
            p[1] = magenta ? 0 : 128;
            p[2] = magenta ? 255 : 128;
        }
    return t;
}

ImageFormat image_format_from_path(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".bmp") return ImageFormat::Bmp;
    if (ext == ".ppm") return ImageFormat::Ppm;
    if (ext == ".pfm") return ImageFormat::Pfm;
    if (ext == ".exr") return ImageFormat::Exr;
    return ImageFormat::Unknown;
}

std::vector<uint8_t> to_bytes(const Image& image) {
    std::vector<uint8_t> bytes(image.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = to_byte(image.rgb[i]);
    return bytes;
}

// The output stage's mistakes (rt/render/mistakes.h), each a switch of spec §9's 8 bits:
// to_byte()'s clamp and rounding, the order of the channels and of the rows.
std::vector<uint8_t> to_bytes(const Image& image, const MistakeSet& mistakes) {
    const bool gamma = mistakes.has(Mistake::Gamma), wrap = mistakes.has(Mistake::WrapOverflow);
    auto byte = [&](double c) -> uint8_t {
        if (!std::isfinite(c)) return 0;
        if (wrap) {  // no clamp: floor(255 c + 0.5) mod 256
            const double b = std::floor(255.0 * c + 0.5);
            if (!(std::abs(b) < 9.0e15)) return 0;
            return static_cast<uint8_t>(static_cast<int64_t>(b) & 0xff);
        }
        c = std::clamp(c, 0.0, 1.0);
        if (gamma) c = std::pow(c, 1.0 / 2.2);  // an sRGB-like transfer before the 8 bits
        return static_cast<uint8_t>(std::floor(255.0 * c + 0.5));
    };
    const size_t w = static_cast<size_t>(image.width), h = static_cast<size_t>(image.height);
    std::vector<uint8_t> bytes(image.rgb.size());
    for (size_t y = 0; y < h; ++y) {
        // flip-vertical: the rows written bottom-up.
        const size_t out_y = mistakes.has(Mistake::FlipVertical) ? h - 1 - y : y;
        for (size_t x = 0; x < w; ++x)
            for (size_t k = 0; k < 3; ++k) {
                const size_t out_k =
                    mistakes.has(Mistake::Bgr) ? 2 - k : k;  // red and blue swapped
                bytes[(out_y * w + x) * 3 + out_k] = byte(image.rgb[(y * w + x) * 3 + k]);
            }
    }
    return bytes;
}

Image as_written(const Image& image, const MistakeSet& mistakes) {
    const std::vector<uint8_t> bytes = to_bytes(image, mistakes);
    Image out(image.width, image.height);
    for (size_t i = 0; i < bytes.size(); ++i) out.rgb[i] = bytes[i] / 255.0;
    return out;
}

// The encoded file of each format, in memory; save_image() writes it atomically.
static std::string encode_pfm(const Image& image) {
    // PFM stores rows bottom-to-top; a negative scale means little-endian floats.
    std::string data =
        "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
    const size_t row_floats = static_cast<size_t>(image.width) * 3;
    std::vector<float> row(row_floats);
    for (int y = image.height - 1; y >= 0; --y) {
        for (size_t i = 0; i < row_floats; ++i) {
            const double v = image.rgb[static_cast<size_t>(y) * row_floats + i];
            row[i] = std::isfinite(v) ? static_cast<float>(v) : 0.0f;  // spec §9
        }
        data.append(reinterpret_cast<const char*>(row.data()), row_floats * sizeof(float));
    }
    return data;
}

static std::string encode_ppm(const Image& image) {
    const std::vector<uint8_t> bytes = to_bytes(image);
    std::string data =
        "P6\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
    data.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    return data;
}

// PNG or BMP through stb, into memory (stb's own file writers ignore write errors: a full disk
// gave a truncated file reported as written).
static std::string encode_stb(const Image& image, ImageFormat format, const std::string& path) {
    const std::vector<uint8_t> bytes = to_bytes(image);
    std::string encoded;
    auto append = [](void* ctx, void* data, int size) {
        static_cast<std::string*>(ctx)->append(static_cast<const char*>(data),
                                               static_cast<size_t>(size));
    };
    const int ok =
        format == ImageFormat::Png
            ? stbi_write_png_to_func(append, &encoded, image.width, image.height, 3, bytes.data(),
                                     image.width * 3)
            : stbi_write_bmp_to_func(append, &encoded, image.width, image.height, 3, bytes.data());
    if (!ok) throw std::runtime_error("cannot encode '" + path + "'");
    return encoded;
}

void save_image(const Image& image, const std::string& path) {
    const ImageFormat format = image_format_from_path(path);
    if (format == ImageFormat::Unknown)
        throw std::runtime_error("unknown image format for '" + path +
                                 "' (use .png, .bmp, .ppm, .pfm or .exr)");
    if (format == ImageFormat::Exr) return save_exr(image, {}, false, path);
    // A temporary file renamed at the end: a failed run leaves no partial output file.
    write_file_atomic(path, format == ImageFormat::Pfm   ? encode_pfm(image)
                            : format == ImageFormat::Ppm ? encode_ppm(image)
                                                         : encode_stb(image, format, path));
}

Image load_pfm(const std::string& path) {
    std::string data, error;
    if (!read_file(path, &data, &error)) throw std::runtime_error(error);
    Image image;
    if (!decode_pfm(data, &image, &error))
        throw std::runtime_error("cannot read '" + path + "': " + error);
    return image;
}

Image load_image(const std::string& path) {
    const ImageFormat format = image_format_from_path(path);
    if (format == ImageFormat::Pfm) return load_pfm(path);
    if (format == ImageFormat::Exr) return load_exr_rgb(path);  // R, G and B alone
    TextureImage t;
    std::string error;
    if (!load_texture_image(path, &t, &error))
        throw std::runtime_error("cannot read '" + path + "': " + error);
    Image image(t.width, t.height);
    for (size_t i = 0; i < t.rgb.size(); ++i) image.rgb[i] = t.rgb[i] / 255.0;
    return image;
}

Image display_transform(const Image& linear, double exposure_stops, Tonemap tonemap) {
    const double scale = std::exp2(exposure_stops);
    Image out = linear;
    for (double& c : out.rgb) {
        const double x = c * scale;
        switch (tonemap) {
            case Tonemap::Clamp:
                c = x;  // to_byte() clamps
                break;
            case Tonemap::Reinhard:
                c = x > 0 ? x / (1 + x) : 0.0;
                break;
            case Tonemap::Aces:  // Narkowicz's fit of the ACES filmic curve
                c = x > 0 ? std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0,
                                       1.0)
                          : 0.0;
                break;
        }
    }
    return out;
}

size_t count_non_finite(const Image& image) {
    size_t n = 0;
    for (double v : image.rgb) n += std::isfinite(v) ? 0 : 1;
    return n;
}

}  // namespace rt
