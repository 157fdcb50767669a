// Tokenizer for .ray and .key files (spec §2): whitespace-separated tokens, // comments,
// !...! strings, line/column tracking for LF, CRLF and CR. Streaming: no token list is built.
#pragma once

#include <string>
#include <string_view>

#include "rt/util/error.h"

namespace rt {

enum class TokenKind { Directive, Word, String, End };

struct Token {
    TokenKind kind = TokenKind::End;
    std::string_view text;
    int line = 0;
    int col = 0;
};

class Lexer {
public:
    /// `text` must outlive the lexer. `file` names the source in locations.
    Lexer(std::string_view text, const std::string* file);

    /// The next token; throws SceneError for an unterminated !...! string.
    Token next();
    /// The next token without consuming it.
    Token peek();
    /// Consumes the words that come next, up to a directive, a string or the end, as next()
    /// would one by one, without making their tokens (the dialect pre-scan's pass over a mesh).
    /// Nothing when a token is peeked; a word that is a lone '#' stops it too.
    void skip_words();

    SourceLoc loc(const Token& t) const { return {m_file, t.line, t.col}; }
    const std::string* file() const { return m_file; }
    std::string_view text() const { return m_text; }
    /// Bytes not yet scanned (for bounding reservations by what the text can still hold).
    size_t remaining() const { return m_text.size() - m_pos; }
    /// Where a token of this lexer's text starts, in bytes (the end of the text for End).
    size_t offset(const Token& t) const {
        return t.kind == TokenKind::End ? m_text.size()
                                        : static_cast<size_t>(t.text.data() - m_text.data());
    }
    /// Continues at byte `pos`, which is at line `line`, column `col`: where another lexer of
    /// the same text met a token (a piece of a mesh that a second thread parses).
    void seek(size_t pos, int line, int col) {
        m_pos = pos;
        m_line = line;
        m_col = col;
        m_has_peek = false;
    }

private:
    void skip_space_and_comments();
    void scan_word();  // past the word at m_pos, counting its columns
    Token scan();

    std::string_view m_text;
    const std::string* m_file = nullptr;
    size_t m_pos = 0;
    int m_line = 1;
    int m_col = 1;
    bool m_has_peek = false;
    Token m_peek;
};

/// Parses a `real` token per spec §2. Returns false when the token is not of the grammar;
/// sets *non_finite when it is nan/inf or overflows.
bool parse_real(std::string_view s, double* out, bool* non_finite);
/// Parses an `int` token per spec §2 (32-bit signed). *out_of_range is set when it overflows.
bool parse_int(std::string_view s, int* out, bool* out_of_range);
namespace parser_impl {
/// For messages: "end of file" or the quoted token (parser.cpp).
std::string describe(const Token& t);
}  // namespace parser_impl

}  // namespace rt
