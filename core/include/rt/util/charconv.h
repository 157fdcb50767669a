// std::from_chars and std::to_chars for floating point, or their equivalents where the
// standard library lacks them (the web build's libc++ 14 has only the integer overloads):
// strtod, which musl and glibc round correctly, and the shortest %.*g that reads back to the
// same value, in the "C" locale the web build always has. (Where the text differs from
// std::to_chars's it is in fixed against scientific notation only: both read back to the same
// bits.) The fallbacks are compiled everywhere, so the desktop's tests check them against the
// standard library's.
#pragma once

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>
#include <version>

namespace rt {

namespace charconv_fallback {

inline std::from_chars_result from_chars(const char* first, const char* last, double& v) {
    const std::string text(first, last);
    char* end = nullptr;
    errno = 0;
    const double parsed = std::strtod(text.c_str(), &end);
    if (end == text.c_str()) return {first, std::errc::invalid_argument};
    std::from_chars_result r{first + (end - text.c_str()), std::errc()};
    // Out of range as std::from_chars has it: overflow, or an underflow to zero (strtod's
    // ERANGE for a denormal result is not).
    if (errno == ERANGE && (parsed == 0 || std::isinf(parsed)))
        r.ec = std::errc::result_out_of_range;
    else
        v = parsed;
    return r;
}

template <class T>
std::to_chars_result to_chars_shortest(char* first, char* last, T v) {
    char buf[64];
    int n = 0;
    for (int precision = 1; precision <= 17; ++precision) {
        n = std::snprintf(buf, sizeof buf, "%.*g", precision, static_cast<double>(v));
        if (static_cast<T>(std::strtod(buf, nullptr)) == v) break;
    }
    if (n < 0 || n > last - first) return {last, std::errc::value_too_large};
    std::copy(buf, buf + n, first);
    return {first + n, std::errc()};
}

inline std::to_chars_result to_chars_general(char* first, char* last, double v, int precision) {
    char buf[64];
    const int n = std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (n < 0 || n > last - first) return {last, std::errc::value_too_large};
    std::copy(buf, buf + n, first);
    return {first + n, std::errc()};
}

}  // namespace charconv_fallback

/// std::from_chars(first, last, v) for a double.
inline std::from_chars_result from_chars_double(const char* first, const char* last, double& v) {
#if defined(__cpp_lib_to_chars)
    return std::from_chars(first, last, v);
#else
    return charconv_fallback::from_chars(first, last, v);
#endif
}

/// The shortest text that reads back as `v` (std::to_chars(first, last, v)); float or double.
template <class T>
std::to_chars_result to_chars_shortest(char* first, char* last, T v) {
#if defined(__cpp_lib_to_chars)
    return std::to_chars(first, last, v);
#else
    return charconv_fallback::to_chars_shortest(first, last, v);
#endif
}

/// std::to_chars(first, last, v, std::chars_format::general, precision): %.*g.
inline std::to_chars_result to_chars_general(char* first, char* last, double v, int precision) {
#if defined(__cpp_lib_to_chars)
    return std::to_chars(first, last, v, std::chars_format::general, precision);
#else
    return charconv_fallback::to_chars_general(first, last, v, precision);
#endif
}

}  // namespace rt
