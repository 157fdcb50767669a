// Text from files shown safely (rt/util/text.h): what the parser's messages, the ray tree and
// raycompare's table print of a name, a token or a path; the names of enum values
// (rt/util/enum_names.h, the light kinds' in rt/util/light_kind.h).
#include <gtest/gtest.h>

#include <string>

#include "rt/util/enum_names.h"
#include "rt/util/isa.h"
#include "rt/util/light_kind.h"
#include "rt/util/text.h"

namespace rt {
namespace {

TEST(Text, ControlBytesAndInvalidUtf8AreEscaped) {
    EXPECT_EQ(escape("plain name.png"), "plain name.png");
    EXPECT_EQ(escape("caf\xc3\xa9 \xe2\x82\xac"), "caf\xc3\xa9 \xe2\x82\xac");  // UTF-8 kept
    // A terminal's escape sequence, a carriage return that would overwrite a line, a NUL.
    EXPECT_EQ(escape("a\x1b[2Kb\rPASS"), "a\\x1b[2Kb\\x0dPASS");
    EXPECT_EQ(escape(std::string("x\0y", 3)), "x\\x00y");
    EXPECT_EQ(escape("\x7f"), "\\x7f");
    // Not UTF-8: a lone continuation, a truncated sequence, an overlong '/', a surrogate.
    EXPECT_EQ(escape("\x80"), "\\x80");
    EXPECT_EQ(escape("\xe2\x82"), "\\xe2\\x82");
    EXPECT_EQ(escape("\xc0\xaf"), "\\xc0\\xaf");
    EXPECT_EQ(escape("\xed\xa0\x80"), "\\xed\\xa0\\x80");
}

TEST(Text, PrintableTextIsWhatEscapeLeavesAlone) {
    for (const std::string s :
         {"abc", "caf\xc3\xa9", "a\tb", "\x1b", "\xff", "", "\xf4\x8f\xbf\xbf"})
        EXPECT_EQ(printable_text(s), escape(s) == s) << escape(s);
}

TEST(Text, QuoteCutsLongText) {
    EXPECT_EQ(quote("#oops"), "'#oops'");
    EXPECT_EQ(quote("a\x1b"), "'a\\x1b'");
    const std::string q = quote(std::string(1000, 'a'));
    EXPECT_EQ(q, "'" + std::string(200, 'a') + "'... (1000 bytes)");
}

// A table of names in the enum's order: each value its name, a value outside the table the
// fallback.
TEST(EnumNames, TheTableInTheEnumsOrderAndTheFallbackPastIt) {
    enum class E { A, B };
    static constexpr const char* kNames[] = {"a", "b"};
    EXPECT_STREQ(enum_name(E::B, kNames), "b");
    EXPECT_STREQ(enum_name(static_cast<E>(2), kNames), "");
    EXPECT_STREQ(enum_name(static_cast<E>(-1), kNames, "?"), "?");
    EXPECT_STREQ(isa_name(Isa::Avx512), "avx512");
    EXPECT_STREQ(isa_name(static_cast<Isa>(7)), "?");
}

// The light kinds' names, spelled once: each kind's name names it back, another word nothing.
TEST(EnumNames, LightKindNamesGoBothWays) {
    EXPECT_STREQ(light_kind_name(LightKind::Directional), "directional");
    EXPECT_STREQ(light_kind_name(LightKind::Sphere), "sphere");
    for (int k = 0; k < kLightKinds; ++k) {
        const LightKind kind = static_cast<LightKind>(k);
        EXPECT_EQ(light_kind_from_name(light_kind_name(kind)), kind);
    }
    EXPECT_FALSE(light_kind_from_name("area").has_value());
    EXPECT_FALSE(light_kind_from_name("").has_value());
}

}  // namespace
}  // namespace rt
