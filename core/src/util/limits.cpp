#include "rt/util/limits.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace rt {

namespace {
std::atomic<uint64_t> g_max_image_pixels{kDefaultMaxImagePixels};
}

uint64_t max_image_pixels() { return g_max_image_pixels.load(std::memory_order_relaxed); }

void set_max_image_pixels(uint64_t pixels) {
    g_max_image_pixels.store(std::clamp<uint64_t>(pixels, 1, kMaxImagePixelsLimit),
                             std::memory_order_relaxed);
}

std::string image_size_error(uint64_t width, uint64_t height, const std::string& what) {
    return image_size_error(width, height, what, max_image_pixels());
}

std::string image_size_error(uint64_t width, uint64_t height, const std::string& what,
                             uint64_t budget) {
    // width * height without overflow: compare width with budget / height first.
    if (width == 0 || height == 0 || width <= budget / height) return {};
    std::string e =
        what + " of " + std::to_string(width) + "x" + std::to_string(height) + " pixels";
    if (width <= UINT64_MAX / height) e += " (" + std::to_string(width * height) + ")";
    e += " is larger than the budget of " + std::to_string(budget) + " pixels";
    const auto side = static_cast<uint64_t>(std::sqrt(static_cast<double>(budget)));
    if (side * side == budget) e += " (" + std::to_string(side) + "x" + std::to_string(side) + ")";
    return e + "; --max-pixels raises it";
}

}  // namespace rt
