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

uint64_t max_scene_texels() { return 4 * max_image_pixels(); }

namespace {
thread_local const DecodeBudget* t_decode_budget = nullptr;
}

DecodeBudget::DecodeBudget(uint64_t pixels, std::string name)
    : m_pixels(pixels), m_name(std::move(name)), m_outer(t_decode_budget) {
    t_decode_budget = this;
}

DecodeBudget::~DecodeBudget() { t_decode_budget = m_outer; }

std::string decode_size_error(uint64_t width, uint64_t height, const std::string& what) {
    if (std::string e = image_size_error(width, height, what); !e.empty()) return e;
    const DecodeBudget* b = t_decode_budget;
    if (!b || width == 0 || height == 0 || width <= b->m_pixels / height) return {};
    // width * height fits: it passed image_size_error against a budget of at most 2^40.
    return what + " of " + std::to_string(width) + "x" + std::to_string(height) + " pixels (" +
           std::to_string(width * height) + ") is larger than " + b->m_name +
           "; --max-pixels raises it";
}

}  // namespace rt
