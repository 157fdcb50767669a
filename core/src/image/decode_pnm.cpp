// Netpbm grey and colour maps (P2, P3, P5, P6) and PFM float images. Their headers share one
// syntax: a magic word, then whitespace-separated fields with '#' comments, then one whitespace
// byte before the samples. The samples a header declares are checked against the bytes that
// follow before anything is allocated.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "image/decode_util.h"
#include "rt/image/decode.h"

namespace rt {

namespace {

using decode_impl::fail;

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// Reads the header's fields one word at a time.
class HeaderReader {
public:
    explicit HeaderReader(std::string_view d) : m_d(d) {}

    // The next word after whitespace and comments; empty at the end of the file.
    std::string_view word() {
        for (;;) {
            while (m_pos < m_d.size() && is_space(m_d[m_pos])) ++m_pos;
            if (m_pos >= m_d.size() || m_d[m_pos] != '#') break;
            while (m_pos < m_d.size() && m_d[m_pos] != '\n' && m_d[m_pos] != '\r') ++m_pos;
        }
        const size_t start = m_pos;
        while (m_pos < m_d.size() && !is_space(m_d[m_pos]) && m_d[m_pos] != '#') ++m_pos;
        return m_d.substr(start, m_pos - start);
    }

    // A decimal integer of at most 9 digits (no sign), else false.
    bool number(uint32_t* v) {
        const std::string_view w = word();
        if (w.empty() || w.size() > 9) return false;
        *v = 0;
        for (const char c : w) {
            if (c < '0' || c > '9') return false;
            *v = *v * 10 + static_cast<uint32_t>(c - '0');
        }
        return true;
    }

    // The single whitespace byte that ends the header; false if there is none. Returns the
    // offset of the first sample.
    bool end(size_t* data_at) {
        if (m_pos >= m_d.size() || !is_space(m_d[m_pos])) return false;
        *data_at = m_pos + 1;
        return true;
    }

private:
    std::string_view m_d;
    size_t m_pos = 0;
};

uint8_t to_8bit(uint32_t v, uint32_t maxval) {
    return static_cast<uint8_t>((uint64_t{v} * 255 + maxval / 2) / maxval);
}

// The samples after a PNM header, one at a time: ASCII words (P2, P3), or binary values of one
// byte up to maxval 255 and two bytes (most significant first) above (P5, P6).
class SampleReader {
public:
    SampleReader(std::string_view d, size_t at, bool ascii, uint32_t maxval)
        : m_ascii(d.substr(at)),
          m_d(d),
          m_at(at),
          m_is_ascii(ascii),
          m_bytes(maxval < 256 ? 1 : 2),
          m_maxval(maxval) {}

    // Checks that the file can hold `count` samples, before anything is allocated. An ASCII
    // sample takes at least two bytes (a digit and a separator; the last needs no separator).
    bool check_count(uint64_t count, uint64_t w, uint64_t h, std::string* error) const {
        const uint64_t have = m_d.size() - m_at;
        if (!m_is_ascii)
            return decode_impl::check_length(count * m_bytes, have, w, h, "PNM", error);
        if (count <= (have + 1) / 2) return true;
        return fail(error, "truncated PNM: " + std::to_string(w) + "x" + std::to_string(h) +
                               " pixels need " + std::to_string(count) +
                               " samples, the file has room for at most " +
                               std::to_string((have + 1) / 2));
    }

    bool next(uint32_t* v, std::string* error) {
        if (m_is_ascii) {
            if (!m_ascii.number(v))
                return fail(error,
                            "truncated or bad PNM data at sample " + std::to_string(m_count + 1));
        } else {
            const size_t pos = m_at + m_count * m_bytes;
            *v = m_bytes == 1 ? static_cast<uint8_t>(m_d[pos]) : decode_impl::be16(m_d, pos);
        }
        ++m_count;
        if (*v > m_maxval)
            return fail(error, "PNM sample " + std::to_string(*v) + " above its maximum " +
                                   std::to_string(m_maxval));
        return true;
    }

private:
    HeaderReader m_ascii;
    std::string_view m_d;
    size_t m_at;
    bool m_is_ascii;
    size_t m_bytes;
    uint32_t m_maxval;
    size_t m_count = 0;
};

}  // namespace

bool decode_pnm(std::string_view d, TextureImage* out, std::string* error) {
    HeaderReader r(d);
    const std::string_view magic = r.word();
    if (magic.size() != 2 || magic[0] != 'P' || magic[1] < '1' || magic[1] > '7')
        return fail(error, "not a PNM file");
    const char kind = magic[1];
    if (kind != '2' && kind != '3' && kind != '5' && kind != '6')
        return fail(error, "unsupported PNM kind P" + std::string(1, kind) +
                               " (P2, P3, P5 and P6 are read)");
    uint32_t w = 0, h = 0, maxval = 0;
    size_t at = 0;
    if (!r.number(&w) || !r.number(&h) || !r.number(&maxval) || !r.end(&at))
        return fail(error, "bad PNM header");
    if (maxval == 0 || maxval > 65535)
        return fail(error, "PNM maximum " + std::to_string(maxval) + " outside 1..65535");
    if (!decode_impl::check_size(w, h, "PNM image", error)) return false;
    const uint64_t channels = kind == '3' || kind == '6' ? 3 : 1;
    SampleReader samples(d, at, kind == '2' || kind == '3', maxval);
    if (!samples.check_count(uint64_t{w} * h * channels, w, h, error)) return false;
    decode_impl::start_image(out, w, h);
    for (size_t i = 0; i < out->rgb.size(); i += 3)
        for (size_t k = 0; k < channels; ++k) {
            uint32_t v = 0;
            if (!samples.next(&v, error)) {
                *out = TextureImage();
                return false;
            }
            out->rgb[i + k] = to_8bit(v, maxval);
            if (channels == 1) out->rgb[i + 1] = out->rgb[i + 2] = out->rgb[i];  // spec §7.3
        }
    return true;
}

bool decode_pfm(std::string_view d, Image* out, std::string* error) {
    HeaderReader r(d);
    if (r.word() != "PF") return fail(error, "not a 3-channel PFM file");
    uint32_t w = 0, h = 0;
    const bool sides = r.number(&w) && r.number(&h);
    // The scale: its sign tells the byte order (negative: little-endian).
    const std::string scale_word(r.word());
    char* end = nullptr;
    const double scale = std::strtod(scale_word.c_str(), &end);
    size_t at = 0;
    if (!sides || scale_word.empty() || *end != '\0' || !std::isfinite(scale) || scale == 0.0 ||
        !r.end(&at))
        return fail(error, "bad PFM header");
    if (!decode_impl::check_size(w, h, "PFM image", error)) return false;
    const uint64_t row_floats = uint64_t{w} * 3;
    if (!decode_impl::check_length(row_floats * h * 4, d.size() - at, w, h, "PFM", error))
        return false;
    const bool little = scale < 0;
    *out = Image(static_cast<int>(w), static_cast<int>(h));
    // PFM stores rows from the bottom.
    for (uint64_t y = 0; y < h; ++y)
        for (uint64_t i = 0; i < row_floats; ++i) {
            const size_t pos = static_cast<size_t>(at + ((h - 1 - y) * row_floats + i) * 4);
            const uint32_t bits = little ? decode_impl::le32(d, pos) : decode_impl::be32(d, pos);
            float f = 0.0f;
            std::memcpy(&f, &bits, sizeof f);
            out->rgb[y * row_floats + i] = static_cast<double>(f);
        }
    return true;
}

}  // namespace rt
