// The HTML report's folder (raycompare --html DIR). A teacher often points it at the folder of
// the students' images, whose names (image_1.png, ...) may be the report's own: the report never
// writes into a folder of someone else's files, and never replaces or removes a file named on the
// command line, whatever its name (checked by identity: device and inode, so neither a second
// name, a link nor a relative path gets past it).
#pragma once

#include <sys/types.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rt/image/image.h"

namespace raycompare {

/// The marker file that says a folder holds a report of ours: its first line says so, the next
/// ones name the files the report wrote (each added before the file is written).
inline constexpr const char* kMarkerName = ".raycompare-report";

/// A name the report writes: index.html, scale.png, signed_scale.png, image_N.png, heat_N.png,
/// signed_N.png, mutant_N.png, reference_WxH.png (N, W, H decimal numbers) or the marker.
bool is_report_name(const std::string& name);

/// A folder that cannot take the report; said before anything is rendered. `refused`: the
/// folder is the wrong one (someone else's files, an input's name: exit status 2), else it could
/// not be made or written (exit status 1, as an output that cannot be written).
struct ReportDirError : std::runtime_error {
    ReportDirError(const std::string& what, bool is_refusal)
        : std::runtime_error(what), refused(is_refusal) {}
    bool refused;
};

class ReportDir {
public:
    /// Takes `dir` for the report, with `inputs` the files named on the command line (those that
    /// do not exist yet, such as the --csv file, are kept by name). `dir` may be missing (it is
    /// made), empty, or hold a report of ours (the marker file): then the files its marker names
    /// are removed, so that no row of the earlier report stays. Throws ReportDirError when `dir`
    /// holds other files and no marker, is not a folder, cannot be written, or when a file of the
    /// report's names is one of the inputs.
    ReportDir(const std::string& dir, const std::vector<std::string>& inputs);

    const std::string& dir() const { return m_dir; }

    /// Writes `image` as the report's PNG `name` (a name of is_report_name()), replacing an
    /// earlier file of ours; never an input. False after a failure, whose message error() keeps
    /// (the first one): the report stops there, and the comparison goes on.
    bool write_png(const std::string& name, const rt::Image& image);
    /// The same for a text file (the page).
    bool write_text(const std::string& name, const std::string& text);

    /// Empty, or why the report could not be written.
    const std::string& error() const { return m_error; }

private:
    // Adds `name` to the marker and checks that it is no input; false after a failure.
    bool claim(const std::string& name);
    std::string path_of(const std::string& name) const;
    bool is_input(const std::string& path) const;

    std::string m_dir;
    std::vector<std::pair<dev_t, ino_t>> m_inputs;  // the inputs that exist
    std::string m_error;
};

}  // namespace raycompare
