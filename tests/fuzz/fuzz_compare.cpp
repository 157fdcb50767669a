// libFuzzer target: file bytes -> raycompare's comparison path (app/raycompare/compare_class.h):
// the bytes as a student's image (named .pfm, .exr or .png after their first bytes, so that each
// reader is reached), read, compared with a small fixed reference of its size (with
// --neighbourhood for an odd number of bytes), written to an HTML report in a new folder (its
// image, heat map, scale bar, reference and page), and the table and CSV made; for one input in
// 8, the same class again into that folder, which holds our report now (its files replaced); then
// the folder removed. Any input must end in a row, PASS or FAIL: a crash, a sanitizer report, an
// exception out of compare_class(), a report file beside an unreadable image, or a control byte
// in the table (the name is the bytes, too) is a bug.
//
// The image budget is 64x64 pixels, so that every execution is fast (the checks are the same at
// any budget). Seeds: tests/fuzz/corpus/compare.
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_util.h"
#include "raycompare/compare_class.h"
#include "rt/util/limits.h"

namespace {

namespace fs = std::filesystem;

// The reference of any size: a fixed pattern of the size asked for, in [0, 1] and beyond (a
// linear image's highlights).
rt::Image reference(int width, int height) {
    rt::Image image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image.set(x, y, {(x % 8) / 7.0, (y % 4) / 3.0, (x + y) % 5 == 0 ? 2.0 : 0.25});
    return image;
}

const char* extension(std::string_view data) {
    if (data.substr(0, 2) == "PF") return ".pfm";
    if (data.substr(0, 4) == std::string_view("\x76\x2f\x31\x01", 4)) return ".exr";
    return ".png";
}

// Aborts when `text` holds a byte that would reach the terminal as a control (a line break
// only ends a line).
void printable(const std::string& text) {
    for (const char c : text) {
        const auto b = static_cast<unsigned char>(c);
        if ((b < 0x20 && b != '\n') || b == 0x7F) std::abort();
    }
}

void run_class(const std::string& image, const std::string& dir, bool first, bool neighbourhood) {
    raycompare::Limits limits;
    limits.neighbourhood = neighbourhood;
    raycompare::ReportDir report(dir, {image});
    const raycompare::ClassResult result =
        raycompare::compare_class({image}, reference, limits, &report);
    if (result.rows.size() != 1) std::abort();
    const raycompare::Row& row = result.rows[0];
    const bool compared = row.error.empty();
    // An image compared has its image and heat map in the report; one that was not has neither.
    if (report.error().empty() &&
        (row.image_written != compared || row.heat_written != compared ||
         fs::exists(fs::path(dir) / raycompare::image_name(0)) != compared ||
         fs::exists(fs::path(dir) / raycompare::heat_name(0)) != compared))
        std::abort();
    if (!compared && row.pass) std::abort();
    printable(raycompare::table_text(result.rows, limits));
    (void)raycompare::csv_text(result.rows);
    report.write_text(raycompare::kPageName,
                      raycompare::page_html("scene.ray", result.references, result.rows, limits));
    if (first && !report.error().empty()) std::abort();  // a new folder of ours takes every file
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    (void)rt_fuzz::work_dir();
    rt::set_max_image_pixels(64 * 64);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* bytes, size_t size) {
    const std::string_view data(reinterpret_cast<const char*>(bytes), size);
    const std::string image = rt_fuzz::write_file(std::string("student") + extension(data), data);
    const std::string dir = rt_fuzz::work_dir() + "/report";
    std::error_code ec;
    fs::remove_all(dir, ec);
    try {
        run_class(image, dir, true, size % 2 == 1);
        // Into our own report again, which it replaces: for one input in 8, as the PNG writer
        // (instrumented) takes most of an execution and the folder's handling is the same for
        // any input.
        if (size % 8 == 0) run_class(image, dir, false, size % 2 == 0);
    } catch (const raycompare::ReportDirError&) {
        std::abort();  // a new folder, then our own report's: both are the report's to take
    }
    fs::remove_all(dir, ec);
    // The table of a row named by the bytes themselves (no such file) shows no control byte.
    raycompare::Row named;
    named.path = std::string(data.substr(0, 256));
    named.error = "cannot read '" + named.path + "': " + named.path;
    printable(raycompare::table_text({named}, {}));
    printable(raycompare::csv_text({named}));
    return 0;
}
