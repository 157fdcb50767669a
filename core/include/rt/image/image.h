// Images: linear float RGB in memory, 8-bit texture images, and reading/writing PNG, BMP, PPM,
// JPEG (read), PFM (float) and OpenEXR (half or float; with extra channels: rt/image/exr.h).
// Row 0 is the top row everywhere (spec §9). The decoders, and which library reads which format:
// rt/image/decode.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rt/util/math.h"

namespace rt {

/// A linear, unclamped RGB image. Values stay double until they are written, so the 8-bit
/// rounding of spec §9 sees the exact mean.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<double> rgb;  // 3 values per pixel, row-major from the top

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(w) * h * 3, 0.0) {}
    Vec3 at(int x, int y) const {
        const size_t i = (static_cast<size_t>(y) * width + x) * 3;
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
    void set(int x, int y, const Vec3& c) {
        const size_t i = (static_cast<size_t>(y) * width + x) * 3;
        rgb[i] = c.x;
        rgb[i + 1] = c.y;
        rgb[i + 2] = c.z;
    }
};

/// An 8-bit RGB texture as decoded from a file (alpha dropped, grey replicated).
struct TextureImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgb;
};

/// Spec §9: byte = floor(255 * clamp(c, 0, 1) + 0.5); non-finite values become 0.
uint8_t to_byte(double c);

/// The image as 8-bit RGB, each value through to_byte() (what PNG, BMP and PPM files hold).
std::vector<uint8_t> to_bytes(const Image& image);

/// Reads a regular file (read_file) and decodes it: BMP, PNG, JPEG or PPM/PGM (binary and
/// ASCII), told by its content, not its name (decode_texture). Returns false and sets *error on
/// failure; an image larger than the budget (max_image_pixels) or a file shorter than its header
/// says is refused before the pixels are allocated.
bool load_texture_image(const std::string& path, TextureImage* out, std::string* error);

/// The stand-in for a texture that cannot be opened or decoded (--missing-textures checker): a
/// loud magenta and grey checker of 8x8 squares on a 64x64 image, magenta at the top left.
TextureImage checker_texture();

/// Image file kinds chosen by extension.
enum class ImageFormat { Png, Bmp, Ppm, Pfm, Exr, Unknown };
ImageFormat image_format_from_path(const std::string& path);
/// PFM and EXR files hold linear, unclamped values (what the render computed); the others 8-bit
/// values after display_transform() (spec §9's clamp by default).
inline bool holds_linear(ImageFormat f) { return f == ImageFormat::Pfm || f == ImageFormat::Exr; }

/// Writes the image; throws std::runtime_error on failure. Non-finite values are written as 0
/// (spec §9; count_non_finite() tells the caller how many there were). Writes to a temporary file
/// in the same directory and renames it, so a failed write never leaves a partial file. PFM and
/// EXR keep linear, unclamped values (EXR: half RGB; save_exr() writes float and more channels).
void save_image(const Image& image, const std::string& path);

/// Reads a PFM written by save_image (or any 3-channel PFM). Throws std::runtime_error, also when
/// the header's size is beyond the budget or beyond the bytes the file holds.
Image load_pfm(const std::string& path);

/// Reads any image as linear RGB: PFM and EXR (its R, G, B channels) as stored, the 8-bit
/// formats of load_texture_image() as byte / 255. Throws std::runtime_error.
Image load_image(const std::string& path);

/// How an image is shown and written to 8-bit files: Clamp is spec §9's (what raytrace writes),
/// Reinhard c / (1 + c), Aces a filmic curve (Narkowicz's fit).
enum class Tonemap { Clamp, Reinhard, Aces };

/// The image scaled by 2^exposure_stops and tonemapped, for display and 8-bit output (float
/// outputs stay linear). Clamp with 0 stops returns the image unchanged.
Image display_transform(const Image& linear, double exposure_stops, Tonemap tonemap);

/// Number of non-finite values in the image (spec §9: must not occur).
size_t count_non_finite(const Image& image);

}  // namespace rt
