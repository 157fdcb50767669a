// Lexical rules of spec §2: tokens, comments, !...! strings, line/column counting, numbers.
#include <gtest/gtest.h>

#include <memory>

#include "format/lexer.h"

namespace rt {
namespace {

// Tokens view into the text, so it is kept alive here for the test's duration.
std::vector<Token> tokens(const char* source) {
    static std::vector<std::unique_ptr<std::string>> keep;
    keep.push_back(std::make_unique<std::string>(source));
    Lexer lex(*keep.back(), intern_file_name("t.ray"));
    std::vector<Token> out;
    for (Token t = lex.next(); t.kind != TokenKind::End; t = lex.next()) out.push_back(t);
    return out;
}

TEST(Lexer, SplitsOnAllWhitespaceKinds) {
    const auto t = tokens("#a 1\t2\v3\f4\r\n5");
    ASSERT_EQ(t.size(), 6u);
    EXPECT_EQ(t[0].kind, TokenKind::Directive);
    EXPECT_EQ(t[5].text, "5");
}

TEST(Lexer, CountsLinesForLfCrlfAndCr) {
    const auto t = tokens("a\nb\r\nc\rd");
    ASSERT_EQ(t.size(), 4u);
    EXPECT_EQ(t[1].line, 2);
    EXPECT_EQ(t[2].line, 3);
    EXPECT_EQ(t[3].line, 4);
    EXPECT_EQ(t[3].col, 1);
}

TEST(Lexer, ColumnsCountBytesAndTabIsOneColumn) {
    const auto t = tokens("\t  #x\tyy z");
    EXPECT_EQ(t[0].col, 4);
    EXPECT_EQ(t[1].col, 7);
    EXPECT_EQ(t[2].col, 10);
}

TEST(Lexer, SkipsBomAndComments) {
    const auto t = tokens("\xEF\xBB\xBF#a // comment #b\n1 //x\n// whole line\n2");
    ASSERT_EQ(t.size(), 3u);
    EXPECT_EQ(t[0].col, 1);
    EXPECT_EQ(t[2].text, "2");
    EXPECT_EQ(t[2].line, 4);
}

TEST(Lexer, CommentEndsAWordToken) {
    const auto t = tokens("1.5// comment\n2");
    ASSERT_EQ(t.size(), 2u);
    EXPECT_EQ(t[0].text, "1.5");
}

TEST(Lexer, StringsKeepSpacesAndSlashes) {
    const auto t = tokens("#material 1 !a // b! !! !clickable!");
    ASSERT_EQ(t.size(), 5u);
    EXPECT_EQ(t[2].kind, TokenKind::String);
    EXPECT_EQ(t[2].text, "!a // b!");
    EXPECT_EQ(t[3].text, "!!");
    EXPECT_EQ(t[4].text, "!clickable!");
}

TEST(Lexer, UnterminatedStringIsAnError) {
    try {
        tokens("#material\n !abc\n!");
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.loc().line, 2);
        EXPECT_EQ(e.loc().col, 2);
        EXPECT_NE(std::string(e.what()).find("unterminated"), std::string::npos);
    }
}

// skip_words() drops the words next() would return, and leaves the lexer where next() would:
// the directives, strings and the End that follow have the same text, line and column, on
// text with comments after words, '/' inside words, a lone '#', every line end and a BOM.
TEST(Lexer, SkippingWordsLeavesTheSameTokens) {
    const std::string text =
        "\xEF\xBB\xBF#vertex 1 2/3 4// c #no\r\n  5 # 6\t!s 7! 8\r#shape_x a//b\n"
        "9 #/ 10 //\n\n #end 1\n2";
    std::vector<Token> all, kept;
    {
        Lexer lex(text, intern_file_name("t.ray"));
        for (Token t = lex.next(); t.kind != TokenKind::End; t = lex.next())
            if (t.kind != TokenKind::Word || t.text == "#") all.push_back(t);
        all.push_back(lex.next());
    }
    {
        Lexer lex(text, intern_file_name("t.ray"));
        for (;;) {
            lex.skip_words();
            const Token t = lex.next();
            if (t.kind != TokenKind::Word || t.text == "#") kept.push_back(t);
            if (t.kind == TokenKind::End) break;
        }
    }
    ASSERT_EQ(all.size(), kept.size());
    ASSERT_GE(all.size(), 7u);  // 4 directives, a string, the lone '#', End
    for (size_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(all[i].kind, kept[i].kind) << i;
        EXPECT_EQ(all[i].text, kept[i].text) << i;
        EXPECT_EQ(all[i].line, kept[i].line) << i;
        EXPECT_EQ(all[i].col, kept[i].col) << i;
    }
}

TEST(Lexer, RealGrammar) {
    double v = 0;
    bool nf = false;
    for (const char* ok : {"1", "-1", "+1", "1.", ".5", "1.5e3", "1E-3", "-.5e+2", "0007"}) {
        EXPECT_TRUE(parse_real(ok, &v, &nf)) << ok;
    }
    EXPECT_TRUE(parse_real("-.5e+2", &v, &nf));
    EXPECT_EQ(v, -50.0);
    EXPECT_TRUE(parse_real("+2.5", &v, &nf));
    EXPECT_EQ(v, 2.5);
    for (const char* bad : {".", "e3", "1e", "1.5x", "0x1p3", "--1", "1,5", "", "abc"}) {
        EXPECT_FALSE(parse_real(bad, &v, &nf)) << bad;
        EXPECT_FALSE(nf) << bad;
    }
    for (const char* nonfinite : {"nan", "-inf", "INF", "Infinity", "1e999", "-1e400"}) {
        EXPECT_FALSE(parse_real(nonfinite, &v, &nf)) << nonfinite;
        EXPECT_TRUE(nf) << nonfinite;
    }
    EXPECT_TRUE(parse_real("1e-400", &v, &nf));  // underflow to zero is fine
    EXPECT_EQ(v, 0.0);
}

TEST(Lexer, IntGrammar) {
    int v = 0;
    bool oor = false;
    EXPECT_TRUE(parse_int("-1", &v, &oor));
    EXPECT_EQ(v, -1);
    EXPECT_TRUE(parse_int("+7", &v, &oor));
    EXPECT_EQ(v, 7);
    EXPECT_FALSE(parse_int("2.0", &v, &oor));
    EXPECT_FALSE(parse_int("1e3", &v, &oor));
    EXPECT_FALSE(parse_int("-", &v, &oor));
    EXPECT_FALSE(parse_int("2147483648", &v, &oor));
    EXPECT_TRUE(oor);
    EXPECT_TRUE(parse_int("2147483647", &v, &oor));
}

}  // namespace
}  // namespace rt
