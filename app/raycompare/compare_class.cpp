#include "compare_class.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <utility>

#include "cli.h"
#include "rt/image/compare.h"
#include "rt/util/file_io.h"
#include "rt/util/text.h"

namespace raycompare {

namespace {

std::string size_text(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

// A JPEG file by its name (.jpg, .jpeg in any case): compared under the lossy rule.
bool jpeg_name(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".jpg" || ext == ".jpeg";
}

// Row `n` (its size known) against the reference of its size: the image read again, compared,
// written to the report with its heat map, and dropped with its per-pixel differences; the row
// keeps the numbers. What goes wrong is the row's error.
// The diagnosis of a failing 8-bit image: Row::diagnosis, one explanation a line, and the first
// one's mutant reference in the report (mutant_N.png). What goes wrong is said in its place.
void diagnose_one(Row& r, size_t n, const rt::Image& image, rt::MutantRenders& mutants,
                  const Diagnoser& diagnoser, ReportDir* report) {
    try {
        const rt::Diagnosis d =
            rt::diagnose(image, mutants, diagnoser.catalogue, diagnoser.settings);
        r.diagnosis = d.ranked.empty() ? d.summary() : "";
        for (size_t k = 0; k < d.ranked.size(); ++k) {
            char share[40];
            std::snprintf(share, sizeof share, " (explains %.0f%%)", 100 * d.ranked[k].explained);
            r.diagnosis +=
                (k ? "\n" : "") + std::to_string(k + 1) + ". " + d.ranked[k].name() + share;
        }
        if (report && !d.ranked.empty())
            r.mutant_written = report->write_png(mutant_name(n), d.ranked[0].mutant);
    } catch (const std::exception& e) {
        r.diagnosis = rtapp::error_text(e, "diagnosing " + r.path);
    }
}

void compare_one(Row& r, size_t n, const rt::Image& reference, const Limits& limits,
                 ReportDir* report, rt::MutantRenders* mutants, const Diagnoser* diagnoser) {
    try {
        rt::ImageComparison c;
        {
            const rt::Image image = rt::load_image(r.path);
            if (image.width != r.width || image.height != r.height)
                throw std::runtime_error("'" + r.path + "' changed while it was compared (" +
                                         size_text(r.width, r.height) + ", then " +
                                         size_text(image.width, image.height) + ")");
            rt::CompareSettings cs;
            cs.tolerance = limits.tolerance;
            cs.neighbourhood = limits.neighbourhood;
            cs.lossy = r.lossy;
            cs.linear = rt::holds_linear(rt::image_format_from_path(r.path));
            c = rt::compare_images(image, reference, cs);
            if (report) r.image_written = report->write_png(image_name(n), image);
            if (mutants && !cs.linear && c.share_off > limits.max_bad)
                diagnose_one(r, n, image, *mutants, *diagnoser, report);
        }
        r.heat_scale = limits.heat_scale;  // one scale for the class
        if (report) {
            r.heat_written = report->write_png(heat_name(n), rt::heat_map(c, r.heat_scale));
            r.signed_written = report->write_png(signed_name(n), rt::signed_map(c, r.heat_scale));
        }
        // 8 bytes a pixel: the row keeps the numbers only
        std::vector<float>().swap(c.error);
        std::vector<float>().swap(c.signed_error);
        r.c = std::move(c);
        r.pass = r.c.share_off <= limits.max_bad;
    } catch (const std::exception& e) {
        r.error = rtapp::error_text(e, "comparing " + r.path);
        r.pass = false;
    }
}

}  // namespace

ClassResult compare_class(const std::vector<std::string>& images, const RenderReference& render,
                          const Limits& limits, ReportDir* report,
                          const std::function<void(int width, int height)>& rendered,
                          const Diagnoser* diagnoser) {
    ClassResult out;
    out.rows.resize(images.size());
    out.width = limits.width;
    out.height = limits.height;
    const std::vector<std::string> names = student_names(images);
    // The sizes, in the order they first appear; each image's pixels are dropped once read.
    std::vector<std::pair<int, int>> sizes;
    for (size_t i = 0; i < images.size(); ++i) {
        Row& r = out.rows[i];
        r.path = images[i];
        r.name = names[i];
        r.lossy = limits.lossy || jpeg_name(r.path);
        struct stat st {};
        if (::stat(r.path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size == 0) {
            r.error = "cannot read " + rt::quote(r.path) + ": empty file";
            r.unreadable = true;
            continue;
        }
        try {
            const rt::Image image = rt::load_image(r.path);
            r.width = image.width;
            r.height = image.height;
        } catch (const std::exception& e) {
            r.error = rtapp::error_text(e, "reading " + r.path);
            r.unreadable = true;
            continue;
        }
        if (out.width == 0) out.width = r.width, out.height = r.height;  // the first's size
        if (out.width > 0 && (r.width != out.width || r.height != out.height)) {
            r.error = "the image is " + size_text(r.width, r.height) + ", not the expected " +
                      size_text(out.width, out.height) +
                      (limits.width > 0 ? " (--size)"
                                        : " (the first image's size; set it with --size WxH)");
            continue;
        }
        if (std::find(sizes.begin(), sizes.end(), std::make_pair(r.width, r.height)) == sizes.end())
            sizes.emplace_back(r.width, r.height);
    }
    if (report) {
        report->write_png(kScaleName, scale_bar());
        report->write_png(kSignedScaleName, signed_scale_bar());
    }
    for (const auto& [width, height] : sizes) {
        rt::Image reference;
        std::string failed;
        try {
            reference = render(width, height);
        } catch (const std::exception& e) {
            failed =
                rtapp::error_text(e, "rendering the " + size_text(width, height) + " reference");
        }
        if (failed.empty()) {
            if (rendered) rendered(width, height);
            out.references.push_back({width, height});
            if (report) report->write_png(reference_name(width, height), reference);
        }
        // The mutants of this size, each rendered once for the class (when asked for).
        std::optional<rt::MutantRenders> mutants;
        if (diagnoser)
            mutants.emplace([&, w = width, h = height](const std::vector<std::string>& m) {
                return diagnoser->render(w, h, m);
            });
        for (size_t i = 0; i < out.rows.size(); ++i) {
            Row& r = out.rows[i];
            if (r.width != width || r.height != height || !r.error.empty()) continue;
            if (failed.empty())
                compare_one(r, i, reference, limits, report, mutants ? &*mutants : nullptr,
                            diagnoser);
            else
                r.error = failed;
        }
        if (mutants) out.mutant_renders += mutants->renders();
    }
    return out;
}

}  // namespace raycompare
