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

// The 3x3 means of an image's values (3 a pixel, row-major), clipped at the border: a pixel's
// mean is over those of its neighbours that are in the image.
std::vector<double> box_means(const std::vector<double>& v, int width, int height) {
    std::vector<double> out(v.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double sum[3] = {0, 0, 0};
            int count = 0;
            for (int qy = std::max(0, y - 1); qy <= std::min(height - 1, y + 1); ++qy)
                for (int qx = std::max(0, x - 1); qx <= std::min(width - 1, x + 1); ++qx) {
                    const size_t q = (static_cast<size_t>(qy) * width + qx) * 3;
                    for (size_t k = 0; k < 3; ++k) sum[k] += v[q + k];
                    ++count;
                }
            const size_t p = (static_cast<size_t>(y) * width + x) * 3;
            for (size_t k = 0; k < 3; ++k) out[p + k] = sum[k] / count;
        }
    return out;
}

// The reference's 3x3 neighbourhood of (x, y) spans more than `tolerance` in some channel: the
// pixel is on an edge, where a shift by a pixel is no mistake.
bool on_edge(const std::vector<double>& b, int width, int height, int x, int y, double tolerance) {
    for (size_t k = 0; k < 3; ++k) {
        double lo = INFINITY, hi = -INFINITY;
        for (int qy = std::max(0, y - 1); qy <= std::min(height - 1, y + 1); ++qy)
            for (int qx = std::max(0, x - 1); qx <= std::min(width - 1, x + 1); ++qx) {
                const double v = b[(static_cast<size_t>(qy) * width + qx) * 3 + k];
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        if (hi - lo > tolerance) return true;
    }
    return false;
}

// The image's 3x3 block around (x, y) is the reference's around (x + dx, y + dy) within
// `tolerance` in every channel (pixels outside the image skipped): the image there is the
// reference moved by (dx, dy), as an edge shifted by a pixel is. A broader highlight is not: its
// flank is less steep, so that no move of the reference's fits the whole block.
bool block_fits(const std::vector<double>& a, const std::vector<double>& b, int width, int height,
                int x, int y, int dx, int dy, double tolerance) {
    for (int ey = -1; ey <= 1; ++ey)
        for (int ex = -1; ex <= 1; ++ex) {
            const int px = x + ex, py = y + ey, qx = px + dx, qy = py + dy;
            if (px < 0 || py < 0 || px >= width || py >= height || qx < 0 || qy < 0 ||
                qx >= width || qy >= height)
                continue;
            const size_t p = (static_cast<size_t>(py) * width + px) * 3;
            const size_t q = (static_cast<size_t>(qy) * width + qx) * 3;
            for (size_t k = 0; k < 3; ++k)
                if (std::abs(a[p + k] - b[q + k]) / std::max(1.0, b[q + k] / 255.0) > tolerance)
                    return false;
        }
    return true;
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
    c.signed_error.assign(n, 0.0f);
    if (n == 0) return c;
    const bool linear = settings.linear;
    std::vector<double> a(n * 3), b(n * 3);
    for (size_t i = 0; i < n * 3; ++i) {
        a[i] = steps(image.rgb[i], linear);
        b[i] = steps(reference.rgb[i], linear);
    }
    if (settings.lossy) {
        a = box_means(a, c.width, c.height);
        b = box_means(b, c.width, c.height);
    }
    Vec3 sum(0.0);
    size_t off = 0;
    c.max_diff = -1;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const size_t p = static_cast<size_t>(y) * c.width + x;
            // The reference pixel of the neighbourhood nearest in colour (the pixel itself
            // without one, or off an edge of the reference), among those whose move of the
            // reference fits the image's 3x3 block around the pixel (block_fits).
            const int r = settings.neighbourhood && !settings.lossy &&
                                  on_edge(b, c.width, c.height, x, y, settings.tolerance)
                              ? 1
                              : 0;
            std::array<double, 3> best{};
            double best_signed = 0;
            double best_d = INFINITY;
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    const int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= c.width || qy >= c.height) continue;
                    if ((dx != 0 || dy != 0) &&
                        !block_fits(a, b, c.width, c.height, x, y, dx, dy, settings.tolerance))
                        continue;
                    const size_t q = static_cast<size_t>(qy) * c.width + qx;
                    std::array<double, 3> d;
                    double sd = 0;
                    for (size_t k = 0; k < 3; ++k) {
                        const double sg =
                            (a[p * 3 + k] - b[q * 3 + k]) /
                            std::max(1.0, b[q * 3 + k] / 255.0);  // relative above white
                        d[k] = std::abs(sg);
                        sd += sg / 3.0;
                    }
                    const double m = std::max({d[0], d[1], d[2]});
                    if (m < best_d) best_d = m, best = d, best_signed = sd;
                }
            sum += Vec3(best[0], best[1], best[2]);
            off += best_d > settings.tolerance;
            c.error[p] = static_cast<float>(best_d);
            c.signed_error[p] = static_cast<float>(best_signed);
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

Vec3 signed_colour(double t) {
    t = std::clamp(std::isfinite(t) ? t : 0.0, -1.0, 1.0);
    // Perceptually even enough: the brightness grows with |t| on either side.
    const double m = std::sqrt(std::abs(t));
    return t >= 0 ? Vec3(1.0, 0.55, 0.1) * m : Vec3(0.2, 0.5, 1.0) * m;
}

Image signed_map(const ImageComparison& c, double scale) {
    if (!(scale > 0)) scale = std::max(1.0, c.max_diff);
    Image out(c.width, c.height);
    if (c.signed_error.size() != static_cast<size_t>(c.width) * static_cast<size_t>(c.height))
        return out;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
            out.set(x, y,
                    signed_colour(double{c.signed_error[static_cast<size_t>(y) * c.width + x]} /
                                  scale));
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
