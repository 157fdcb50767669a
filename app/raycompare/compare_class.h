// raycompare's work on a class's images, one image at a time, so that a class of any size fits
// in the memory of a few images: each image is read, compared with the reference of its size,
// its report images written, and only its numbers kept; one reference is held at a time, and
// what goes wrong with one image (a bad file, out of memory, a reference that cannot be
// rendered) is that image's FAIL row, never the end of the class. raycompare's main.cpp and the
// fuzz target (tests/fuzz/fuzz_compare.cpp) call it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "report.h"
#include "report_dir.h"
#include "rt/image/diagnose.h"
#include "rt/image/image.h"

namespace raycompare {

/// Renders the reference of a width x height image; throws what it cannot (out of memory).
using RenderReference = std::function<rt::Image(int width, int height)>;

/// --diagnose: the reference of a width x height image rendered with the named mistakes on, as
/// its 8-bit file holds it (rt::render_written), the catalogue's names, and the settings.
struct Diagnoser {
    std::function<rt::Image(int width, int height, const std::vector<std::string>& mistakes)>
        render;
    std::vector<std::string> catalogue;
    rt::DiagnoseSettings settings;
};

/// What compare_class() made: one row per image, in the order given, and the references
/// rendered (those in the report as reference_WxH.png when it was written).
struct ClassResult {
    std::vector<Row> rows;
    std::vector<Reference> references;
    /// The size the images were held to (limits' width and height, the first readable image's
    /// for 0); -1 when any size was taken.
    int width = -1, height = -1;
    size_t mutant_renders = 0;  // with a diagnoser: the mutant references rendered
};

/// Compares each image with the reference. First each image is read to learn its size (its
/// pixels dropped at once; an empty file, or one that is no image, is a row that cannot be read);
/// an image of another size than the expected one (limits.width x height, 0: the first readable
/// image's) fails with that reason and is not compared. Then the reference is rendered once,
/// the images compared (JPEG files, or every image with limits.lossy, under the lossy rule), and
/// the reference dropped; with limits.width -1 (any size), one reference per size, in the order
/// they first appear. Each row is named by student_names(). With `report`, writes the
/// references, each image (image_N.png), its heat map (heat_N.png) and signed view
/// (signed_N.png) on the class's scale (limits.heat_scale) and the scale bars as it goes; not
/// the page (page_html()). `rendered`, when given, is told of
/// each reference rendered (main.cpp prints it). With `diagnoser`, each failing 8-bit image is
/// diagnosed (Row::diagnosis, and its first explanation's mutant as mutant_N.png in the
/// report), each mutant rendered once per size for the class.
ClassResult compare_class(const std::vector<std::string>& images, const RenderReference& render,
                          const Limits& limits, ReportDir* report,
                          const std::function<void(int width, int height)>& rendered = {},
                          const Diagnoser* diagnoser = nullptr);

}  // namespace raycompare
