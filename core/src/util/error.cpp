#include "rt/util/error.h"

#include <mutex>
#include <unordered_set>

namespace rt {

const std::string* intern_file_name(std::string_view name) {
    // Never freed: the names are few (the files a program opened), and locations that outlive
    // their scene (an error kept by the viewer) stay valid.
    static std::mutex mutex;
    static std::unordered_set<std::string>* names = new std::unordered_set<std::string>;
    const std::lock_guard<std::mutex> lock(mutex);
    return &*names->emplace(name).first;
}

std::string SourceLoc::str() const {
    std::string s = file ? *file : std::string("<input>");
    if (line > 0) {
        s += ':';
        s += std::to_string(line);
        s += ':';
        s += std::to_string(col);
    }
    return s;
}

static std::string format_error(const SourceLoc& loc, const std::string& message,
                                const std::vector<SourceLoc>& included_from) {
    std::string s = loc.str() + ": error: " + message;
    for (const SourceLoc& inc : included_from) s += "\n  included from " + inc.str();
    return s;
}

SceneError::SceneError(SourceLoc loc, std::string message, std::vector<SourceLoc> included_from)
    : std::runtime_error(format_error(loc, message, included_from)),
      m_loc(std::move(loc)),
      m_message(std::move(message)),
      m_included_from(std::move(included_from)) {}

std::string Warning::str() const {
    std::string s = loc.str() + ": warning: " + message;
    if (count > 1) s += " (" + std::to_string(count) + " times in this file)";
    for (const SourceLoc& inc : included_from) s += "\n  included from " + inc.str();
    return s;
}

void Diagnostics::warn(const SourceLoc& loc, std::string kind, std::string message,
                       std::vector<SourceLoc> included_from) {
    for (Warning& w : m_warnings) {
        const bool same_file =
            (w.loc.file && loc.file) ? *w.loc.file == *loc.file : w.loc.file == loc.file;
        if (w.kind == kind && same_file) {
            ++w.count;
            return;
        }
    }
    m_warnings.push_back({loc, std::move(kind), std::move(message), 1, std::move(included_from)});
}

bool Diagnostics::has(const std::string& kind) const {
    for (const Warning& w : m_warnings)
        if (w.kind == kind) return true;
    return false;
}

}  // namespace rt
