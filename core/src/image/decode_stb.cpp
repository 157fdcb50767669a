// PNG and JPEG through stb_image, for the web page (no libpng or libjpeg there). Debian's stb
// snapshot (2022) lacks upstream's later fixes for malformed files (a JPEG Huffman table whose
// counts sum past 256 writes out of bounds in stbi__build_huffman), so stb only ever sees a file
// that passed checks of ours first: its structure walked (PNG: every chunk's length and CRC, the
// IHDR first and the IEND last; JPEG: every segment's length, every Huffman table's counts
// against the code space, a frame before the first scan, every table a scan uses defined and the
// EOI at the end) and its size
// checked against the budget. stb is built for PNG and JPEG only, from memory only. Compiled in
// every build, so that the fuzz target exercises it on the desktop too.
#include <array>
#include <cstring>
#include <memory>

#include "image/decode_util.h"
#include "rt/image/decode.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_FAILURE_USERMSG
#include <stb_image.h>

namespace rt {

namespace {

using decode_impl::be16;
using decode_impl::be32;
using decode_impl::fail;

// ---- PNG
// -----------------------------------------------------------------------------------------

// The CRC-32 of PNG chunks (ISO 3309; the table of PNG's specification, annex D).
uint32_t crc32(std::string_view bytes) {
    static const std::array<uint32_t, 256> table = [] {
        std::array<uint32_t, 256> t{};
        for (uint32_t n = 0; n < 256; ++n) {
            uint32_t c = n;
            for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[n] = c;
        }
        return t;
    }();
    uint32_t c = 0xFFFFFFFFu;
    for (const char b : bytes) c = table[(c ^ static_cast<uint8_t>(b)) & 0xFF] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

// Walks the chunks: lengths within the file, CRCs right, IHDR first, IDAT present, IEND last.
bool check_png(std::string_view d, uint32_t* w, uint32_t* h, std::string* error) {
    size_t pos = 8;  // after the signature
    bool idat = false;
    for (int index = 0;; ++index) {
        if (d.size() - pos < 12) return fail(error, "truncated PNG (no IEND chunk)");
        const uint32_t length = be32(d, pos);
        if (length > 0x7FFFFFFFu || length > d.size() - pos - 12)
            return fail(error, "truncated PNG: a chunk of " + std::to_string(length) +
                                   " bytes at offset " + std::to_string(pos));
        const std::string_view type = d.substr(pos + 4, 4);
        if (crc32(d.substr(pos + 4, 4 + size_t{length})) != be32(d, pos + 8 + length))
            return fail(error, "PNG chunk " + std::string(type) + " has a bad CRC");
        if ((index == 0) != (type == "IHDR"))
            return fail(error, "PNG file without an IHDR chunk first");
        if (type == "IHDR") {
            if (length != 13) return fail(error, "bad PNG IHDR chunk");
            *w = be32(d, pos + 8);
            *h = be32(d, pos + 12);
        }
        idat |= type == "IDAT";
        pos += 12 + size_t{length};
        if (type == "IEND") break;
    }
    return idat || fail(error, "PNG file without image data");
}

// ---- JPEG
// ----------------------------------------------------------------------------------------

// The Huffman tables a file has defined so far: [class: 0 DC, 1 AC][slot].
using HuffmanTables = std::array<std::array<bool, 4>, 2>;

// One DHT segment's tables: class and slot in range, each table's 16 counts within the code space
// (at most 2^n codes of n bits, less those taken by shorter codes; so at most 256 symbols in
// all, the bound stbi__build_huffman needs) and its symbols within the segment.
bool check_dht(std::string_view seg, HuffmanTables* defined, std::string* error) {
    size_t pos = 0;
    while (pos < seg.size()) {
        if (seg.size() - pos < 17) return fail(error, "truncated JPEG Huffman table");
        const auto tc = static_cast<uint8_t>(seg[pos]);
        if ((tc >> 4) > 1 || (tc & 15) > 3) return fail(error, "bad JPEG Huffman table class");
        uint32_t codes = 0, symbols = 0;  // codes: free codes of the current length, used
        for (size_t n = 1; n <= 16; ++n) {
            const uint32_t count = static_cast<uint8_t>(seg[pos + n]);
            codes = codes * 2 + count;  // the codes of length n, with those of shorter length
            symbols += count;
            if (codes > (1u << n))
                return fail(error, "JPEG Huffman table with more codes than fit their lengths");
        }
        if (symbols > 256 || seg.size() - pos - 17 < symbols)
            return fail(error, "bad JPEG Huffman table of " + std::to_string(symbols) + " symbols");
        (*defined)[tc >> 4][tc & 15] = true;
        pos += 17 + symbols;
    }
    return true;
}

// A scan header (SOS): its length right, and every table it uses defined before it (stb decodes
// with a table that was never defined from uninitialised memory): both tables in a sequential
// frame (stb decodes all 64 coefficients whatever the scan's Ss and Se say); in a progressive
// one the DC tables when the scan holds the DC coefficients (Ss = 0), the AC tables when it
// holds AC ones (Se > 0).
bool check_sos(std::string_view seg, bool progressive, const HuffmanTables& defined,
               std::string* error) {
    if (seg.empty()) return fail(error, "bad JPEG scan header");
    const size_t n = static_cast<uint8_t>(seg[0]);
    if (n < 1 || n > 4 || seg.size() != 1 + 2 * n + 3) return fail(error, "bad JPEG scan header");
    const bool dc = !progressive || seg[1 + 2 * n] == 0;
    const bool ac = !progressive || seg[2 + 2 * n] != 0;
    for (size_t c = 0; c < n; ++c) {
        const auto tables = static_cast<uint8_t>(seg[2 + 2 * c]);
        const size_t td = tables >> 4, ta = tables & 15;
        if (td > 3 || ta > 3 || (dc && !defined[0][td]) || (ac && !defined[1][ta]))
            return fail(error, "JPEG scan using a Huffman table it has not defined");
    }
    return true;
}

bool is_sof(uint8_t m) { return m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC; }

// Skips the entropy-coded data after a scan's header: to the next marker that is neither a
// stuffed 0xFF00 nor a restart marker. Returns its offset (the 0xFF), or npos.
size_t skip_scan(std::string_view d, size_t pos) {
    for (; pos + 1 < d.size(); ++pos) {
        if (static_cast<uint8_t>(d[pos]) != 0xFF) continue;
        const auto m = static_cast<uint8_t>(d[pos + 1]);
        if (m != 0x00 && m != 0xFF && (m < 0xD0 || m > 0xD7)) return pos;
    }
    return std::string_view::npos;
}

// Walks the segments from the SOI to the EOI: lengths within the file, every DHT checked, the
// frame's size read (one frame, before the first scan).
bool check_jpeg(std::string_view d, uint32_t* w, uint32_t* h, std::string* error) {
    size_t pos = 2;  // after the SOI
    bool frame = false, progressive = false;
    HuffmanTables defined{};
    for (;;) {
        while (pos < d.size() && static_cast<uint8_t>(d[pos]) != 0xFF) ++pos;  // as stb skips
        while (pos + 1 < d.size() && static_cast<uint8_t>(d[pos + 1]) == 0xFF) ++pos;  // fill
        if (d.size() - pos < 2 || pos >= d.size()) return fail(error, "truncated JPEG (no EOI)");
        const auto m = static_cast<uint8_t>(d[pos + 1]);
        pos += 2;
        if (m == 0xD9) break;                                 // EOI
        if (m == 0x01 || (m >= 0xD0 && m <= 0xD7)) continue;  // TEM, RSTn: no length
        if (m == 0xD8) return fail(error, "JPEG file with a second SOI");
        if (d.size() - pos < 2) return fail(error, "truncated JPEG (no EOI)");
        const uint32_t length = be16(d, pos);
        if (length < 2 || length > d.size() - pos)
            return fail(error, "truncated JPEG: a segment of " + std::to_string(length) +
                                   " bytes at offset " + std::to_string(pos));
        const std::string_view seg = d.substr(pos + 2, length - 2);
        if (m == 0xC4 && !check_dht(seg, &defined, error)) return false;
        if (is_sof(m)) {
            if (frame) return fail(error, "JPEG file with two frames");
            if (seg.size() < 6) return fail(error, "bad JPEG frame header");
            frame = true;
            progressive = m == 0xC2 || m == 0xC6 || m == 0xCA || m == 0xCE;
            *h = be16(seg, 1);
            *w = be16(seg, 3);
        }
        pos += length;
        if (m == 0xDA) {  // SOS: the entropy-coded data follows
            if (!frame) return fail(error, "JPEG scan before its frame header");
            if (!check_sos(seg, progressive, defined, error)) return false;
            pos = skip_scan(d, pos);
            if (pos == std::string_view::npos) return fail(error, "truncated JPEG (no EOI)");
        }
    }
    return frame || fail(error, "JPEG file without a frame header");
}

}  // namespace

bool decode_png_jpeg_stb(std::string_view data, TextureImage* out, std::string* error) {
    const TextureFormat format = sniff_texture_format(data);
    uint32_t w = 0, h = 0;
    if (format == TextureFormat::Png) {
        if (!check_png(data, &w, &h, error)) return false;
    } else if (format == TextureFormat::Jpeg) {
        if (!check_jpeg(data, &w, &h, error)) return false;
    } else {
        return fail(error, "not a PNG or JPEG file");
    }
    const char* what = format == TextureFormat::Png ? "PNG image" : "JPEG image";
    if (!decode_impl::check_size(w, h, what, error)) return false;
    if (data.size() > INT32_MAX) return fail(error, "file too large for stb_image");
    int sw = 0, sh = 0, channels = 0;
    // Three channels asked for: stb replicates grey and drops alpha (spec §7.3).
    // Freed however this ends (start_image may throw std::bad_alloc).
    const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> pixels(
        stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(data.data()),
                              static_cast<int>(data.size()), &sw, &sh, &channels, 3),
        &stbi_image_free);
    if (!pixels) return fail(error, stbi_failure_reason() ? stbi_failure_reason() : "bad image");
    if (static_cast<uint32_t>(sw) != w || static_cast<uint32_t>(sh) != h)
        return fail(error, "the decoded size differs from the header's");
    decode_impl::start_image(out, w, h);
    std::memcpy(out->rgb.data(), pixels.get(), out->rgb.size());
    return true;
}

}  // namespace rt
