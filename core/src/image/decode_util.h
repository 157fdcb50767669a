// What the image decoders (rt/image/decode.h) share: reading bytes with bounds checks, and the
// size checks made before anything is allocated.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "rt/image/image.h"
#include "rt/util/limits.h"

namespace rt::decode_impl {

/// Sets *error and returns false, so a decoder can `return fail(error, "...")`.
inline bool fail(std::string* error, std::string message) {
    *error = std::move(message);
    return false;
}

/// Unsigned integers of the file, little- or big-endian, at `pos` (the caller checks the bounds).
inline uint32_t le16(std::string_view d, size_t pos) {
    return uint32_t{static_cast<uint8_t>(d[pos])} | uint32_t{static_cast<uint8_t>(d[pos + 1])} << 8;
}
inline uint32_t le32(std::string_view d, size_t pos) {
    return le16(d, pos) | le16(d, pos + 2) << 16;
}
inline uint32_t be16(std::string_view d, size_t pos) {
    return uint32_t{static_cast<uint8_t>(d[pos])} << 8 | uint32_t{static_cast<uint8_t>(d[pos + 1])};
}
inline uint32_t be32(std::string_view d, size_t pos) {
    return be16(d, pos) << 16 | be16(d, pos + 2);
}

/// The budget check of every decoder, before it allocates: false with the message of
/// decode_size_error() ("<what> of WxH pixels ... is larger than the budget ...") when the image
/// does not fit, or "<what> of WxH pixels is empty" when a side is 0.
inline bool check_size(uint64_t width, uint64_t height, const std::string& what,
                       std::string* error) {
    if (width == 0 || height == 0)
        return fail(error, what + " of " + std::to_string(width) + "x" + std::to_string(height) +
                               " pixels is empty");
    // TextureImage and Image keep their sides as int, whatever budget --max-pixels sets.
    if (width > INT32_MAX || height > INT32_MAX)
        return fail(error, what + " of " + std::to_string(width) + "x" + std::to_string(height) +
                               " pixels is too wide or too tall");
    std::string e = decode_size_error(width, height, what);
    return e.empty() || fail(error, std::move(e));
}

/// Checks a size declared by a header against the bytes the file holds after it: "truncated
/// <what>: WxH pixels need N bytes of pixel data, the file has M". `need` is computed by the
/// caller without overflow (the sizes passed check_size() first).
inline bool check_length(uint64_t need, uint64_t have, uint64_t width, uint64_t height,
                         const std::string& what, std::string* error) {
    if (need <= have) return true;
    return fail(error, "truncated " + what + ": " + std::to_string(width) + "x" +
                           std::to_string(height) + " pixels need " + std::to_string(need) +
                           " bytes of pixel data, the file has " + std::to_string(have));
}

/// Sizes `out` for a width x height image (after check_size()).
inline void start_image(TextureImage* out, uint64_t width, uint64_t height) {
    out->width = static_cast<int>(width);
    out->height = static_cast<int>(height);
    out->rgb.assign(static_cast<size_t>(width * height * 3), 0);
}

}  // namespace rt::decode_impl
