// The walk over a file's directives, and the one place the parse uses more than one thread: a
// long run of one mesh directive (#vertex, or #shape_triangle in one group or triangle list),
// which the pre-scan found and marked (MeshRun), is cut at its marks into one piece per thread.
// The calling thread parses the first piece itself; each other piece is parsed by the same
// directive code with a FileState of its own that starts from the file's state (its counts, its
// part, its triangle list) and refers to the file's materials and vertices. Every piece writes
// its vertices or shapes straight into its own range of the file's array. The pieces are then
// joined in file order: their ranges closed up, their warnings handed on, and the first error in
// file order thrown, so the description, the warnings and the errors are those of the
// serial parse (ParseOptions::threads = 1), which the tests and the scene fuzz target compare.
#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <system_error>
#include <thread>
#include <type_traits>
#include <vector>

#include "format/driver.h"
#include "rt/util/threads.h"

namespace rt::parser_impl {

// Not an anonymous namespace: parse_pieces(), a member template, uses them.
namespace run_pieces {

// A piece of a run on another thread: its state, what it reports, and where it stopped.
struct Piece {
    FileState state;
    PieceOutput out;
    size_t bound = 0;  // the offset of the next piece's first directive, or the run's end
    size_t slot = 0;   // the place in the run's array of its first vertex or shape
    Token stop;        // the first directive at or after `bound`, or the end
    std::exception_ptr error;

