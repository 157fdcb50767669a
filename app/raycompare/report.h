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
    std::string name;           // the student's: student_names()' (empty: the path's)
    int width = 0, height = 0;  // 0: unknown (the image could not be read)
    std::string error;          // empty: compared
    bool unreadable = false;    // the error is that the file cannot be read as an image
    bool lossy = false;         // compared under the lossy rule (--lossy, or a JPEG file)
    rt::ImageComparison c;      // without the per-pixel differences (c.error is empty)
    bool pass = false;
    bool image_written = false;   // image_N.png is in the report (N: the row's place, from 1)
    bool heat_written = false;    // heat_N.png too, on a scale of 0 to heat_scale
    bool signed_written = false;  // signed_N.png too, on the same scale
    double heat_scale = 1;
    /// The mistakes that best explain a failing image, one a line, best first: empty until a
    /// diagnosis fills it (a later --diagnose). The table, the page and Gradescope's output show
    /// it under the row when it is not empty.
    std::string diagnosis;
    bool mutant_written = false;  // mutant_N.png: the reference as the first explanation makes it
};

/// What decided pass or fail.
struct Limits {
    double tolerance = 8;    // 8-bit steps
    double max_bad = 0.005;  // share of pixels off by more than the tolerance
    bool neighbourhood = false;
    bool lossy = false;  // the lossy rule for every image (it is always used for JPEG files)
    /// The size every image must have (--size WxH); 0: the first readable image's; -1: any size,
    /// each image against a reference of its own size (--size any).
    int width = 0, height = 0;
    /// The heat map's and the signed view's scale for the whole class: full colour at this many
    /// 8-bit steps and beyond.
    double heat_scale = 64;
};

/// The rule as one sentence (the table's header, the page's, Gradescope's output).
std::string rule_text(const Limits& limits);

/// How many pass, fail, and cannot be read: "6 images: 2 pass, 3 fail, 1 cannot be read".
std::string summary_text(const std::vector<Row>& rows);

/// The students' names for the images, in order: each file's stem ("ann" for ann.png); when
/// stems repeat (a class laid out as one folder per student: class/ann/scene.png), the folder's
/// name; when those repeat too, folder/stem. Never more of the path than that.
std::vector<std::string> student_names(const std::vector<std::string>& paths);

/// The columns a terminal gives `s` (UTF-8): one a character, two for a wide (East Asian) one,
/// none for a combining mark; a byte that is not UTF-8 counts one.
size_t display_width(std::string_view s);

/// The command that explains the worst pixel of a row: raytrace SCENE --width W --height H
/// --inspect X,Y (the scene quoted for a POSIX shell when needed). Empty for a row not compared.
std::string inspect_command(const std::string& scene, const Row& r);

/// The row's verdict in words: "PASS: 0.1% off (at most 0.5%)", "FAIL: 12.3% of pixels off by
/// more than 8 (at most 0.5%); the largest difference 72 at (3,4)", or "FAIL: " and why.
std::string reason_text(const Row& r, const Limits& limits);

/// Gradescope's autograder results (results.json): one test per image (its name, 1 point for a
/// pass, its reason, the worst pixel's --inspect command, and the diagnosis when there is one),
/// score and max_score their sums, the summary and the rule as the output.
std::string gradescope_json(const std::string& scene, const std::vector<Row>& rows,
                            const Limits& limits);

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
std::string image_name(size_t row);   // image_N.png, N = row + 1
std::string heat_name(size_t row);    // heat_N.png
std::string signed_name(size_t row);  // signed_N.png
std::string mutant_name(size_t row);  // mutant_N.png
std::string reference_name(int width, int height);
inline constexpr const char* kScaleName = "scale.png";
inline constexpr const char* kPageName = "index.html";

inline constexpr const char* kSignedScaleName = "signed_scale.png";

/// The heat map's scale bar (kScaleName): a horizontal ramp of rt::heat_colour.
rt::Image scale_bar();
/// The signed view's (kSignedScaleName): rt::signed_colour from -1 (left) to 1.
rt::Image signed_scale_bar();

/// The page, index.html: the references, and one row per image (its image and heat map when
/// written, with the scale bar, its figures, pass or fail; sortable by each column).
std::string page_html(const std::string& scene, const std::vector<Reference>& references,
                      const std::vector<Row>& rows, const Limits& limits);

}  // namespace raycompare
