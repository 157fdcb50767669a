// imgdiff: how far one image is from another of the same size, for the viewer's tests and the
// preview-against-trace measurements. Prints the mean absolute difference per channel (0-255)
// and the share of pixels where the second image is bright (luminance > 0.3) and the first one
// nearly black (< 0.05): "the preview shows black where the trace is lit" when called as
// imgdiff PREVIEW TRACE. Exits 1 when a limit given is exceeded, 2 on a usage or read error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "rt/image/image.h"

namespace {

double luminance(const rt::TextureImage& im, size_t i) {
    return (0.2126 * im.rgb[i] + 0.7152 * im.rgb[i + 1] + 0.0722 * im.rgb[i + 2]) / 255.0;
}

struct Region {
    int x = 0, y = 0, w = 0, h = 0;
};

}  // namespace

int main(int argc, char** argv) {
    std::string a_path, b_path;
    double max_mad = -1, max_dark = -1;
    std::vector<int> crop;
    CLI::App app{
        "Compares two images of the same size: mean absolute difference per channel "
        "(0-255) and the share of pixels dark in A (luminance < 0.05) where B is lit "
        "(> 0.3).",
        "imgdiff"};
    app.add_option("a", a_path, "the first image (e.g. the preview)")->required();
    app.add_option("b", b_path, "the second image (e.g. the trace)")->required();
    app.add_option("--max-mad", max_mad, "exit 1 when a channel's mean difference exceeds X")
        ->type_name("X");
    app.add_option("--max-dark-share", max_dark, "exit 1 when the dark-where-lit share exceeds S")
        ->type_name("S");
    app.add_option("--crop", crop, "compare only this rectangle of both images")
        ->type_name("X Y W H")
        ->expected(4);
    CLI11_PARSE(app, argc, argv);

    rt::TextureImage a, b;
    std::string error;
    if (!rt::load_texture_image(a_path, &a, &error) ||
        !rt::load_texture_image(b_path, &b, &error)) {
        std::fprintf(stderr, "imgdiff: error: %s\n", error.c_str());
        return 2;
    }
    if (a.width != b.width || a.height != b.height) {
        std::fprintf(stderr, "imgdiff: error: %s is %dx%d but %s is %dx%d\n", a_path.c_str(),
                     a.width, a.height, b_path.c_str(), b.width, b.height);
        return 2;
    }
    Region r{0, 0, a.width, a.height};
    if (crop.size() == 4) r = {crop[0], crop[1], crop[2], crop[3]};
    if (r.x < 0 || r.y < 0 || r.w <= 0 || r.h <= 0 || r.x + r.w > a.width || r.y + r.h > a.height) {
        std::fprintf(stderr, "imgdiff: error: the crop is outside the %dx%d images\n", a.width,
                     a.height);
        return 2;
    }
    double sum[3] = {0, 0, 0};
    long dark = 0;
    for (int y = r.y; y < r.y + r.h; ++y)
        for (int x = r.x; x < r.x + r.w; ++x) {
            const size_t i = (static_cast<size_t>(y) * a.width + x) * 3;
            for (int k = 0; k < 3; ++k) sum[k] += std::abs(int(a.rgb[i + k]) - int(b.rgb[i + k]));
            dark += luminance(b, i) > 0.3 && luminance(a, i) < 0.05;
        }
    const double n = static_cast<double>(r.w) * r.h;
    const double mad[3] = {sum[0] / n, sum[1] / n, sum[2] / n};
    const double share = static_cast<double>(dark) / n;
    std::printf("mean abs diff %.2f %.2f %.2f; dark where lit %.4f (%ld of %.0f pixels)\n", mad[0],
                mad[1], mad[2], share, dark, n);
    bool over = max_dark >= 0 && share > max_dark;
    for (double m : mad) over |= max_mad >= 0 && m > max_mad;
    return over ? 1 : 0;
}