    // Its state at mark m of a run of file f: the file's as the run's first directive left it.
    Piece(const FileState& f, const MeshRun& run, const MeshRun::Mark& m)
        : state(f.lex.text(), f.lex.file()) {
        FileState& s = state;
        s.lex.seek(m.offset, m.line, m.col);
        s.counted = m.offset;
        s.parent = &f;
        s.top = f.top;
        s.dir = f.dir;
        s.graph_started = f.graph_started;
        s.counts = f.counts;
        if (run.vertices) s.counts[kVertices].found += m.index - 1;  // the first is counted
        s.v3_part = f.v3_part;
        s.stack.push_back(&s.desc.root);
        s.stack_is_joint.push_back(0);
        if (!f.v3.empty()) {
            s.v3.emplace_back();
            s.v3.back().kind = f.v3.back().kind;
            s.v3.back().material = f.v3.back().material;
        }
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

// The array a run adds to: the file's vertices, or the open group's (or triangle list's) shapes.
HugePageVector<VertexDesc>& run_array(FileState& f, std::true_type) { return f.desc.vertices; }
HugePageVector<ShapeDesc>& run_array(FileState& f, std::false_type) {
    return f.v3.empty() ? f.stack.back()->shapes : f.v3.back().group.shapes;
}
FileState::Slots<VertexDesc>& run_slots(FileState& f, std::true_type) { return f.vertex_slots; }
FileState::Slots<ShapeDesc>& run_slots(FileState& f, std::false_type) { return f.shape_slots; }

}  // namespace run_pieces

using run_pieces::Joiner;
using run_pieces::Piece;
using run_pieces::run_array;
using run_pieces::run_slots;

void Parser::count_progress(FileState& f, size_t offset) const {
    if (!m_options.progress || offset <= f.counted) return;
    m_options.progress->done.fetch_add(offset - f.counted, std::memory_order_relaxed);
    f.counted = offset;
}

void Parser::check_cancel(const SourceLoc& loc) const {
    if (m_options.progress && m_options.progress->cancel.load(std::memory_order_relaxed))
        m_build.fail(loc, "loading cancelled");
}

void Parser::count_text(size_t bytes) const {
    if (m_options.progress) m_options.progress->total.fetch_add(bytes, std::memory_order_relaxed);
}

unsigned Parser::parse_threads() const {
    if (!have_threads() || on_browser_main_thread()) return 1;
    return m_options.threads ? m_options.threads : hardware_threads();
}

Token Parser::walk(FileState& f, Token t, size_t bound, const std::atomic<bool>* stop) {
    for (unsigned n = 1; t.kind != TokenKind::End; ++n) {
        if (t.kind == TokenKind::Directive && f.lex.offset(t) >= bound) break;
        if (stop && stop->load(std::memory_order_relaxed)) break;
        if (t.kind != TokenKind::Directive)
            m_build.fail(f.lex.loc(t), "expected a directive, got " + quote(t.text));
        if (n % 1024 == 0 && (m_options.progress || m_halt)) {
            // A file parsed ahead that the tree no longer needs (its parse failed) stops.
            if (halted()) m_build.fail(f.lex.loc(t), "parse stopped");
            if (m_options.progress) {
                check_cancel(f.lex.loc(t));
                count_progress(f, f.lex.offset(t));
            }
        }
        dispatch(f, t);
        t = f.lex.next();
    }
    count_progress(f, f.lex.offset(t));
    return t;
}

void Parser::walk_file(FileState& f) {
    const auto sizes = m_sizes.find(f.desc.canonical_path);
    const std::vector<MeshRun>* runs = sizes != m_sizes.end() ? &sizes->second.runs : nullptr;
    size_t next = 0;
    if (parse_threads() < 2) runs = nullptr;
    Token t = f.lex.next();
    if (t.kind != TokenKind::End && !printable_text(t.text))
        m_build.fail(f.lex.loc(t), not_text_message(f.desc.path));
    while (t.kind != TokenKind::End) {
        const size_t bound = runs && next < runs->size() ? (*runs)[next].marks[0].offset : SIZE_MAX;
        t = walk(f, t, bound);
        if (t.kind == TokenKind::End) break;
        // A run the parse did not meet where the pre-scan saw it is parsed as any directive.
        if (f.lex.offset(t) == bound) t = parse_run(f, t, (*runs)[next]);
        ++next;
    }
    count_progress(f, f.lex.text().size());
}

Token Parser::parse_run(FileState& f, const Token& first, const MeshRun& run) {
    // The first directive on its own settles the file's state the pieces start from (the graph
    // started, the part of a V3 file); an error there is the run's first.
    dispatch(f, first);
    return run.vertices ? parse_pieces(f, run, std::true_type{})
                        : parse_pieces(f, run, std::false_type{});
}

// The run after its first directive, cut into pieces. Each piece writes into its own range of
// the array (one place per directive), and the ranges are closed up afterwards where a piece
// wrote fewer (a degenerate triangle skipped): no copy of the pieces' output is made.
template <class IsVertices>
Token Parser::parse_pieces(FileState& f, const MeshRun& run, IsVertices kind) {
    const size_t marks = run.marks.size();
    const size_t parts = std::min<size_t>(parse_threads(), marks);
    const auto start = [&](size_t p) -> const MeshRun::Mark& {
        return run.marks[p * marks / parts];
    };
    auto& array = run_array(f, kind);
    const size_t base = array.size();
    array.resize(base + run.count - 1);  // directives 1 .. count - 1
    const auto slots_of = [&](size_t from, size_t to) {
        return std::remove_reference_t<decltype(run_slots(f, kind))>{array.data() + base + from - 1,
                                                                     array.data() + base + to - 1};
    };

    std::vector<std::unique_ptr<Piece>> pieces;
    for (size_t p = 1; p < parts; ++p) {
        const MeshRun::Mark& m = start(p);
        auto piece = std::make_unique<Piece>(f, run, m);
        run_slots(piece->state, kind) =
            slots_of(m.index, p + 1 < parts ? start(p + 1).index : run.count);
        piece->slot = base + m.index - 1;
        piece->bound = p + 1 < parts ? start(p + 1).offset : run.end;
        pieces.push_back(std::move(piece));
    }
    auto& own = run_slots(f, kind);
    own = slots_of(1, parts > 1 ? start(1).index : run.count);
    auto* const own_first = own.next;

    std::atomic<bool> stop{false};
    std::vector<std::thread> workers;
    Token t;
    {
        Joiner joiner{stop, workers};
        for (const std::unique_ptr<Piece>& p : pieces) {
            const auto parse = [this, &stop, piece = p.get()] {
                SceneBuilder::t_piece = &piece->out;
                try {
                    FileState& s = piece->state;
                    piece->stop = walk(s, s.lex.next(), piece->bound, &stop);
                } catch (...) {
                    piece->error = std::current_exception();
                }
                SceneBuilder::t_piece = nullptr;
            };
            try {
                workers.emplace_back(parse);
            } catch (const std::system_error&) {
                parse();  // no thread to be had: this one parses the piece
            }
        }
        try {
            t = walk(f, f.lex.next(), parts > 1 ? start(1).offset : run.end);
        } catch (...) {
            own = {};
            throw;
        }
    }
    // What the file's own walk wrote is kept; the rest of the room goes unless the pieces are
    // joined.
    const size_t kept = base + static_cast<size_t>(own.next - own_first);
    own = {};
    // The first piece ends where the second starts, unless the text was read differently from
    // the pre-scan's marks: then the pieces are dropped and the parse goes on from here.
    if (pieces.empty() || t.kind == TokenKind::End || f.lex.offset(t) != start(1).offset) {
        array.resize(kept);
        return t;
    }

    size_t end = kept;
    for (const std::unique_ptr<Piece>& p : pieces) {
        for (PieceOutput::Pending& w : p->out.warnings) m_build.warn(std::move(w));
        m_build.scene().skipped_shapes += p->out.skipped;
        if (p->error) std::rethrow_exception(p->error);
        FileState& s = p->state;
        const size_t written =
            static_cast<size_t>(run_slots(s, kind).next - (array.data() + p->slot));
        if (p->slot != end)
            std::move(array.begin() + static_cast<std::ptrdiff_t>(p->slot),
                      array.begin() + static_cast<std::ptrdiff_t>(p->slot + written),
                      array.begin() + static_cast<std::ptrdiff_t>(end));
        end += written;
        run_slots(s, kind) = {};
        f.graph_started = f.graph_started || s.graph_started;
    }
    array.resize(end);
    Piece& last = *pieces.back();
    f.counts = last.state.counts;
    f.lex = last.state.lex;
    f.counted = last.state.counted;
    return last.stop;
}

}  // namespace rt::parser_impl
