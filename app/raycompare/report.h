// raycompare's results: one row per image, printed as a table, written as CSV and as an HTML
// page a teacher opens from disk (the images beside it, no server, no external links).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "rt/image/compare.h"

namespace raycompare {

/// One image compared with the reference of its size (or why it could not be): its numbers
/// only. Its pixels and its heat map are written to the report as it is compared, and dropped.
struct Row {
    std::string path;
    int width = 0, height = 0;  // 0: unknown (the image could not be read)
    std::string error;          // empty: compared
    rt::ImageComparison c;      // without the per-pixel differences (c.error is empty)
    bool pass = false;
    bool image_written = false;  // image_N.png is in the report (N: the row's place, from 1)
    bool heat_written = false;   // heat_N.png too, on a scale of 0 to heat_scale
    double heat_scale = 1;
};

/// What decided pass or fail.
struct Limits {
    double tolerance = 8;    // 8-bit steps
    double max_bad = 0.005;  // share of pixels off by more than the tolerance
    bool neighbourhood = false;
};

/// A name or a message as the terminal shows it: control bytes and bytes that are not UTF-8
/// written as \xNN, as the scene's error messages write them, so that a file's name cannot move
/// the cursor or rewrite a row (a name ending in "\r...PASS").
std::string escaped(std::string_view s);

/// The table: file, size, mean absolute difference, share off, largest difference and where,
/// PASS or FAIL (or the error), one line each; names and errors escaped().
std::string table_text(const std::vector<Row>& rows, const Limits& limits);

/// The same as CSV (a header line, then one line per image; names and errors escaped(), fields
/// quoted where needed).
std::string csv_text(const std::vector<Row>& rows);

/// A reference image's size, for the page (its file: reference_name()).
struct Reference {
    int width = 0, height = 0;
};

/// The names of the report's files in its folder.
std::string image_name(size_t row);  // image_N.png, N = row + 1
std::string heat_name(size_t row);   // heat_N.png
std::string reference_name(int width, int height);
inline constexpr const char* kScaleName = "scale.png";
inline constexpr const char* kPageName = "index.html";

/// The heat map's scale bar (kScaleName): a horizontal ramp of rt::heat_colour.
rt::Image scale_bar();

/// The page, index.html: the references, and one row per image (its image and heat map when
/// written, with the scale bar, its figures, pass or fail; sortable by each column).
std::string page_html(const std::string& scene, const std::vector<Reference>& references,
                      const std::vector<Row>& rows, const Limits& limits);

}  // namespace raycompare
