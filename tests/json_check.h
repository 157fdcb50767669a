// A strict JSON reader for the tests and the fuzz targets (RFC 8259, no extensions): UTF-8 only
// (no overlong forms, no surrogates, nothing above U+10FFFF), no raw control characters in
// strings, \u escapes with their surrogates paired, numbers of the grammar, nothing after the
// value but white space, and a bound on the nesting (common parsers stop at a few hundred
// levels). It builds the value, so that a test can look inside it.
#pragma once

#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace rt::test {

struct JsonValue {
    enum class Type { Null, Bool, Number, String, Array, Object };
    Type type = Type::Null;
    bool boolean = false;
    double number = 0.0;
    std::string string;
    std::vector<JsonValue> array;
    struct Member;  // (a std::pair of an incomplete JsonValue does not compile with clang)
    std::vector<Member> object;  // in order, duplicates kept

    /// The member `key` of an object (the first of that name), else nullptr.
    const JsonValue* get(std::string_view key) const;
    /// The member `key`, else a null value (has() tells them apart).
    const JsonValue& operator[](std::string_view key) const;
    bool has(std::string_view key) const { return get(key) != nullptr; }
};

struct JsonValue::Member {
    std::string key;
    JsonValue value;
};

inline const JsonValue* JsonValue::get(std::string_view key) const {
    for (const Member& m : object)
        if (m.key == key) return &m.value;
    return nullptr;
}

inline const JsonValue& JsonValue::operator[](std::string_view key) const {
    static const JsonValue none;
    const JsonValue* v = get(key);
    return v ? *v : none;
}

class JsonReader {
public:
    /// Parses `text` whole; false with the reason and the byte offset in *why when it is not
    /// strict JSON or nests deeper than `max_depth`. *depth: the deepest nesting met (the top
    /// value's array or object is level 1).
    bool parse(std::string_view text, JsonValue* out, std::string* why, int max_depth = 64,
               int* depth = nullptr) {
        m_s = text;
        m_i = 0;
        m_max = max_depth;
        m_deepest = 0;
        m_error.clear();
        JsonValue v;
        bool ok = value(v, 0);
        if (ok) {
            ws();
            if (m_i != m_s.size()) ok = fail("text after the value");
        }
        if (depth) *depth = m_deepest;
        if (!ok) {
            if (why) *why = m_error + " at byte " + std::to_string(m_i);
            return false;
        }
        if (out) *out = std::move(v);
        return true;
    }

private:
    bool fail(const char* what) {
        if (m_error.empty()) m_error = what;
        return false;
    }
    int peek() const { return m_i < m_s.size() ? static_cast<unsigned char>(m_s[m_i]) : -1; }
    void ws() {
        while (m_i < m_s.size() &&
               (m_s[m_i] == ' ' || m_s[m_i] == '\t' || m_s[m_i] == '\n' || m_s[m_i] == '\r'))
            ++m_i;
    }
    bool literal(std::string_view word) {
        if (m_s.substr(m_i, word.size()) != word) return fail("not a JSON value");
        m_i += word.size();
        return true;
    }

    bool value(JsonValue& v, int level) {
        ws();
        const int c = peek();
        if (c == '{' || c == '[') {
            if (level + 1 > m_max) return fail("nested too deep");
            if (level + 1 > m_deepest) m_deepest = level + 1;
        }
        switch (c) {
            case '{':
                v.type = JsonValue::Type::Object;
                return object(v, level + 1);
            case '[':
                v.type = JsonValue::Type::Array;
                return array(v, level + 1);
            case '"':
                v.type = JsonValue::Type::String;
                return string(v.string);
            case 't':
                v.type = JsonValue::Type::Bool;
                v.boolean = true;
                return literal("true");
            case 'f':
                v.type = JsonValue::Type::Bool;
                return literal("false");
            case 'n':
                return literal("null");
            default:
                v.type = JsonValue::Type::Number;
                return number(v.number);
        }
    }

    bool object(JsonValue& v, int level) {
        ++m_i;  // {
        ws();
        if (peek() == '}') return ++m_i, true;
        for (;;) {
            ws();
            std::string key;
            if (peek() != '"') return fail("an object's key is not a string");
            if (!string(key)) return false;
            ws();
            if (peek() != ':') return fail("no ':' after an object's key");
            ++m_i;
            JsonValue member;
            if (!value(member, level)) return false;
            v.object.push_back({std::move(key), std::move(member)});
            ws();
            if (peek() == ',') {
                ++m_i;
                continue;
            }
            if (peek() == '}') return ++m_i, true;
            return fail("no ',' or '}' in an object");
        }
    }

    bool array(JsonValue& v, int level) {
        ++m_i;  // [
        ws();
        if (peek() == ']') return ++m_i, true;
        for (;;) {
            JsonValue item;
            if (!value(item, level)) return false;
            v.array.push_back(std::move(item));
            ws();
            if (peek() == ',') {
                ++m_i;
                continue;
            }
            if (peek() == ']') return ++m_i, true;
            return fail("no ',' or ']' in an array");
        }
    }

