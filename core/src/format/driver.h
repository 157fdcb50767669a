// The driver of a parse, private to core/src/format.
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "format/grammar.h"
#include "format/parser_impl.h"
#include "format/scene_builder.h"

namespace rt::parser_impl {

/// The driver of a parse: the dialect pre-scan of the file tree (dialect.cpp), the include stack
/// with the included files parsed ahead (parser.cpp) and the walk over a file's directives, its
/// long runs of mesh directives in pieces on several threads (mesh_runs.cpp). Each directive goes
/// to the grammar walk of the tree's dialect (grammar.h); what they build, and what it means, is
/// the SceneBuilder's. A file parsed ahead (as pbrt's import: a copy of the builder, its result
/// merged) and a piece of a run are parsed into copies of the builder, merged in file order, so
/// the description, the warnings and the errors are those of the serial parse.
class Parser final {
public:
    Parser(Diagnostics& diag, const ParseOptions& options);
    ~Parser();
    Parser(const Parser&) = delete;
    Parser& operator=(const Parser&) = delete;
    SceneDesc run(std::string_view text, const std::string& name, const std::string& dir);
    SceneDesc run_file(const std::string& path);

private:
    /// A file's text as the walk reads it: its tokens, whether it is the tree's top-level file,
    /// and how much of it ParseProgress has counted.
    struct Reading {
        Lexer lex;
        bool top = false;
        size_t counted = 0;
    };
    /// An included file the pre-scan read, parsed on a thread of its own (a Parser of its own,
    /// whose builder is a copy of the tree's) while the top-level file is; the walk merges its
    /// result where its first #ray_file is met.
    struct AheadJob {
        std::string canonical, name, dir;
        FileBytes text;
        Diagnostics diag;                  // its warnings, until the merge
        std::unique_ptr<Parser> parser;    // its parse (null: stopped before it started)
        std::exception_ptr error;          // what stopped its parse
        std::atomic<bool> claimed{false};  // a thread parses it (a worker, or the walk's)
        std::promise<void> done;
        std::future<void> ready = done.get_future();
    };
    /// The parser of a file parsed ahead for `tree`, its warnings into `own`.
    Parser(const Parser& tree, Diagnostics& own);

    // The include stack: each file parsed once, the files parsed ahead merged where the walk
    // meets them.
    /// One file's directives into the builder (`from`: its #ray_file; none: the top-level file,
    /// or the file parsed ahead).
    void parse_text(std::string_view text, const std::string& name, const std::string& canonical,
                    const std::string& dir, const SceneBuilder::Include* from);
    /// The file of a #ray_file, new to the tree: merged when it was parsed ahead, else parsed.
    void include(const SceneBuilder::Include& inc);
    void start_ahead();
    void parse_ahead(AheadJob& job) const;
    void stop_ahead();
    /// A file parsed ahead whose tree's parse has ended (its walk stops, "parse stopped").
    bool halted() const { return m_halt && m_halt->load(std::memory_order_relaxed); }

    // The walk over a file's directives, its mesh runs in pieces on several threads.
    /// Parses from token `t` to the first directive at or after byte `bound` (or the end of the
    /// file, or until *stop is set, or after `most` directives), which it returns unparsed, into
    /// `b` (the tree's builder, or a piece's).
    Token walk(SceneBuilder& b, Reading& r, Token t, size_t bound,
               const std::atomic<bool>* stop = nullptr, size_t most = SIZE_MAX);
    /// The directives of a file, the long runs of mesh directives in pieces on several threads.
    void walk_file(Reading& r, const std::string& name, const std::string& canonical);
    /// The threads a run is cut for, and that parse included files ahead (ParseOptions::threads;
    /// 1 where none can start, and on the web page's main thread).
    unsigned parse_threads() const;
    /// ParseProgress: the bytes of r's text up to `offset` are parsed (counted once each).
    void count_progress(Reading& r, size_t offset) const;
    /// ParseProgress::cancel set: throws "loading cancelled" at `loc` (through `b`).
    void check_cancel(const SceneBuilder& b, const SourceLoc& loc) const;
    /// ParseProgress::total grows by a text read.
    void count_text(size_t bytes) const;
    /// A run the pre-scan found, from its first directive: cut into pieces, parsed on several
    /// threads into copies of the builder, merged in file order.
    Token parse_run(Reading& r, const Token& first, const MeshRun& run);
    Token parse_pieces(Reading& r, const MeshRun& run, const Token& second);

    // The dialect pre-scan: the tree's dialect, the texts of its files, their runs and sizes.
    void detect_dialect(std::string_view text, const std::string& name,
                        const std::string& canonical, const std::string& dir);
    /// The file's text (read once); nullptr, with the reason in *why, when it cannot be read.
    const FileBytes* cached_text(const std::string& path, const std::string& canonical,
                                 std::string* why = nullptr);
    /// An error of the pre-scan, with the includes that led to it.
    [[noreturn]] void scan_fail(const SourceLoc& loc, const std::string& message) const;
    struct Scan;
    std::optional<std::string> find_file(const std::string& dir, const std::string& path,
                                         bool v3) const;
    void prescan(std::string_view text, const std::string& name, const std::string& canonical,
                 const std::string& dir, Scan& scan);
    void prescan_directive(Lexer& lex, const Token& t, const std::string& dir, Scan& scan);
    void prescan_marker(const SourceLoc& loc, std::string_view what, bool v3, Scan& scan);
    bool wants_marker(bool v3, const Scan& scan) const;
    void run_prescan(std::string_view text, const std::string& name, const std::string& canonical,
                     const std::string& dir, bool v3, Scan& scan);

    ParseOptions m_options;
    SceneBuilder m_build;
    std::string m_v3_marker;  // "'#static_affine' at F:L:C", for messages
    // Files parsed ahead, by canonical path; the threads that parse them; their stop.
    std::map<std::string, std::unique_ptr<AheadJob>> m_ahead;
    std::vector<std::thread> m_ahead_threads;
    std::atomic<size_t> m_next_ahead{0};
    std::vector<AheadJob*> m_ahead_order;
    std::atomic<bool> m_stop_ahead{false};
    const std::atomic<bool>* m_halt = nullptr;  // a file parsed ahead: the tree's stop
    Dialect m_dialect = Dialect::V1;
    std::map<std::string, FileBytes> m_texts;         // included files read, not yet parsed
    std::map<std::string, std::string> m_text_names;  // and the paths they were read as
    std::string m_top_dir = ".";                      // directory of the top-level file
    std::vector<SourceLoc> m_scan_locs;  // the pre-scan's #ray_file chain, outermost first
    // What the pre-scan counted in each file (by canonical path), for the parse's reservations.
    struct FileSizes {
        size_t vertices = 0;
        size_t top_shapes = 0;  // #shape_* directives outside any group (V0/V1)
        std::vector<MeshRun> runs;
    };
    std::map<std::string, FileSizes> m_sizes;
    SourceLoc m_first_v0, m_first_v1;  // first material of each dialect (pre-scan)
    bool m_default_use = false;        // some shape uses material index -1
};

}  // namespace rt::parser_impl
