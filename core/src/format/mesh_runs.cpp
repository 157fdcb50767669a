// The walk over a file's directives, and the one place the parse uses more than one thread: a
// long run of one mesh directive (#vertex, or #shape_triangle in one group or triangle list),
// which the pre-scan found and marked (MeshRun), is cut at its marks into one piece per thread.
// The calling thread parses the first piece itself, into the file; each other piece is parsed by
// the same directive code into a copy of the builder that starts from the file's state (its
// counts, its part, its triangle list) and reads the file's materials and vertices. The run's
// output is sized once (SceneBuilder::open_run) and each copy writes its range of it in place.
// The copies are then merged in file order (SceneBuilder::merge): a range written short moved
// down, their warnings handed on, and the first error in file order thrown, so the description, the
// warnings and the errors are those of the serial parse (ParseOptions::threads = 1), which the
// tests and the scene fuzz target compare.
#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <system_error>
#include <thread>
#include <vector>

#include "format/driver.h"
#include "rt/util/threads.h"

namespace rt::parser_impl {

namespace {

// A piece of a run on another thread: its builder (a copy of the file's, reading its
// definitions), its text, where it stops, and what it reports.
struct Piece {
    Diagnostics diag;
    SceneBuilder b;
    Lexer lex;
    size_t counted = 0;     // of its text, by ParseProgress
    size_t bound = 0;       // the offset of the next piece's first directive, or the run's end
    size_t directives = 0;  // at most, so that it writes no more than its range
    Token stop;             // the first directive at or after `bound`, or the end
    std::exception_ptr error;

