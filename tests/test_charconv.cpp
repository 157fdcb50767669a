// The floating-point conversions of rt/util/charconv.h: the fallbacks the web build uses
// (its libc++ has no floating-point std::from_chars or std::to_chars) give what the standard
// library gives here.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "rt/util/charconv.h"

namespace rt {
namespace {

TEST(Charconv, TheFallbackReadsNumbersAsFromCharsDoes) {
    for (const char* text : {"0", "1", "-2.5", "0.1", "1e10", "3.14159265358979311600",
                             "123456789012345678901234567890", "2.2250738585072014e-308",
                             "4.9e-324", "1e-400", "1e400", "-0", "7.", ".5", "1e+05"}) {
        const char* end = text + std::strlen(text);
        double expected = -1, got = -1;
        const auto e = std::from_chars(text, end, expected);
        const auto g = charconv_fallback::from_chars(text, end, got);
        EXPECT_EQ(g.ptr, e.ptr) << text;
        if (e.ec == std::errc()) {
            EXPECT_EQ(g.ec, std::errc()) << text;
            EXPECT_EQ(got, expected) << text;  // bit for bit, the sign of zero aside
            EXPECT_EQ(std::signbit(got), std::signbit(expected)) << text;
        } else {
            EXPECT_EQ(g.ec, std::errc::result_out_of_range) << text;
        }
    }
    double v = 0;
    EXPECT_EQ(charconv_fallback::from_chars("x", "x" + 1, v).ec, std::errc::invalid_argument);
}

// The shortest text reads back to the very value, and has no more digits than std::to_chars.
template <class T>
void expect_shortest_round_trip(T v) {
    char fallback[64], standard[64];
    const auto f = charconv_fallback::to_chars_shortest(fallback, fallback + sizeof fallback, v);
    const auto s = std::to_chars(standard, standard + sizeof standard, v);
    ASSERT_EQ(f.ec, std::errc());
    const std::string text(fallback, f.ptr);
    EXPECT_EQ(static_cast<T>(std::strtod(text.c_str(), nullptr)), v) << text;
    auto digits = [](const char* b, const char* e) {
        int n = 0;
        for (; b != e && *b != 'e'; ++b) n += *b >= '0' && *b <= '9';
        return n;
    };
    EXPECT_LE(digits(fallback, f.ptr), std::max(digits(standard, s.ptr), 1))
        << text << " against " << std::string(standard, s.ptr);
}

TEST(Charconv, TheFallbackWritesTheShortestTextThatReadsBack) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(-1, 1);
    for (int i = 0; i < 2000; ++i) {
        const double d = unit(rng) * std::pow(10.0, static_cast<int>(rng() % 40) - 20);
        expect_shortest_round_trip(d);
        expect_shortest_round_trip(static_cast<float>(d));
    }
    for (double d : {0.0, 0.1, 0.3, 1.0 / 3, 1e21, 5e-324, 1.7976931348623157e308})
        expect_shortest_round_trip(d);
    char buf[64];
    const auto r = charconv_fallback::to_chars_general(buf, buf + sizeof buf, 1.0 / 3, 9);
    EXPECT_EQ(std::string(buf, r.ptr), "0.333333333");
}

}  // namespace
}  // namespace rt
