#include "rt/util/text.h"

namespace rt {

namespace {

// Appends s[i, end) escaped to `out`; returns where it stopped (end, or the first byte at or past
// `limit` that starts a character).
size_t escape_into(std::string_view s, size_t limit, std::string* out) {
    static constexpr char kHex[] = "0123456789abcdef";
    size_t i = 0;
    while (i < s.size() && i < limit) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        const size_t n = c >= 0x80 ? utf8_length(s, i) : (c < 0x20 || c == 0x7F ? 0 : 1);
        if (n == 0) {
            *out += "\\x";
            *out += kHex[c >> 4];
            *out += kHex[c & 15];
            ++i;
        } else {
            out->append(s.substr(i, n));
            i += n;
        }
    }
    return i;
}

}  // namespace

size_t utf8_length(std::string_view s, size_t i) {
    const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    size_t n = 0;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2;
    else if (c >= 0xE0 && c <= 0xEF)
        n = 3;
    else if (c >= 0xF0 && c <= 0xF4)
        n = 4;
    if (n == 0 || i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k)
        if ((b(i + k) & 0xC0) != 0x80) return 0;
    // No overlong forms, surrogates or code points above U+10FFFF.
    if ((c == 0xE0 && b(i + 1) < 0xA0) || (c == 0xED && b(i + 1) > 0x9F) ||
        (c == 0xF0 && b(i + 1) < 0x90) || (c == 0xF4 && b(i + 1) > 0x8F))
        return 0;
    return n;
}

bool printable_text(std::string_view s) {
    for (size_t i = 0; i < s.size();) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        const size_t n = c >= 0x80 ? utf8_length(s, i) : (c < 0x20 || c == 0x7F ? 0 : 1);
        if (n == 0) return false;
        i += n;
    }
    return true;
}

std::string escape(std::string_view s) {
    std::string r;
    escape_into(s, s.size(), &r);
    return r;
}

std::string quote(std::string_view s) {
    constexpr size_t kMax = 200;
    std::string r = "'";
    const size_t i = escape_into(s, kMax, &r);
    r += '\'';
    if (i < s.size()) {
        r += "... (";
        r += std::to_string(s.size());
        r += " bytes)";
    }
    return r;
}

}  // namespace rt
