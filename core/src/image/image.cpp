#include "rt/image/image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "rt/image/exr.h"
#include "rt/util/file_io.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_FAILURE_USERMSG
#include <stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

namespace rt {

uint8_t to_byte(double c) {
    if (!std::isfinite(c)) return 0;
    c = std::clamp(c, 0.0, 1.0);
    return static_cast<uint8_t>(std::floor(255.0 * c + 0.5));
}

// ASCII PNM (P2 grey, P3 colour), which stb_image does not read. Returns false if not one.
static bool load_ascii_pnm(const std::string& path, TextureImage* out, std::string* error) {
    std::ifstream f(path, std::ios::binary);
    std::string magic;
    if (!(f >> magic) || (magic != "P2" && magic != "P3")) return false;
    const int channels = magic == "P3" ? 3 : 1;
    auto next = [&](long* v) {
        // Skips '#' comments between values.
        for (;;) {
            f >> std::ws;
            if (f.peek() == '#') {
                std::string line;
                std::getline(f, line);
                continue;
            }
            return static_cast<bool>(f >> *v);
        }
    };
    long w = 0, h = 0, maxval = 0;
    if (!next(&w) || !next(&h) || !next(&maxval) || w <= 0 || h <= 0 || w > (1L << 16) ||
        h > (1L << 16) || maxval <= 0 || maxval > 65535) {
        *error = "bad ASCII PNM header";
        return true;
    }
    // Every value takes at least two bytes (a digit and a separator): a header that promises
    // more than the file holds is refused before anything is allocated.
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    if (ec || static_cast<unsigned long long>(w * h * channels) > bytes / 2 + 1) {
        *error = "ASCII PNM header promises more values than the file holds";
        return true;
    }
    out->width = static_cast<int>(w);
    out->height = static_cast<int>(h);
    out->rgb.resize(static_cast<size_t>(w * h * 3));
    for (long i = 0; i < w * h; ++i) {
        long c[3] = {0, 0, 0};
        for (int k = 0; k < channels; ++k)
            if (!next(&c[k]) || c[k] < 0 || c[k] > maxval) {
                *error = "truncated or bad ASCII PNM data";
                out->width = 0;
                return true;
            }
        for (int k = 0; k < 3; ++k)
            out->rgb[static_cast<size_t>(i * 3 + k)] =
                static_cast<uint8_t>((c[channels == 3 ? k : 0] * 255 + maxval / 2) / maxval);
    }
    return true;
}

bool load_texture_image(const std::string& path, TextureImage* out, std::string* error) {
    if (load_ascii_pnm(path, out, error)) return out->width > 0;
    int w = 0, h = 0, n = 0;
    // A header may promise far more pixels than the file holds (compressed formats): refuse
    // textures above 2^26 pixels (8192 x 8192) before decoding.
    if (stbi_info(path.c_str(), &w, &h, &n) && static_cast<long long>(w) * h > (1LL << 26)) {
        std::string e = "texture of ";
        e += std::to_string(w);
        e += "x";
        e += std::to_string(h);
        e += " pixels is larger than the limit of 2^26 pixels";
        *error = std::move(e);
        return false;
    }
    // Ask for 3 channels: stb replicates grey and drops alpha, as spec §7.3 wants.
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 3);
    if (!data) {
        *error = stbi_failure_reason() ? stbi_failure_reason() : "unknown decoder error";
        return false;
    }
    out->width = w;
    out->height = h;
    out->rgb.assign(data, data + static_cast<size_t>(w) * h * 3);
    stbi_image_free(data);
    return true;
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
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("cannot open '" + path + "'");
    std::string magic;
    int w = 0, h = 0;
    double scale = 0.0;
    f >> magic >> w >> h >> scale;
    f.get();  // the single whitespace byte after the header
    if (magic != "PF" || w <= 0 || h <= 0 || w > (1 << 16) || h > (1 << 16) || scale == 0.0)
        throw std::runtime_error("'" + path + "' is not a 3-channel PFM file of a sensible size");
    if (scale > 0) throw std::runtime_error("'" + path + "': big-endian PFM is not supported");
    Image image(w, h);
    const size_t row_floats = static_cast<size_t>(w) * 3;
    std::vector<float> row(row_floats);
    for (int y = h - 1; y >= 0; --y) {
        f.read(reinterpret_cast<char*>(row.data()),
               static_cast<std::streamsize>(row_floats * sizeof(float)));
        for (size_t i = 0; i < row_floats; ++i)
            image.rgb[static_cast<size_t>(y) * row_floats + i] = static_cast<double>(row[i]);
    }
    if (!f) throw std::runtime_error("'" + path + "' is truncated");
    return image;
}

Image load_image(const std::string& path) {
    const ImageFormat format = image_format_from_path(path);
    if (format == ImageFormat::Pfm) return load_pfm(path);
    if (format == ImageFormat::Exr) return load_exr(path).rgb();
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
