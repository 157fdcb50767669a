#include "report_dir.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "report.h"
#include "rt/util/file_io.h"

namespace raycompare {

namespace {

namespace fs = std::filesystem;

constexpr const char* kMarkerHeader =
    "raycompare report: the files named below were written by raycompare, which removes them "
    "when it writes a report here again";

// A marker of ours names a few files per image: a larger file of that name is someone else's.
constexpr size_t kMaxMarkerBytes = size_t{16} << 20;

// `s` from `at` is a decimal number up to `end` (at least one digit).
bool digits(const std::string& s, size_t at, size_t end) {
    if (at >= end || end > s.size()) return false;
    return std::all_of(s.begin() + static_cast<std::ptrdiff_t>(at),
                       s.begin() + static_cast<std::ptrdiff_t>(end),
                       [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

bool starts(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

bool ends(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string shown(const std::string& path) { return "'" + escaped(path) + "'"; }

}  // namespace

bool is_report_name(const std::string& name) {
    if (name == kPageName || name == kScaleName || name == kSignedScaleName || name == kMarkerName)
        return true;
    if (!ends(name, ".png")) return false;
    const size_t end = name.size() - 4;
    if (starts(name, "image_")) return digits(name, 6, end);
    if (starts(name, "heat_")) return digits(name, 5, end);
    if (starts(name, "signed_")) return digits(name, 7, end);
    if (starts(name, "mutant_")) return digits(name, 7, end);
    if (starts(name, "reference_")) {
        const size_t x = name.find('x', 10);
        return x != std::string::npos && digits(name, 10, x) && digits(name, x + 1, end);
    }
    return false;
}

ReportDir::ReportDir(const std::string& dir, const std::vector<std::string>& inputs) : m_dir(dir) {
    for (const std::string& p : inputs) {
        struct stat st {};
        if (::stat(p.c_str(), &st) == 0) m_inputs.emplace_back(st.st_dev, st.st_ino);
    }
    const std::string lead = "--html " + shown(dir) + ": ";
    std::error_code ec;
    const fs::file_status status = fs::status(dir, ec);
    if (fs::exists(status) && !fs::is_directory(status))
        throw ReportDirError(lead + "it is not a folder", true);
    const bool made = !fs::exists(status);
    if (made && !fs::create_directories(dir, ec) && ec)
        throw ReportDirError(lead + "cannot make the folder: " + ec.message(), false);
    // A folder made here for a report that is refused is removed again.
    const auto refuse = [&](const std::string& why) {
        if (made) fs::remove(dir, ec);
        throw ReportDirError(lead + why, true);
    };

    std::vector<std::string> names;  // what the folder holds
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        names.push_back(it->path().filename().string());
    if (ec) throw ReportDirError(lead + "cannot read the folder: " + ec.message(), false);

    std::string marker;
    if (!names.empty()) {
        const std::string marker_path = path_of(kMarkerName);
        std::error_code size_ec;
        const auto size = fs::file_size(marker_path, size_ec);
        if (size_ec || size > kMaxMarkerBytes || !rt::read_file(marker_path, &marker) ||
            marker.substr(0, marker.find('\n')) != kMarkerHeader)
            refuse(std::string("the folder is not empty and holds no report of raycompare (no ") +
                   kMarkerName +
                   " file): give a new or an empty folder, so that none of its files is replaced");
    }
    // A file of the report's names (existing or to be written, such as the --csv file) that is
    // one of the inputs: the report would replace it.
    for (const std::string& p : inputs) {
        const fs::path path(p);
        const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
        const std::string name = path.filename().string();
        if (is_report_name(name) && fs::equivalent(parent, dir, ec))
            refuse("the report writes a file named " + shown(name) + " there, and " + shown(p) +
                   " is one of the files given on the command line: give another folder");
    }
    for (const std::string& name : names)
        if (is_report_name(name) && is_input(path_of(name)))
            refuse("the report writes " + shown(path_of(name)) +
                   ", which is one of the files given on the command line: give another folder");

    if (!names.empty()) {
        // The earlier report's files, so that none of its rows stays (a larger class's).
        size_t at = marker.find('\n');
        while (at != std::string::npos && at + 1 < marker.size()) {
            const size_t next = marker.find('\n', at + 1);
            const std::string name = marker.substr(at + 1, next - at - 1);
            at = next;
            if (!is_report_name(name) || name == kMarkerName) continue;
            const std::string path = path_of(name);
            if (!fs::exists(fs::symlink_status(path, ec)) || is_input(path)) continue;
            if (!fs::remove(path, ec) && ec)
                throw ReportDirError(lead + "cannot remove the earlier report's " + shown(path) +
                                         ": " + ec.message(),
                                     false);
        }
    }
    try {
        rt::write_file_atomic(path_of(kMarkerName), std::string(kMarkerHeader) + "\n");
    } catch (const std::exception& e) {
        throw ReportDirError(e.what(), false);
    }
}

std::string ReportDir::path_of(const std::string& name) const {
    return (fs::path(m_dir) / name).string();
}

bool ReportDir::is_input(const std::string& path) const {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return false;
    return std::find(m_inputs.begin(), m_inputs.end(), std::make_pair(st.st_dev, st.st_ino)) !=
           m_inputs.end();
}

bool ReportDir::claim(const std::string& name) {
    if (!m_error.empty()) return false;
    const std::string path = path_of(name);
    if (is_input(path)) {
        m_error = "cannot write " + shown(path) + ": it is a file of the command line";
        return false;
    }
    // Named in the marker before it exists, so that a run stopped half way is cleaned up too.
    std::ofstream marker(path_of(kMarkerName), std::ios::app | std::ios::binary);
    marker << name << '\n';
    if (!marker.flush()) {
        m_error = "cannot write " + shown(path_of(kMarkerName));
        return false;
    }
    return true;
}

bool ReportDir::write_png(const std::string& name, const rt::Image& image) {
    if (!claim(name)) return false;
    try {
        rt::save_image(image, path_of(name));
    } catch (const std::exception& e) {
        m_error = e.what();
        return false;
    }
    return true;
}

bool ReportDir::write_text(const std::string& name, const std::string& text) {
    if (!claim(name)) return false;
    try {
        rt::write_file_atomic(path_of(name), text);
    } catch (const std::exception& e) {
        m_error = e.what();
        return false;
    }
    return true;
}

}  // namespace raycompare
