// imgdiff: how far one image is from another of the same size, for the viewer's tests and the
// preview-against-trace measurements. Prints the mean absolute difference per channel (0-255)
// and the share of pixels where the second image is bright (luminance > 0.3) and the first one
// nearly black (< 0.05): "the preview shows black where the trace is lit" when called as
// imgdiff PREVIEW TRACE, the share of pixels off by more than K/255 in one channel (--off, 32 by
// default), and the largest difference of one value (linear, 1 = white). Reads the
// 8-bit formats, PFM and EXR (rt::load_image). Exits 1 when a limit given is exceeded, 2 on a
// usage or read error.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli.h"
#include "rt/image/image.h"

namespace {

double luminance(const rt::Image& im, size_t i) {
    return 0.2126 * im.rgb[i] + 0.7152 * im.rgb[i + 1] + 0.0722 * im.rgb[i + 2];
}

bool eight_bit(const std::string& path) {
    return !rt::holds_linear(rt::image_format_from_path(path));
}

struct Region {
    int x = 0, y = 0, w = 0, h = 0;
};

/// What a comparison measures over a region of two images of the same size.
struct Stats {
    double mad[3] = {0, 0, 0};  // mean absolute difference per channel, 0-255
    double dark_share = 0;      // dark in A where B is lit
    long dark = 0;
    double off_share = 0;  // off by more than `off`/255 in one channel
    long off_count = 0;
    double largest = 0;  // the largest difference of one value, linear
    double pixels = 0;
};

Stats measure(const rt::Image& a, const rt::Image& b, const Region& r, bool bytes, double off) {
    Stats s;
    for (int y = r.y; y < r.y + r.h; ++y)
        for (int x = r.x; x < r.x + r.w; ++x) {
            const size_t i = (static_cast<size_t>(y) * a.width + x) * 3;
            bool is_off = false;
            for (size_t k = 0; k < 3; ++k) {
                const double d = std::abs(a.rgb[i + k] - b.rgb[i + k]);
                const double d255 = bytes ? std::round(255 * d) : 255 * d;
                s.mad[k] += d255;
                is_off |= d255 > off;
                s.largest = std::max(s.largest, d);
            }
            s.off_count += is_off;
            s.dark += luminance(b, i) > 0.3 && luminance(a, i) < 0.05;
        }
    s.pixels = static_cast<double>(r.w) * r.h;
    for (double& m : s.mad) m /= s.pixels;
    s.dark_share = static_cast<double>(s.dark) / s.pixels;
    s.off_share = static_cast<double>(s.off_count) / s.pixels;
    return s;
}

/// Both images, of the same size, and the region compared; false after printing why not.
bool load_pair(const std::string& a_path, const std::string& b_path, const std::vector<int>& crop,
               rt::Image* a, rt::Image* b, Region* r) {
    try {
        *a = rt::load_image(a_path);
        *b = rt::load_image(b_path);
    } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "imgdiff: error: %s\n", e.what());
        return false;
    }
    if (a->width != b->width || a->height != b->height) {
        std::fprintf(stderr, "imgdiff: error: %s is %dx%d but %s is %dx%d\n", a_path.c_str(),
                     a->width, a->height, b_path.c_str(), b->width, b->height);
        return false;
    }
    *r = {0, 0, a->width, a->height};
    if (crop.size() == 4) *r = {crop[0], crop[1], crop[2], crop[3]};
    if (r->x < 0 || r->y < 0 || r->w <= 0 || r->h <= 0 || r->x + r->w > a->width ||
        r->y + r->h > a->height) {
        std::fprintf(stderr, "imgdiff: error: the crop is outside the %dx%d images\n", a->width,
                     a->height);
        return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::string a_path, b_path;
    double max_mad = -1, max_dark = -1, max_abs = -1, off = 32, max_off = -1;
    std::vector<int> crop;
    CLI::App app{
        "Compares two images of the same size: mean absolute difference per channel "
        "(0-255) and the share of pixels dark in A (luminance < 0.05) where B is lit "
        "(> 0.3)."};
    rtapp::setup_cli(app, "imgdiff");
    app.add_option("a", a_path, "the first image (e.g. the preview)")->required();
    app.add_option("b", b_path, "the second image (e.g. the trace)")->required();
    app.add_option("--max-mad", max_mad, "exit 1 when a channel's mean difference exceeds X")
        ->type_name("X");
    app.add_option("--max-dark-share", max_dark, "exit 1 when the dark-where-lit share exceeds S")
        ->type_name("S");
    app.add_option("--max-abs", max_abs,
                   "exit 1 when a value differs by more than X (linear, 1 = white; 0: the "
                   "same values)")
        ->type_name("X");
    app.add_option("--off", off, "count the pixels off by more than K/255 in one channel")
        ->type_name("K")
        ->capture_default_str();
    app.add_option("--max-off-share", max_off,
                   "exit 1 when the share of pixels off by more than --off exceeds S")
        ->type_name("S");
    app.add_option("--crop", crop, "compare only this rectangle of both images")
        ->type_name("X Y W H")
        ->expected(4);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return rtapp::cli_exit(app, e);
    }

    rt::Image a, b;
    Region r;
    if (!load_pair(a_path, b_path, crop, &a, &b, &r)) return 2;
    // Two 8-bit files differ by whole steps of 1/255: counted exactly.
    const Stats s = measure(a, b, r, eight_bit(a_path) && eight_bit(b_path), off);
    std::printf("mean abs diff %.2f %.2f %.2f; dark where lit %.4f (%ld of %.0f pixels)\n",
                s.mad[0], s.mad[1], s.mad[2], s.dark_share, s.dark, s.pixels);
    std::printf("off by more than %g/255: %.4f (%ld pixels)\n", off, s.off_share, s.off_count);
    std::printf("max abs diff %.6g\n", s.largest);
    bool over = (max_dark >= 0 && s.dark_share > max_dark) ||
                (max_abs >= 0 && s.largest > max_abs) || (max_off >= 0 && s.off_share > max_off);
    for (double m : s.mad) over |= max_mad >= 0 && m > max_mad;
    return over ? 1 : 0;
}
