#include "rt/image/fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <stdexcept>

namespace rt {
namespace {

// Channel k of `im` at (x, y) in pixel units (pixel i's centre at i), bilinearly, the edge
// repeated outside.
double sample(const Image& im, double x, double y, int k) {
    x = std::clamp(x, 0.0, im.width - 1.0);
    y = std::clamp(y, 0.0, im.height - 1.0);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, im.width - 1), y1 = std::min(y0 + 1, im.height - 1);
    const double fx = x - x0, fy = y - y0;
    auto v = [&](int px, int py) {
        return im.rgb[(static_cast<size_t>(py) * im.width + px) * 3 + static_cast<size_t>(k)];
    };
    return (1 - fy) * ((1 - fx) * v(x0, y0) + fx * v(x1, y0)) +
           fy * ((1 - fx) * v(x0, y1) + fx * v(x1, y1));
}

// The parameter in [lo, hi] that makes `error` least: a grid of `steps` on a log scale (the
// error of a zoom has many local minima: the grid finds the right basin), then a golden-section
// search between the best point's neighbours.
double least(double lo, double hi, int steps, const std::function<double(double)>& error) {
    const double ratio = std::pow(hi / lo, 1.0 / steps);
    double best = lo, best_error = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= steps; ++i) {
        const double t = lo * std::pow(ratio, i);
        const double e = error(t);
        if (e < best_error) {
            best_error = e;
            best = t;
        }
    }
    double a = std::log(std::max(lo, best / ratio)), b = std::log(std::min(hi, best * ratio));
    const double g = (std::sqrt(5.0) - 1) / 2;
    double c = b - g * (b - a), d = a + g * (b - a);
    double ec = error(std::exp(c)), ed = error(std::exp(d));
    for (int i = 0; i < 30; ++i) {
        if (ec < ed) {
            b = d, d = c, ed = ec;
            c = b - g * (b - a);
            ec = error(std::exp(c));
        } else {
            a = c, c = d, ec = ed;
            d = a + g * (b - a);
            ed = error(std::exp(d));
        }
    }
    const double refined = std::exp(ec < ed ? c : d);
    return std::min(ec, ed) < best_error ? refined : best;
}

// Three significant digits: 2.2, 0.5, 2.14.
std::string short_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

}  // namespace

double mean_squared_bytes(const Image& reference, const Image& image) {
    if (reference.width != image.width || reference.height != image.height)
        throw std::invalid_argument("fit: the image is " + std::to_string(image.width) + "x" +
                                    std::to_string(image.height) + ", its reference " +
                                    std::to_string(reference.width) + "x" +
                                    std::to_string(reference.height));
    if (image.rgb.empty()) return 0.0;
    double sum = 0;
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        const double d = double(to_byte(reference.rgb[i])) - double(to_byte(image.rgb[i]));
        sum += d * d;
    }
    return sum / static_cast<double>(image.rgb.size());
}

