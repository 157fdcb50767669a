#include "rt/image/compare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rt {

namespace {

// A value on the 0-255 scale: as an 8-bit file holds it, or linear (non-finite values are
// written as 0, spec §9).
double steps(double v, bool linear) {
    if (!linear) return to_byte(v);
    return std::isfinite(v) ? 255.0 * v : 0.0;
}

}  // namespace

ImageComparison compare_images(const Image& image, const Image& reference,
                               const CompareSettings& settings) {
    if (image.width != reference.width || image.height != reference.height)
        throw std::invalid_argument("the image is " + std::to_string(image.width) + "x" +
                                    std::to_string(image.height) + ", the reference " +
                                    std::to_string(reference.width) + "x" +
                                    std::to_string(reference.height));
    ImageComparison c;
    c.width = image.width;
    c.height = image.height;
    const size_t n = static_cast<size_t>(c.width) * static_cast<size_t>(c.height);
    c.error.assign(n, 0.0f);
    if (n == 0) return c;
    const bool linear = settings.linear;
    std::vector<double> a(n * 3), b(n * 3);
    for (size_t i = 0; i < n * 3; ++i) {
        a[i] = steps(image.rgb[i], linear);
        b[i] = steps(reference.rgb[i], linear);
    }
    const int r = settings.neighbourhood ? 1 : 0;
    Vec3 sum(0.0);
    size_t off = 0;
    c.max_diff = -1;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const size_t p = static_cast<size_t>(y) * c.width + x;
            // The reference pixel of the neighbourhood nearest in colour (the pixel itself
            // without one).
            std::array<double, 3> best{};
            double best_d = INFINITY;
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    const int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= c.width || qy >= c.height) continue;
                    const size_t q = static_cast<size_t>(qy) * c.width + qx;
                    std::array<double, 3> d;
                    for (size_t k = 0; k < 3; ++k)
                        d[k] = std::abs(a[p * 3 + k] - b[q * 3 + k]) /
                               std::max(1.0, b[q * 3 + k] / 255.0);  // relative above white
                    const double m = std::max({d[0], d[1], d[2]});
                    if (m < best_d) best_d = m, best = d;
                }
            sum += Vec3(best[0], best[1], best[2]);
            off += best_d > settings.tolerance;
            c.error[p] = static_cast<float>(best_d);
            if (best_d > c.max_diff) c.max_diff = best_d, c.max_x = x, c.max_y = y;
        }
    c.mean_abs = sum / static_cast<double>(n);
    c.share_off = static_cast<double>(off) / static_cast<double>(n);
    return c;
}

Vec3 heat_colour(double t) {
    // Black, blue, green, yellow, red: brighter and warmer with the difference.
    static constexpr std::array<std::array<double, 4>, 5> kStops = {{{0.0, 0.0, 0.0, 0.0},
                                                                     {0.2, 0.0, 0.1, 0.9},
                                                                     {0.45, 0.0, 0.8, 0.3},
                                                                     {0.7, 1.0, 0.9, 0.0},
                                                                     {1.0, 1.0, 0.0, 0.0}}};
    t = std::clamp(std::isfinite(t) ? t : 1.0, 0.0, 1.0);
    for (size_t i = 1; i < kStops.size(); ++i) {
        const auto& lo = kStops[i - 1];
        const auto& hi = kStops[i];
        if (t > hi[0]) continue;
        const double f = (t - lo[0]) / (hi[0] - lo[0]);
        return {lo[1] + f * (hi[1] - lo[1]), lo[2] + f * (hi[2] - lo[2]),
                lo[3] + f * (hi[3] - lo[3])};
    }
    return {1.0, 0.0, 0.0};
}

Image heat_map(const ImageComparison& c, double scale) {
    if (!(scale > 0)) scale = std::max(1.0, c.max_diff);
    Image out(c.width, c.height);
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
            out.set(x, y,
                    heat_colour(double{c.error[static_cast<size_t>(y) * c.width + x]} / scale));
    return out;
}

Image threshold_map(const ImageComparison& c, const Image& reference, double tolerance) {
    Image out(c.width, c.height);
    if (reference.width != c.width || reference.height != c.height) return out;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const Vec3 v = glm::clamp(reference.at(x, y), Vec3(0.0), Vec3(1.0));
            const double grey = 0.35 * (0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z);
            const bool off =
                static_cast<double>(c.error[static_cast<size_t>(y) * c.width + x]) > tolerance;
            out.set(x, y, off ? Vec3(1.0, 0.1, 0.1) : Vec3(grey));
        }
    return out;
}

}  // namespace rt
