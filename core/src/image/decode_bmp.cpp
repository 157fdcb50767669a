// BMP textures (the course's format): uncompressed Windows and OS/2 bitmaps. Every header field
// is checked, and the pixel data the header declares against the bytes the file holds, before
// anything is allocated.
#include <bit>
#include <cstdint>

#include "image/decode_util.h"
#include "rt/image/decode.h"

namespace rt {

namespace {

using decode_impl::fail;
using decode_impl::le16;
using decode_impl::le32;

constexpr uint32_t kRgb = 0, kRle8 = 1, kRle4 = 2, kBitFields = 3, kJpeg = 4, kPng = 5,
                   kAlphaBitFields = 6;

// One channel of a bit-field pixel: its mask's position and width, and the way to 8 bits.
struct Channel {
    uint32_t shift = 0;
    uint32_t max = 0;  // the largest value of the field: 2^bits - 1
    int bits = 0;

    // A field of fewer than 8 bits has its bits repeated to fill 8 (5 bits abcde: abcdeabc), as
    // the readers before this one (stb_image) and most others do: 0 stays 0 and max becomes 255.
    // A wider field keeps its top 8 bits.
    uint8_t get(uint32_t pixel) const {
        const uint32_t v = (pixel >> shift) & max;
        if (bits >= 8) return static_cast<uint8_t>(v >> (bits - 8));
        uint32_t out = 0;
        int filled = 0;
        for (; filled < 8; filled += bits) out = (out << bits) | v;
        return static_cast<uint8_t>(out >> (filled - 8));
    }
};

// A mask must be one run of set bits within the pixel's bits.
bool channel_of(uint32_t mask, uint32_t bpp, Channel* c) {
    if (mask == 0 || (bpp < 32 && mask >> bpp != 0)) return false;
    c->shift = static_cast<uint32_t>(std::countr_zero(mask));
    c->max = mask >> c->shift;
    c->bits = std::popcount(c->max);
    return (c->max & (c->max + 1)) == 0;
}

struct Header {
    uint32_t header_size = 0;
    uint64_t width = 0, height = 0;
    bool top_down = false;
    uint32_t bpp = 0, compression = kRgb, colours = 0;
    uint32_t masks[3] = {0, 0, 0};  // red, green, blue
    size_t palette_at = 0;          // offset of the colour table
    uint32_t palette_entry = 4;     // bytes per colour: 3 in OS/2 1.x files
    size_t pixels_at = 0;
};

const char* compression_name(uint32_t c) {
    switch (c) {
        case kRle8:
            return "RLE8";
        case kRle4:
            return "RLE4";
        case kJpeg:
            return "JPEG";
        case kPng:
            return "PNG";
        default:
            return nullptr;
    }
}

bool read_header(std::string_view d, Header* h, std::string* error) {
    if (d.size() < 18) return fail(error, "truncated BMP header");
    h->pixels_at = le32(d, 10);
    h->header_size = le32(d, 14);
    const uint32_t hs = h->header_size;
    if (hs != 12 && hs != 40 && hs != 52 && hs != 56 && hs != 108 && hs != 124)
        return fail(error, "unsupported BMP header size " + std::to_string(hs));
    if (d.size() < 14 + size_t{hs}) return fail(error, "truncated BMP header");
    uint32_t planes = 0;
    if (hs == 12) {  // OS/2 1.x: 16-bit sides, 3-byte colours
        h->width = le16(d, 18);
        h->height = le16(d, 20);
        planes = le16(d, 22);
        h->bpp = le16(d, 24);
        h->palette_entry = 3;
    } else {
        const auto w = static_cast<int32_t>(le32(d, 18));
        const auto height = static_cast<int32_t>(le32(d, 22));
        if (w <= 0 || height == 0 || height == INT32_MIN)
            return fail(error, "bad BMP size " + std::to_string(w) + "x" + std::to_string(height));
        h->width = static_cast<uint64_t>(w);
        h->top_down = height < 0;  // a negative height: rows from the top
        h->height = static_cast<uint64_t>(height < 0 ? -int64_t{height} : int64_t{height});
        planes = le16(d, 26);
        h->bpp = le16(d, 28);
        h->compression = le32(d, 30);
        h->colours = le32(d, 46);
    }
    if (planes != 1) return fail(error, "bad BMP plane count " + std::to_string(planes));
    const uint32_t b = h->bpp;
    if (b != 1 && b != 4 && b != 8 && b != 16 && b != 24 && b != 32)
        return fail(error, "unsupported BMP depth of " + std::to_string(b) + " bits");
    size_t after = 14 + size_t{hs};
    if (h->compression == kBitFields || h->compression == kAlphaBitFields) {
        if (b != 16 && b != 32)
            return fail(error, "BMP bit fields with " + std::to_string(b) + " bits per pixel");
        // The masks follow a 40-byte header, and are part of the longer ones.
        if (hs == 40) after += h->compression == kBitFields ? 12 : 16;
        if (d.size() < after) return fail(error, "truncated BMP header");
        for (size_t k = 0; k < 3; ++k) h->masks[k] = le32(d, 54 + 4 * k);
    } else if (h->compression != kRgb) {
        const char* name = compression_name(h->compression);
        return fail(error, name ? std::string("unsupported BMP compression (") + name + ")"
                                : "unknown BMP compression " + std::to_string(h->compression));
    } else if (b == 16) {  // 5-5-5
        h->masks[0] = 0x7C00;
        h->masks[1] = 0x03E0;
        h->masks[2] = 0x001F;
    } else if (b == 32) {
        h->masks[0] = 0x00FF0000;
        h->masks[1] = 0x0000FF00;
        h->masks[2] = 0x000000FF;
    }
    if (b <= 8) {
        if (h->colours == 0) h->colours = 1u << b;
        if (h->colours > (1u << b))
            return fail(error, "BMP colour table of " + std::to_string(h->colours) +
                                   " entries for " + std::to_string(b) + " bits per pixel");
        h->palette_at = after;
        after += size_t{h->colours} * h->palette_entry;
    }
    if (h->pixels_at < after || h->pixels_at > d.size())
        return fail(error, "BMP pixel data offset " + std::to_string(h->pixels_at) +
                               " outside the file (header and colours end at " +
                               std::to_string(after) + ", the file has " +
                               std::to_string(d.size()) + " bytes)");
    return true;
}

// Decodes one row of `width` pixels from `src` into RGB at `dst`. False when an index is outside
// the colour table.
bool decode_row(std::string_view d, const Header& h, const Channel* ch, const uint8_t* src,
                uint8_t* dst, std::string* error) {
    for (uint64_t x = 0; x < h.width; ++x, dst += 3) {
        if (h.bpp <= 8) {
            const uint64_t bit = x * h.bpp;
            const uint32_t shift = 8 - h.bpp - static_cast<uint32_t>(bit % 8);
            const uint32_t index = (src[bit / 8] >> shift) & ((1u << h.bpp) - 1);
            if (index >= h.colours)
                return fail(error, "BMP pixel index " + std::to_string(index) +
                                       " outside its colour table of " + std::to_string(h.colours));
            const size_t at = h.palette_at + size_t{index} * h.palette_entry;  // B, G, R
            dst[0] = static_cast<uint8_t>(d[at + 2]);
            dst[1] = static_cast<uint8_t>(d[at + 1]);
            dst[2] = static_cast<uint8_t>(d[at]);
        } else if (h.bpp == 24) {
            const uint8_t* p = src + x * 3;
            dst[0] = p[2];
            dst[1] = p[1];
            dst[2] = p[0];
        } else {
            const uint8_t* p = src + x * (h.bpp / 8);
            uint32_t pixel = p[0] | uint32_t{p[1]} << 8;
            if (h.bpp == 32) pixel |= uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
            for (size_t k = 0; k < 3; ++k) dst[k] = ch[k].get(pixel);
        }
    }
    return true;
}

}  // namespace

bool decode_bmp(std::string_view d, TextureImage* out, std::string* error) {
    if (d.size() < 2 || d[0] != 'B' || d[1] != 'M') return fail(error, "not a BMP file");
    Header h;
    if (!read_header(d, &h, error)) return false;
    Channel ch[3];
    if (h.bpp == 16 || h.bpp == 32)
        for (size_t k = 0; k < 3; ++k)
            if (!channel_of(h.masks[k], h.bpp, &ch[k]))
                return fail(error, "bad BMP bit-field mask " + std::to_string(h.masks[k]));
    if (!decode_impl::check_size(h.width, h.height, "BMP image", error)) return false;
    // Rows are padded to 4 bytes.
    const uint64_t stride = (h.width * h.bpp + 31) / 32 * 4;
    if (!decode_impl::check_length(stride * h.height, d.size() - h.pixels_at, h.width, h.height,
                                   "BMP", error))
        return false;
    decode_impl::start_image(out, h.width, h.height);
    const auto* pixels = reinterpret_cast<const uint8_t*>(d.data()) + h.pixels_at;
    for (uint64_t row = 0; row < h.height; ++row) {
        const uint64_t y = h.top_down ? row : h.height - 1 - row;  // row 0 is the top
        if (!decode_row(d, h, ch, pixels + row * stride, &out->rgb[y * h.width * 3], error)) {
            *out = TextureImage();
            return false;
        }
    }
    return true;
}

}  // namespace rt
