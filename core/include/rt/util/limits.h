// The resource budget every reader and allocator of the library checks before it allocates: a
// count or a size that a file declares, or that the user asks for, is compared with what the
// file can hold and with this budget first, and refused with a message that names the size.
#pragma once

#include <cstdint>
#include <string>

namespace rt {

/// The default largest image, in pixels: 8192 x 8192. It bounds every image the library makes
/// or reads (the render's own, textures, reference images, part files); --max-pixels raises it.
inline constexpr uint64_t kDefaultMaxImagePixels = uint64_t{1} << 26;

/// The largest budget that can be set: 2^40 pixels, far beyond any machine's memory, so that
/// the size checks' products (pixels x channels x bytes) cannot overflow 64 bits.
inline constexpr uint64_t kMaxImagePixelsLimit = uint64_t{1} << 40;

/// The largest file read (scenes, textures, images, parts, configurations): 4 GiB, a text scene of
/// about 50 million triangles. A larger file is refused with its size before anything is read.
inline constexpr uint64_t kMaxFileBytes = uint64_t{4} << 30;
/// How much a file may grow while it is read beyond the size it had when opened (1 MiB): a read
/// past that is refused, so a file whose reads never end cannot take the machine's memory.
inline constexpr uint64_t kMaxFileGrowth = uint64_t{1} << 20;

/// The budget in force (process-wide; kDefaultMaxImagePixels until set).
uint64_t max_image_pixels();
/// Sets the budget, clamped to [1, kMaxImagePixelsLimit]; the programs call it from --max-pixels
/// before loading anything.
void set_max_image_pixels(uint64_t pixels);

/// Empty when a `width` x `height` image fits the budget, else why not, naming the size and the
/// flag that raises it: "<what> of 32768x32768 pixels (1073741824) is larger than the budget of
/// 67108864 pixels (8192x8192); --max-pixels raises it". No overflow for any 64-bit input.
std::string image_size_error(uint64_t width, uint64_t height, const std::string& what);
/// The same against a given budget instead of the one in force.
std::string image_size_error(uint64_t width, uint64_t height, const std::string& what,
                             uint64_t budget);

/// The texels that all the textures of one scene may hold together: 4 times the image budget
/// (2^28 by default, a 16384x16384 texture's worth, 768 MB as 8-bit RGB), so that a scene of many
/// small files that each decode to the largest image cannot take the machine's memory.
/// --max-pixels raises both.
uint64_t max_scene_texels();

/// While it lives, every image decoded on this thread must also fit within `pixels` (the scene's
/// textures decode within what its texel budget has left), which the message names as `name`
/// ("what is left of the scene's texture budget (...)"). Scopes nest: the innermost applies.
class DecodeBudget {
public:
    DecodeBudget(uint64_t pixels, std::string name);
    ~DecodeBudget();
    DecodeBudget(const DecodeBudget&) = delete;
    DecodeBudget& operator=(const DecodeBudget&) = delete;

private:
    friend std::string decode_size_error(uint64_t, uint64_t, const std::string&);
    uint64_t m_pixels;
    std::string m_name;
    const DecodeBudget* m_outer;
};

/// The decoders' check before they allocate: image_size_error() against the budget in force,
/// then against this thread's DecodeBudget, if any ("<what> of 8192x8192 pixels (67108864) is
/// larger than what is left of the scene's texture budget (...); --max-pixels raises it").
std::string decode_size_error(uint64_t width, uint64_t height, const std::string& what);

}  // namespace rt