namespace {

// Pixel (x, y) of the reference as `fit` changes it; `gamma` maps a value clamped to [0, 1]
// (Gamma only: exactly for the image, from a table while a search tries exponents).
template <class GammaFn>
Vec3 fitted_pixel(const Image& reference, const GlobalFit& fit, int x, int y,
                  const GammaFn& gamma) {
    const int w = reference.width, h = reference.height;
    switch (fit.kind) {
        case FitKind::Scale:
            return reference.at(x, y) * fit.value;
        case FitKind::Gamma: {
            const Vec3 c = glm::clamp(reference.at(x, y), 0.0, 1.0);
            return {gamma(c.x), gamma(c.y), gamma(c.z)};
        }
        case FitKind::FlipVertical:
            return reference.at(x, h - 1 - y);
        case FitKind::FlipHorizontal:
            return reference.at(w - 1 - x, y);
        case FitKind::Channels: {
            const Vec3 c = reference.at(x, y);
            return {c[fit.channels[0]], c[fit.channels[1]], c[fit.channels[2]]};
        }
        case FitKind::Zoom: {  // pixel centres about the image's centre
            const double rx = 0.5 * w + (x + 0.5 - 0.5 * w) / fit.value - 0.5;
            const double ry = 0.5 * h + (y + 0.5 - 0.5 * h) / fit.value - 0.5;
            return {sample(reference, rx, ry, 0), sample(reference, rx, ry, 1),
                    sample(reference, rx, ry, 2)};
        }
    }
    return {};
}

// The error of fits of one reference to one image, for the searches: the image's bytes made
// once, no image allocated per try, and a zoom tried on every other row and column.
class FitError {
public:
    FitError(const Image& reference, const Image& image)
        : m_reference(reference), m_bytes(to_bytes(image)) {}
    double operator()(const GlobalFit& fit) const {
        std::vector<double> table;  // c^(1/g) at 4096 steps of [0, 1]
        if (fit.kind == FitKind::Gamma) {
            table.resize(kSteps + 1);
            for (int i = 0; i <= kSteps; ++i)
                table[size_t(i)] = std::pow(double(i) / kSteps, 1.0 / fit.value);
        }
        auto gamma = [&](double c) { return table[size_t(c * kSteps + 0.5)]; };
        const int stride = fit.kind == FitKind::Zoom ? 2 : 1;
        double sum = 0;
        size_t n = 0;
        for (int y = 0; y < m_reference.height; y += stride)
            for (int x = 0; x < m_reference.width; x += stride) {
                const Vec3 c = fitted_pixel(m_reference, fit, x, y, gamma);
                const size_t i = (size_t(y) * m_reference.width + x) * 3;
                for (int k = 0; k < 3; ++k) {
                    const double d = double(to_byte(c[k])) - double(m_bytes[i + size_t(k)]);
                    sum += d * d;
                }
                n += 3;
            }
        return n ? sum / double(n) : 0.0;
    }

private:
    static constexpr int kSteps = 4096;
    const Image& m_reference;
    std::vector<uint8_t> m_bytes;
};

}  // namespace

Image apply_fit(const Image& reference, const GlobalFit& fit) {
    Image out(reference.width, reference.height);
    auto gamma = [&](double c) { return std::pow(c, 1.0 / fit.value); };
    for (int y = 0; y < reference.height; ++y)
        for (int x = 0; x < reference.width; ++x)
            out.set(x, y, fitted_pixel(reference, fit, x, y, gamma));
    return out;
}

std::string zoom_mistake(double k, double half_angle, double aspect) {
    auto near = [k](double v) { return std::abs(k / v - 1.0) < 0.03; };
    if (near(std::tan(half_angle) / std::tan(0.5 * half_angle))) return "full-angle";
    if (near(aspect)) return "angle-on-width";
    return "";
}

std::vector<FitResult> fit_global(const Image& reference, const Image& image) {
    const double before = mean_squared_bytes(reference, image);
    std::vector<FitResult> out;
    const FitError error(reference, image);
    auto add = [&](const GlobalFit& f, std::string name, std::string detail) {
        const double after = mean_squared_bytes(apply_fit(reference, f), image);
        FitResult r{f, std::move(name), std::move(detail), before, after};
        if (r.explained() > 0) out.push_back(std::move(r));
    };
    auto searched = [&](FitKind kind, double lo, double hi, int steps) {
        GlobalFit f{kind};
        f.value = least(lo, hi, steps, [&](double v) {
            GlobalFit g{kind};
            g.value = v;
            return error(g);
        });
        return f;
    };
    const GlobalFit scale = searched(FitKind::Scale, 0.05, 20, 32);
    add(scale, "brightness", "x " + short_number(scale.value));
    const GlobalFit gamma = searched(FitKind::Gamma, 0.2, 5, 32);
    add(gamma, "gamma", "exponent " + short_number(gamma.value));
    add({FitKind::FlipVertical}, "flip-vertical", "rows bottom-up");
    add({FitKind::FlipHorizontal}, "flip-horizontal", "columns right to left");
    const int perms[5][3] = {{2, 1, 0}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}};
    for (const auto& p : perms) {
        GlobalFit f{FitKind::Channels};
        std::copy(p, p + 3, f.channels);
        const std::string rgb = {"rgb"[p[0]], "rgb"[p[1]], "rgb"[p[2]]};
        add(f, rgb == "bgr" ? "bgr" : "channels " + rgb, "red, green, blue written as " + rgb);
    }
    const GlobalFit zoom = searched(FitKind::Zoom, 0.25, 4, 96);
    add(zoom, "zoom", "x " + short_number(zoom.value) + " about the centre");
    std::stable_sort(out.begin(), out.end(), [](const FitResult& a, const FitResult& b) {
        return a.error_after < b.error_after;
    });
    return out;
}

}  // namespace rt