    // Its state at mark m of a run, up to the directive of index `end`: the file's as the run's
    // first directive left it.
    Piece(SceneBuilder& file, const Lexer& text, const MeshRun& run, const MeshRun::Mark& m,
          size_t end)
        : b(file, diag, SceneBuilder::Piece{run.vertices, m.index, end - m.index}),
          lex(text.text(), text.file()),
          counted(m.offset) {
        lex.seek(m.offset, m.line, m.col);
    }
};

// Waits for the pieces' threads however the calling thread leaves; when it leaves with an error
// (the first in file order) they stop at their next directive.
struct Joiner {
    std::atomic<bool>& stop;
    std::vector<std::thread>& threads;
    const int errors = std::uncaught_exceptions();
    ~Joiner() {
        if (std::uncaught_exceptions() > errors) stop = true;
        for (std::thread& t : threads)
            if (t.joinable()) t.join();
    }
};

}  // namespace

void Parser::count_progress(Reading& r, size_t offset) const {
    if (!m_options.progress || offset <= r.counted) return;
    m_options.progress->done.fetch_add(offset - r.counted, std::memory_order_relaxed);
    r.counted = offset;
}

void Parser::check_cancel(const SceneBuilder& b, const SourceLoc& loc) const {
    if (m_options.progress && m_options.progress->cancel.load(std::memory_order_relaxed))
        b.fail(loc, "loading cancelled");
}

void Parser::count_text(size_t bytes) const {
    if (m_options.progress) m_options.progress->total.fetch_add(bytes, std::memory_order_relaxed);
}

unsigned Parser::parse_threads() const {
    if (!have_threads() || on_browser_main_thread()) return 1;
    return m_options.threads ? m_options.threads : hardware_threads();
}

Token Parser::walk(SceneBuilder& b, Reading& r, Token t, size_t bound,
                   const std::atomic<bool>* stop, size_t most) {
    Lexer& lex = r.lex;
    for (size_t n = 1; t.kind != TokenKind::End; ++n) {
        if (t.kind == TokenKind::Directive && (lex.offset(t) >= bound || n > most)) break;
        if (stop && stop->load(std::memory_order_relaxed)) break;
        if (t.kind != TokenKind::Directive)
            b.fail(lex.loc(t), "expected a directive, got " + quote(t.text));
        if (n % 1024 == 0 && (m_options.progress || m_halt)) {
            // A file parsed ahead that the tree no longer needs (its parse failed) stops.
            if (halted()) b.fail(lex.loc(t), "parse stopped");
            if (m_options.progress) {
                check_cancel(b, lex.loc(t));
                count_progress(r, lex.offset(t));
            }
        }
        Directive d{b, lex, t, r.top};
        if (m_dialect == Dialect::V3)
            read_v3(d, m_v3_marker);
        else
            read_v1(d);
        if (auto inc = b.take_include()) include(*inc);
        t = lex.next();
    }
    count_progress(r, lex.offset(t));
    return t;
}

void Parser::walk_file(Reading& r, const std::string& name, const std::string& canonical) {
    const auto sizes = m_sizes.find(canonical);
    const std::vector<MeshRun>* runs = sizes != m_sizes.end() ? &sizes->second.runs : nullptr;
    size_t next = 0;
    if (parse_threads() < 2) runs = nullptr;
    Token t = r.lex.next();
    if (t.kind != TokenKind::End && !printable_text(t.text))
        m_build.fail(r.lex.loc(t), not_text_message(name));
    while (t.kind != TokenKind::End) {
        const size_t bound = runs && next < runs->size() ? (*runs)[next].marks[0].offset : SIZE_MAX;
        t = walk(m_build, r, t, bound);
        if (t.kind == TokenKind::End) break;
        // A run the parse did not meet where the pre-scan saw it is parsed as any directive.
        if (r.lex.offset(t) == bound) t = parse_run(r, t, (*runs)[next]);
        ++next;
    }
    count_progress(r, r.lex.text().size());
}

Token Parser::parse_run(Reading& r, const Token& first, const MeshRun& run) {
    // The first directive on its own settles the file's state the pieces start from (the graph
    // started, the part of a V3 file); an error there is the run's first.
    const Token second = walk(m_build, r, first, r.lex.offset(first) + 1);
    return parse_pieces(r, run, second);
}

// The run after its first directive, cut into pieces: the calling thread parses the first into
// the file, each other piece is parsed on a thread of its own into a copy of the builder; the
// copies are merged in file order.
Token Parser::parse_pieces(Reading& r, const MeshRun& run, const Token& second) {
    const size_t marks = run.marks.size();
    const size_t parts = std::min<size_t>(parse_threads(), marks);
    const auto start = [&](size_t p) -> const MeshRun::Mark& {
        return run.marks[p * marks / parts];
    };
    // The run's output sized once; each piece writes its range of it in place.
    const size_t first = (parts > 1 ? start(1).index : run.count) - 1;
    m_build.open_run(run.vertices, run.count - 1, first);
    std::vector<std::unique_ptr<Piece>> pieces;
    for (size_t p = 1; p < parts; ++p) {
        const size_t end = p + 1 < parts ? start(p + 1).index : run.count;
        pieces.push_back(std::make_unique<Piece>(m_build, r.lex, run, start(p), end));
        pieces.back()->bound = p + 1 < parts ? start(p + 1).offset : run.end;
        pieces.back()->directives = end - start(p).index;
    }
    std::atomic<bool> stop{false};
    std::vector<std::thread> workers;
    Token t;
    {
        Joiner joiner{stop, workers};
        for (const std::unique_ptr<Piece>& p : pieces) {
            const auto parse = [this, &stop, top = r.top, piece = p.get()] {
                try {
                    Reading own{piece->lex, top, piece->counted};
                    piece->stop =
                        walk(piece->b, own, own.lex.next(), piece->bound, &stop, piece->directives);
                    piece->lex = own.lex;
                    piece->counted = own.counted;
                } catch (...) {
                    piece->error = std::current_exception();
                }
            };
            try {
                workers.emplace_back(parse);
            } catch (const std::system_error&) {
                parse();  // no thread to be had: this one parses the piece
            }
        }
        t = walk(m_build, r, second, parts > 1 ? start(1).offset : run.end, nullptr, first);
    }
    // The first piece ends where the second starts, unless the text was read differently from
    // the pre-scan's marks: then the pieces are dropped and the parse goes on from here.
    if (pieces.empty() || t.kind == TokenKind::End || r.lex.offset(t) != start(1).offset) {
        m_build.close_run();
        return t;
    }
    for (const std::unique_ptr<Piece>& p : pieces) m_build.merge(p->b, nullptr, p->error);
    m_build.close_run();
    Piece& last = *pieces.back();
    r.lex = last.lex;
    r.counted = last.counted;
    return last.stop;
}

}  // namespace rt::parser_impl
