// Source locations, the one error type the library throws, and the warning sink. The library
// never prints and never exits: callers decide what to do with errors and warnings.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rt {

/// A file name kept for the rest of the program, one copy per distinct name (thread-safe): what
/// source locations point at. A scene of a million shapes holds a million locations; a pointer
/// costs 8 bytes and no reference count.
const std::string* intern_file_name(std::string_view name);

/// Where a token came from: file as given (or as resolved for an include), 1-based line and
/// column (columns count bytes, spec §2). The file name is interned (intern_file_name).
struct SourceLoc {
    const std::string* file = nullptr;
    int line = 0;
    int col = 0;

    std::string str() const;  ///< "file:line:col" (or "file" when line is 0)
};

/// The library's single error type. what() is the whole compiler-style text:
/// "file:line:col: error: message", followed by "  included from file:line:col" lines.
class SceneError : public std::runtime_error {
public:
    SceneError(SourceLoc loc, std::string message, std::vector<SourceLoc> included_from = {});

    const SourceLoc& loc() const { return m_loc; }
    const std::string& message() const { return m_message; }
    const std::vector<SourceLoc>& included_from() const { return m_included_from; }

private:
    SourceLoc m_loc;
    std::string m_message;
    std::vector<SourceLoc> m_included_from;
};

/// One warning, possibly standing for several of the same kind in one file (spec §2).
struct Warning {
    SourceLoc loc;  ///< the first occurrence
    std::string kind;
    std::string message;
    int count = 1;
    std::vector<SourceLoc>
        included_from;  ///< the #ray_file directives that led there, innermost first
    /// "file:line:col: warning: message[ (N times)]", then one "  included from F:L:C" line each.
    std::string str() const;
};

/// Collects warnings; repeated warnings of one kind in one file are merged with a count.
class Diagnostics {
public:
    void warn(const SourceLoc& loc, std::string kind, std::string message,
              std::vector<SourceLoc> included_from = {});
    const std::vector<Warning>& warnings() const { return m_warnings; }
    bool has(const std::string& kind) const;

private:
    std::vector<Warning> m_warnings;
};

}  // namespace rt
