// OpenEXR files: linear RGB in half or float, plus extra channels (the render's AOVs,
// rt/render/aov.h). Row 0 is the top row (spec §9; EXR's increasing-y line order), the data
// window is the whole image, compression ZIP (lossless, 16 scanlines per block).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "rt/image/image.h"

namespace rt {

/// A channel's pixel type in the file. Half: 16-bit float, written as 32-bit float when the
/// whole file is (save_exr's full_float); Float: always 32-bit float; Uint: 32-bit unsigned.
enum class ExrPixel { Half, Float, Uint };

/// One channel: a name ("Albedo.R": the part before the last dot names the layer viewers show)
/// and one value per pixel, row-major from the top.
struct ExrChannel {
    std::string name;
    ExrPixel type = ExrPixel::Half;
    std::vector<double> values;
};

/// Writes R, G, B (from `rgb`) and the extra channels to an EXR file: half, or 32-bit float with
/// full_float. RGB values that are not finite are written as 0 (spec §9, as save_image does);
/// in the extra channels NaN is written as 0 and infinities stay (a depth of +inf: no hit).
/// Finite values beyond half's range are written as +-65504 (half's largest), never as
/// infinities. Uint channels take values rounded and clamped to [0, 2^32 - 1]. Writes to a
/// temporary file in the same directory and renames it: a failed write leaves no file. Throws
/// std::runtime_error when a channel has the wrong size, a name twice or R, G or B, or when
/// the file cannot be written.
void save_exr(const Image& rgb, const std::vector<ExrChannel>& extra, bool full_float,
              const std::string& path);

/// An EXR file read back: every channel as stored (its type as in the file, its values
/// converted to double exactly), in the file's order (by name).
struct ExrImage {
    int width = 0;
    int height = 0;
    std::vector<ExrChannel> channels;

    /// The channel of that name, or nullptr.
    const ExrChannel* find(const std::string& name) const;
    /// R, G and B as an Image. Throws std::runtime_error when one of them is missing.
    Image rgb() const;
};

/// Reads an EXR file (scanline or tiled, any compression; the data window's size). Throws
/// std::runtime_error when it is not a regular file, cannot be decoded, or is larger than the
/// image budget (max_image_pixels(); its channels' values beyond 16 times the budget), which is
/// checked before the pixels are allocated. The file's chunk offset tables are checked against
/// its bytes before OpenEXR reads them (a table or chunk beyond the file's end, or chunks that
/// overlap, are refused), and the pixels are read in bands: the image grows as its chunks
/// decode, so a file that claims more than it holds costs little.
ExrImage load_exr(const std::string& path);
/// The same from the file's bytes in memory (the fuzz target's entry).
ExrImage decode_exr(std::string_view data);

/// R, G and B of an EXR file, as load_exr(path).rgb() but without reading the other channels
/// (load_image's, hence the comparisons').
Image load_exr_rgb(const std::string& path);
/// The same from the file's bytes in memory.
Image decode_exr_rgb(std::string_view data);

}  // namespace rt
