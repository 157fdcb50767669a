#include "format/lexer.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>

#include "rt/util/charconv.h"

namespace rt {

// The bytes that end a word: whitespace, and '/' (which starts a comment when doubled). One
// table look-up per byte in the loops that cross most of a file.
constexpr std::array<bool, 256> kWordEnd = [] {
    std::array<bool, 256> t{};
    for (const char c : {' ', '\t', '\r', '\n', '\v', '\f', '/'})
        t[static_cast<unsigned char>(c)] = true;
    return t;
}();
static bool is_space(char c) { return c != '/' && kWordEnd[static_cast<unsigned char>(c)]; }
static bool is_digit(char c) { return c >= '0' && c <= '9'; }

Lexer::Lexer(std::string_view text, const std::string* file) : m_text(text), m_file(file) {
    // A leading UTF-8 byte order mark is skipped (spec §2).
    if (m_text.substr(0, 3) == "\xEF\xBB\xBF") m_pos = 3;
}

void Lexer::skip_space_and_comments() {
    while (m_pos < m_text.size()) {
        const char c = m_text[m_pos];
        if (c == '\n' || c == '\r') {
            // LF, CRLF and CR each end one line.
            if (c == '\r' && m_pos + 1 < m_text.size() && m_text[m_pos + 1] == '\n') ++m_pos;
            ++m_pos;
            ++m_line;
            m_col = 1;
        } else if (is_space(c)) {
            ++m_pos;
            ++m_col;
        } else if (c == '/' && m_pos + 1 < m_text.size() && m_text[m_pos + 1] == '/') {
            // A comment runs to the end of the line; the newline itself is handled above.
            while (m_pos < m_text.size() && m_text[m_pos] != '\n' && m_text[m_pos] != '\r') {
                ++m_pos;
                ++m_col;
            }
        } else {
            return;
        }
    }
}

Token Lexer::scan() {
    skip_space_and_comments();
    Token t;
    t.line = m_line;
    t.col = m_col;
    if (m_pos >= m_text.size()) {
        t.kind = TokenKind::End;
        return t;
    }
    const size_t start = m_pos;
    if (m_text[m_pos] == '!') {
        // A !…! string: any text up to the next '!' on the same line.
        size_t end = m_pos + 1;
        while (end < m_text.size() && m_text[end] != '!' && m_text[end] != '\n' &&
               m_text[end] != '\r')
            ++end;
        if (end >= m_text.size() || m_text[end] != '!')
            throw SceneError(loc(t), "unterminated !…! string (it must close on the same line)");
        ++end;
        t.kind = TokenKind::String;
        t.text = m_text.substr(start, end - start);
        m_col += static_cast<int>(end - start);
        m_pos = end;
        return t;
    }
    scan_word();
    t.text = m_text.substr(start, m_pos - start);
    t.kind = (t.text.size() > 1 && t.text[0] == '#') ? TokenKind::Directive : TokenKind::Word;
    return t;
}

// A word ends at whitespace or where a // comment starts (spec §2: comments may follow a token
// directly).
void Lexer::scan_word() {
    const size_t start = m_pos, size = m_text.size();
    const char* text = m_text.data();
    while (m_pos < size) {
        const char c = text[m_pos];
        if (kWordEnd[static_cast<unsigned char>(c)] &&
            (c != '/' || (m_pos + 1 < size && text[m_pos + 1] == '/')))
            break;
        ++m_pos;
    }
    m_col += static_cast<int>(m_pos - start);
}

void Lexer::skip_words() {
    if (m_has_peek) return;
    for (;;) {
        skip_space_and_comments();
        if (m_pos >= m_text.size() || m_text[m_pos] == '!' || m_text[m_pos] == '#') return;
        scan_word();
    }
}

Token Lexer::next() {
    if (m_has_peek) {
        m_has_peek = false;
        return m_peek;
    }
    return scan();
}

Token Lexer::peek() {
    if (!m_has_peek) {
        m_peek = scan();
        m_has_peek = true;
    }
    return m_peek;
}

static bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) !=
            std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

bool parse_real(std::string_view s, double* out, bool* non_finite) {
    *non_finite = false;
    size_t i = 0;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    const std::string_view body = s.substr(i);
    if (iequals(body, "nan") || iequals(body, "inf") || iequals(body, "infinity")) {
        *non_finite = true;
        return false;
    }
    // [+-]? ( D+ ( . D* )? | . D+ ) ( [eE] [+-]? D+ )?
    size_t digits = 0;
    while (i < s.size() && is_digit(s[i])) ++i, ++digits;
    if (i < s.size() && s[i] == '.') {
        ++i;
        while (i < s.size() && is_digit(s[i])) ++i, ++digits;
    }
    if (digits == 0) return false;
    if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
        size_t exp_digits = 0;
        while (i < s.size() && is_digit(s[i])) ++i, ++exp_digits;
        if (exp_digits == 0) return false;
    }
    if (i != s.size()) return false;

    const std::string_view num = (s[0] == '+') ? s.substr(1) : s;
    double v = 0.0;
    const auto r = from_chars_double(num.data(), num.data() + num.size(), v);
    if (r.ec == std::errc::result_out_of_range) {
        // Overflow is an error; underflow to a denormal or zero is fine. strtod tells them apart.
        v = std::strtod(std::string(num).c_str(), nullptr);
    } else if (r.ec != std::errc() || r.ptr != num.data() + num.size()) {
        return false;
    }
    if (!std::isfinite(v)) {
        *non_finite = true;
        return false;
    }
    *out = v;
    return true;
}

bool parse_int(std::string_view s, int* out, bool* out_of_range) {
    *out_of_range = false;
    size_t i = 0;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (i == s.size()) return false;
    for (size_t k = i; k < s.size(); ++k)
        if (!is_digit(s[k])) return false;
    const std::string_view num = (s[0] == '+') ? s.substr(1) : s;
    int v = 0;
    const auto r = std::from_chars(num.data(), num.data() + num.size(), v);
    if (r.ec == std::errc::result_out_of_range) {
        *out_of_range = true;
        return false;
    }
    if (r.ec != std::errc() || r.ptr != num.data() + num.size()) return false;
    *out = v;
    return true;
}

}  // namespace rt
