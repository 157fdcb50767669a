// Text from files and users shown safely: in a message, a table, a terminal or a JSON string, a
// control byte (which would move a terminal's cursor) or a byte that is not UTF-8 is escaped, never
// printed as it is. The parser's messages, the ray tree and raycompare's table share these.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace rt {

/// Length in bytes of the valid UTF-8 sequence at s[i] (a byte >= 0x80), 0 when it is not one: no
/// overlong forms, surrogates or code points above U+10FFFF (RFC 3629).
size_t utf8_length(std::string_view s, size_t i);

/// True when `s` is printable UTF-8 text: no control bytes, no invalid UTF-8.
bool printable_text(std::string_view s);

/// `s` with every control byte and every byte that is not UTF-8 written as \xNN, the rest as it
/// is: "red\x1b[2J".
std::string escape(std::string_view s);

/// A token, path or name in a message: escape()d and quoted, cut after 200 bytes (a 100 MB token
/// makes a short message): "'red\x1b[2J'", "'aaaa...'... (104857600 bytes)".
std::string quote(std::string_view s);

}  // namespace rt
