// The file loop of a parse (spec §2, §4.2, §10): the dialect is fixed by a pre-scan of the whole
// file tree (dialect.cpp), then each file is parsed once per canonical path into a FileDesc, its
// directives walked (mesh_runs.cpp) by the grammar of the dialect (grammar.h) into the
// SceneBuilder (scene_builder.h), which completes the tree. The helpers that parser_impl.h
// declares for all the parts are defined here too.
#include "rt/format/parser.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "format/driver.h"
#include "format/lexer.h"
#include "rt/util/file_io.h"

namespace fs = std::filesystem;

namespace rt {

MaterialDesc v0_default_material() {
    MaterialDesc m;
    m.ambient = Vec3(0.2);
    m.diffuse = Vec3(0.8);
    m.specular = Vec3(0.8);
    m.specular_exponent = kV0ExponentScale;  // kspec 1.0
    m.name = "V0 default material";
    return m;
}

namespace parser_impl {

std::string not_text_message(const std::string& name, const std::string& what) {
    return quote(name) + " is not " + what + ": its first bytes are not printable text";
}

std::string read_failure(const std::string& lead, const std::string& path, const std::string& why) {
    // read_file() names the path itself when it cannot open it; it is named once here.
    const std::string opening = "cannot open '" + path + "': ";
    const std::string reason = why.rfind(opening, 0) == 0 ? why.substr(opening.size()) : why;
    return lead + " " + quote(path) + ": " + reason;
}

std::string describe(const Token& t) {
    return t.kind == TokenKind::End ? std::string("end of file") : quote(t.text);
}

bool is_file(const fs::path& p) {
    std::error_code ec;
    const fs::file_status st = fs::status(p, ec);
    return !ec && fs::exists(st) && !fs::is_directory(st);
}

bool is_dir(const fs::path& p) {
    std::error_code ec;
    return fs::is_directory(p, ec);
}

std::string canonical_path(const std::string& path) {
    std::error_code ec;
    const fs::path a = fs::absolute(path, ec);
    if (ec) return path;
    const fs::path c = fs::weakly_canonical(a, ec);
    return ec ? a.lexically_normal().string() : c.string();
}

std::string lower(std::string_view s) {
    std::string r(s);
    for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return r;
}

// ---- the file loop ------------------------------------------------------------------------------
Parser::Parser(Diagnostics& diag, const ParseOptions& options)
    : m_options(options), m_build(diag, options), m_v1(m_build), m_v3(m_build) {
    m_build.set_file_loop(this);
}

Parser::Parser(const Parser& tree, Ahead* out)
    : m_options(tree.m_options), m_build(tree.m_build, out), m_v1(m_build), m_v3(m_build) {
    m_dialect = tree.m_dialect;
    m_top_dir = tree.m_top_dir;
    m_halt = &tree.m_stop_ahead;
}

Parser::~Parser() { stop_ahead(); }

SceneDesc Parser::run(std::string_view text, const std::string& name, const std::string& dir) {
    const std::string canonical = canonical_path(name);
    count_text(text.size());
    detect_dialect(text, name, canonical, dir);
    start_ahead();
    m_build.scene().files.emplace_back();
    parse_file(text, name, canonical, dir, 0);
    stop_ahead();
    return m_build.finish();
}

SceneDesc Parser::run_file(const std::string& path) {
    FileBytes text;
    std::string why;
    if (!read_file(path, &text, &why)) {
        SourceLoc loc{intern_file_name(path), 0, 0};
        throw SceneError(loc, read_failure("cannot open scene file", path, why));
    }
    const std::string dir = fs::path(path).parent_path().string();
    return run(text_of(text), path, dir.empty() ? "." : dir);
}

void Parser::parse_file(std::string_view text, const std::string& name,
                        const std::string& canonical, const std::string& dir, int index) {
    m_build.open_file(canonical, name);
    FileDesc desc = parse_text(text, name, canonical, dir, index == 0);
    m_build.close_file();
    m_build.scene().files[static_cast<size_t>(index)] = std::move(desc);
}

FileDesc Parser::parse_text(std::string_view text, const std::string& name,
                            const std::string& canonical, const std::string& dir, bool top) {
    FileState f(text, intern_file_name(name));
    f.top = top;
    f.dir = dir;
    f.desc.path = name;
    f.desc.canonical_path = canonical;
    f.stack.push_back(&f.desc.root);
    f.stack_is_joint.push_back(0);

    const bool v3 = m_dialect == Dialect::V3;
    if (v3) f.v3.push_back({});  // the root list
    if (auto it = m_sizes.find(canonical); it != m_sizes.end()) {
        // No more than the text can hold when every one is well formed (a #vertex or a shape
        // takes >= 24 bytes), whatever a hostile file's directives count.
        const size_t fit = text.size() / 24;
        f.desc.vertices.reserve(std::min(it->second.vertices, fit));
        if (!v3) f.desc.root.shapes.reserve(std::min(it->second.top_shapes, fit));
    }
    walk_file(f);
    end_of_file(f);
    return std::move(f.desc);
}

// ---- included files parsed ahead ----------------------------------------------------------------
void Parser::start_ahead() {
    if (parse_threads() < 2 || m_texts.empty()) return;
    size_t bytes = 0;
    for (const auto& [canonical, text] : m_texts) bytes += text.size();
    if (bytes < m_options.ahead) return;
    for (auto& [canonical, text] : m_texts) {
        auto job = std::make_unique<AheadJob>();
        job->canonical = canonical;
        job->name = m_text_names.at(canonical);
        const std::string dir = fs::path(job->name).parent_path().string();
        job->dir = dir.empty() ? "." : dir;
        job->text = std::move(text);
        m_ahead_order.push_back(job.get());
        m_ahead.emplace(canonical, std::move(job));
    }
    m_texts.clear();
    // Largest first: the longest parse starts soonest.
    std::stable_sort(
        m_ahead_order.begin(), m_ahead_order.end(),
        [](const AheadJob* a, const AheadJob* b) { return a->text.size() > b->text.size(); });
    const size_t threads = std::min<size_t>(parse_threads(), m_ahead_order.size());
    for (size_t t = 0; t < threads; ++t) {
        const auto work = [this] {
            for (size_t i = m_next_ahead++; i < m_ahead_order.size(); i = m_next_ahead++)
                if (!m_ahead_order[i]->claimed.exchange(true)) parse_ahead(*m_ahead_order[i]);
        };
        try {
            m_ahead_threads.emplace_back(work);
        } catch (const std::system_error&) {
            break;  // no thread to be had: the jobs left are parsed when the walk meets them
        }
    }
}

void Parser::parse_ahead(AheadJob& job) const {
    Ahead& a = job.result;
    a.name = job.name;
    a.canonical = job.canonical;
    if (!m_stop_ahead) {
        Parser file(*this, &a);
        if (auto it = m_sizes.find(job.canonical); it != m_sizes.end()) file.m_sizes.emplace(*it);
        try {
            a.desc = file.parse_text(text_of(job.text), job.name, job.canonical, job.dir, false);
        } catch (...) {
            a.error = std::current_exception();
        }
        a.tracks = std::move(file.m_build.scene().tracks);
        a.skipped = file.m_build.scene().skipped_shapes;
    }
    FileBytes().swap(job.text);
    job.done.set_value();
}

void Parser::stop_ahead() {
    m_stop_ahead = true;
    for (std::thread& t : m_ahead_threads) t.join();
    m_ahead_threads.clear();
}

void Parser::end_of_file(FileState& f) {
    const Token end = f.lex.next();
    const SourceLoc eof = f.lex.loc(end);
    m_build.check_texture_refs(f);
    if (m_dialect == Dialect::V3)
        m_v3.end_of_file(f, eof);
    else
        m_v1.end_of_file(f, eof);
}

void Parser::dispatch(FileState& f, const Token& d) {
    if (m_dialect == Dialect::V3)
        m_v3.directive(f, d);
    else
        m_v1.directive(f, d);
}

// An included file is read once: the dialect pre-scan kept its text (or parsed it ahead).
bool Parser::readable(const std::string& resolved, const std::string& canonical, std::string* why) {
    return m_ahead.count(canonical) || cached_text(resolved, canonical, why) != nullptr;
}

void Parser::parse(const std::string& resolved, const std::string& canonical, int index) {
    if (auto it = m_ahead.find(canonical); it != m_ahead.end()) {
        AheadJob& job = *it->second;
        if (!job.claimed.exchange(true)) parse_ahead(job);  // no thread has started it
        job.ready.wait();
        // Its parse is this one's when the walk names it as the pre-scan did.
        if (job.result.name == resolved) return m_build.replay(job.result, index);
    }
    std::string why;  // read again when parsed ahead under another name (readable() held)
    if (!cached_text(resolved, canonical, &why))
        throw SceneError({intern_file_name(resolved), 0, 0}, why);
    const FileBytes text = std::move(m_texts.at(canonical));
    m_texts.erase(canonical);
    const std::string sub_dir = fs::path(resolved).parent_path().string();
    parse_file(text_of(text), resolved, canonical, sub_dir.empty() ? "." : sub_dir, index);
}

}  // namespace parser_impl

SceneDesc parse_scene_file(const std::string& path, Diagnostics& diag,
                           const ParseOptions& options) {
    parser_impl::Parser p(diag, options);
    return p.run_file(path);
}

SceneDesc parse_scene_string(const std::string& text, const std::string& name, Diagnostics& diag,
                             const ParseOptions& options, const std::string& base_dir) {
    parser_impl::Parser p(diag, options);
    return p.run(text, name, base_dir);
}

}  // namespace rt
