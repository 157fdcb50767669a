// The image decoders, working on a file's bytes in memory (load_texture_image() and load_pfm()
// read the file with read_file() and call them; the fuzz target calls them directly).
//
// Every decoder checks the size the header declares against the image budget
// (rt/util/limits.h) and against the bytes that follow it before it allocates, so a short or
// lying file is an error naming the size, never a huge allocation or uninitialised pixels.
// Which decoder reads what:
//   BMP and PNM (PPM/PGM): our own strict decoders, in every build.
//   PNG and JPEG: Debian's libpng and libjpeg-turbo on the desktop (kept patched by the
//     distribution); the web page, which has neither, uses stb_image restricted to PNG and JPEG
//     behind checks of our own (decode_png_jpeg_stb), as stb's snapshot in Debian lacks
//     upstream's fixes for malformed files.
#pragma once

#include <string>
#include <string_view>

#include "rt/image/image.h"

namespace rt {

/// The formats a texture may have, as told by the first bytes of the file (never its name).
enum class TextureFormat { Bmp, Pnm, Png, Jpeg, Unknown };
TextureFormat sniff_texture_format(std::string_view data);

/// Decodes a texture file's bytes into 8-bit RGB (alpha dropped, grey replicated: spec §7.3).
/// False with the reason in *error (which does not name the file) when it cannot.
bool decode_texture(std::string_view data, TextureImage* out, std::string* error);

/// BMP: uncompressed 1, 4, 8, 16, 24 and 32 bits per pixel (with or without bit-field masks),
/// bottom-up or top-down; RLE compression is refused with a message.
bool decode_bmp(std::string_view data, TextureImage* out, std::string* error);
/// PNM: P2, P3 (ASCII) and P5, P6 (binary) grey and colour maps, maxval up to 65535.
bool decode_pnm(std::string_view data, TextureImage* out, std::string* error);
/// PNG and JPEG: libpng and libjpeg-turbo on the desktop, decode_png_jpeg_stb() on the web.
bool decode_png(std::string_view data, TextureImage* out, std::string* error);
bool decode_jpeg(std::string_view data, TextureImage* out, std::string* error);
/// PNG or JPEG through stb_image, after our own checks of the structure (every PNG chunk length
/// and the IEND; every JPEG segment length, every Huffman table and the EOI) and of the size.
/// The web page's decoder; compiled in every build so that the fuzz target exercises it.
bool decode_png_jpeg_stb(std::string_view data, TextureImage* out, std::string* error);

/// PFM (3-channel, little-endian, as save_image writes it) into linear RGB.
bool decode_pfm(std::string_view data, Image* out, std::string* error);

}  // namespace rt
