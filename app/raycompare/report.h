// raycompare's results: one row per image, printed as a table, written as CSV and as an HTML
// page a teacher opens from disk (the images beside it, no server, no external links).
#pragma once

#include <string>
#include <vector>

#include "rt/image/compare.h"

namespace raycompare {

/// One image compared with the reference of its size (or why it could not be).
struct Row {
    std::string path;
    int width = 0, height = 0;
    std::string error;  // empty: compared
    rt::ImageComparison c;
    bool pass = false;
    rt::Image image;  // as read (for the page)
};

/// What decided pass or fail.
struct Limits {
    double tolerance = 8;    // 8-bit steps
    double max_bad = 0.005;  // share of pixels off by more than the tolerance
    bool neighbourhood = false;
};

/// The table: file, size, mean absolute difference, share off, largest difference and where,
/// PASS or FAIL (or the error), one line each.
std::string table_text(const std::vector<Row>& rows, const Limits& limits);

/// The same as CSV (a header line, then one line per image; fields quoted where needed).
std::string csv_text(const std::vector<Row>& rows);

/// A reference image of one size, for the page.
struct Reference {
    int width = 0, height = 0;
    rt::Image image;
};

/// Writes DIR/index.html with the references and one row per image (the image, its heat map
/// with the scale bar, its figures, pass or fail; sortable by each column), and the PNGs beside
/// it. Every file is written atomically, index.html last. Throws std::runtime_error.
void write_html(const std::string& dir, const std::string& scene,
                const std::vector<Reference>& references, const std::vector<Row>& rows,
                const Limits& limits);

}  // namespace raycompare