    bool number(double& out) {
        const size_t start = m_i;
        const auto digits = [&] {
            const size_t from = m_i;
            while (peek() >= '0' && peek() <= '9') ++m_i;
            return m_i > from;
        };
        if (peek() == '-') ++m_i;
        if (peek() == '0') {
            ++m_i;
        } else if (!digits()) {
            return fail("not a JSON value");
        }
        if (peek() == '.') {
            ++m_i;
            if (!digits()) return fail("no digits after a number's '.'");
        }
        if (peek() == 'e' || peek() == 'E') {
            ++m_i;
            if (peek() == '+' || peek() == '-') ++m_i;
            if (!digits()) return fail("no digits in a number's exponent");
        }
        out = std::strtod(std::string(m_s.substr(start, m_i - start)).c_str(), nullptr);
        return true;
    }

    bool hex4(unsigned* u) {
        *u = 0;
        for (int k = 0; k < 4; ++k) {
            const int c = peek();
            unsigned d;
            if (c >= '0' && c <= '9')
                d = static_cast<unsigned>(c - '0');
            else if (c >= 'a' && c <= 'f')
                d = static_cast<unsigned>(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F')
                d = static_cast<unsigned>(c - 'A' + 10);
            else
                return fail("a \\u escape without four hex digits");
            *u = *u * 16 + d;
            ++m_i;
        }
        return true;
    }

    static void put_utf8(std::string& out, unsigned u) {
        if (u < 0x80) {
            out += static_cast<char>(u);
        } else if (u < 0x800) {
            out += static_cast<char>(0xC0 | (u >> 6));
            out += static_cast<char>(0x80 | (u & 0x3F));
        } else if (u < 0x10000) {
            out += static_cast<char>(0xE0 | (u >> 12));
            out += static_cast<char>(0x80 | ((u >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (u & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (u >> 18));
            out += static_cast<char>(0x80 | ((u >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((u >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (u & 0x3F));
        }
    }

    bool string(std::string& out) {
        ++m_i;  // "
        for (;;) {
            const int c = peek();
            if (c < 0) return fail("a string without its closing quote");
            if (c == '"') return ++m_i, true;
            if (c < 0x20) return fail("a raw control character in a string");
            if (c == '\\') {
                ++m_i;
                const int e = peek();
                ++m_i;
                switch (e) {
                    case '"':
                    case '\\':
                    case '/':
                        out += static_cast<char>(e);
                        break;
                    case 'b':
                        out += '\b';
                        break;
                    case 'f':
                        out += '\f';
                        break;
                    case 'n':
                        out += '\n';
                        break;
                    case 'r':
                        out += '\r';
                        break;
                    case 't':
                        out += '\t';
                        break;
                    case 'u': {
                        unsigned u;
                        if (!hex4(&u)) return false;
                        if (u >= 0xDC00 && u <= 0xDFFF) return fail("a lone low surrogate");
                        if (u >= 0xD800 && u <= 0xDBFF) {
                            unsigned lo;
                            if (m_s.substr(m_i, 2) != "\\u") return fail("a lone high surrogate");
                            m_i += 2;
                            if (!hex4(&lo)) return false;
                            if (lo < 0xDC00 || lo > 0xDFFF) return fail("a lone high surrogate");
                            u = 0x10000 + ((u - 0xD800) << 10) + (lo - 0xDC00);
                        }
                        put_utf8(out, u);
                        break;
                    }
                    default:
                        return fail("an unknown escape in a string");
                }
                continue;
            }
            if (c < 0x80) {
                out += static_cast<char>(c);
                ++m_i;
                continue;
            }
            // UTF-8 (RFC 3629): no overlong forms, surrogates or code points above U+10FFFF.
            const auto b = [&](size_t k) {
                return m_i + k < m_s.size() ? static_cast<unsigned char>(m_s[m_i + k]) : 0u;
            };
            const unsigned c0 = static_cast<unsigned>(c);
            const size_t n = c0 >= 0xC2 && c0 <= 0xDF   ? 2
                             : c0 >= 0xE0 && c0 <= 0xEF ? 3
                             : c0 >= 0xF0 && c0 <= 0xF4 ? 4
                                                        : 0;
            if (n == 0) return fail("a byte that is not UTF-8");
            for (size_t k = 1; k < n; ++k)
                if ((b(k) & 0xC0) != 0x80) return fail("a byte that is not UTF-8");
            if ((c0 == 0xE0 && b(1) < 0xA0) || (c0 == 0xED && b(1) > 0x9F) ||
                (c0 == 0xF0 && b(1) < 0x90) || (c0 == 0xF4 && b(1) > 0x8F))
                return fail("a byte that is not UTF-8");
            out.append(m_s.substr(m_i, n));
            m_i += n;
        }
    }

    std::string_view m_s;
    size_t m_i = 0;
    int m_max = 64;
    int m_deepest = 0;
    std::string m_error;
};

/// Parses `text` as strict JSON (JsonReader::parse).
inline bool parse_strict_json(std::string_view text, JsonValue* out, std::string* why,
                              int max_depth = 64, int* depth = nullptr) {
    return JsonReader().parse(text, out, why, max_depth, depth);
}

}  // namespace rt::test
