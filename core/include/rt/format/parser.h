// Text -> SceneDesc. Reads a .ray file and everything it includes (spec §2-§4, §10), reporting
// the first error as a SceneError with file:line:col and warnings through Diagnostics.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "rt/scene/scene_desc.h"
#include "rt/util/error.h"

namespace rt {

/// What to do with a texture that cannot be opened or decoded: the error the spec requires, or a
/// stand-in (a magenta/grey checker) with one warning per missing file, recorded in
/// SceneDesc::missing_textures (--missing-textures checker).
enum class MissingTextures { Error, Checker };

/// How far a parse has come, for a loader's progress bar, and a way to stop it; read and set from
/// any thread while the parse runs.
struct ParseProgress {
    std::atomic<uint64_t> total{0};   ///< bytes of scene text read so far (the file, its includes)
    std::atomic<uint64_t> done{0};    ///< bytes of it parsed (the dialect pre-scan not counted)
    std::atomic<bool> cancel{false};  ///< set: the parse throws "loading cancelled" promptly
};

struct ParseOptions {
    std::optional<Dialect> dialect;  ///< --dialect: overrides detection (spec §10 step 5)
    MissingTextures missing_textures = MissingTextures::Error;
    /// Threads that parse a file's long runs of #vertex or #shape_triangle directives, each its
    /// own piece of the run, and the included files, each ahead of the walk that meets it (0:
    /// one per core; 1: the serial parse). The description, the warnings and the errors are the
    /// same, in the same order, for every count.
    unsigned threads = 0;
    /// Directives per piece: a run is split only where it is at least two pieces long (the tests
    /// make pieces of one directive, so every scene's runs are split).
    size_t piece = 16384;
    /// Bytes of included text from which the included files are parsed ahead on other threads
    /// (below it the threads cost more than they save; the tests use 0, so every tree is).
    size_t ahead = 256 * 1024;
    ParseProgress* progress = nullptr;  ///< updated as the parse goes, when given
};

/// Parses a scene file and its includes. Throws SceneError.
SceneDesc parse_scene_file(const std::string& path, Diagnostics& diag,
                           const ParseOptions& options = {});

/// Parses scene text given inline; `name` is used in locations and `base_dir` resolves relative
/// paths (includes, textures). Throws SceneError.
SceneDesc parse_scene_string(const std::string& text, const std::string& name, Diagnostics& diag,
                             const ParseOptions& options = {}, const std::string& base_dir = ".");

}  // namespace rt
