// The include stack of a parse (spec §2, §4.2, §10): the dialect is fixed by a pre-scan of the
// whole file tree (dialect.cpp), then each file is parsed once per canonical path, its
// directives walked (mesh_runs.cpp) by the grammar of the dialect (grammar.h) into the
// SceneBuilder (scene_builder.h), which completes the tree; the files the pre-scan read are
// parsed ahead on threads into copies of the builder, merged where the walk meets them. The
// helpers that parser_impl.h declares for all the parts, and the texture cache, are here too.
#include "rt/format/parser.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "format/driver.h"
#include "format/lexer.h"
#include "rt/image/image.h"
#include "rt/util/file_io.h"
#include "rt/util/limits.h"

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

TextureCache::Decoded TextureCache::decode(const std::string& path) {
    const std::lock_guard<std::mutex> lock(m_mutex);
    const auto [it, added] = m_decoded.try_emplace(canonical_path(path));
    if (added) {
        // Each texture decodes within what the scene's texel budget has left, so the #texture
        // that would pass it is refused before its pixels are allocated. (Files parsed ahead
        // decode their textures as their threads reach them: in a tree over the budget, the
        // #texture refused may be another than the serial parse's; the total holds either way.)
        const uint64_t budget = max_scene_texels();
        const uint64_t left = budget - std::min(budget, m_texels);
        const DecodeBudget scope(left, "what is left of the scene's texture budget (" +
                                           std::to_string(left) + " of " + std::to_string(budget) +
                                           " texels, 4 x --max-pixels)");
        auto image = std::make_shared<TextureImage>();
        if (load_texture_image(path, image.get(), &it->second.error)) {
            m_texels += static_cast<uint64_t>(image->width) * image->height;
            it->second.image = std::move(image);
        }
    }
    return it->second;
}

// ---- the include stack --------------------------------------------------------------------------
Parser::Parser(Diagnostics& diag, const ParseOptions& options)
    : m_options(options), m_build(diag, options) {}

Parser::Parser(const Parser& tree, Diagnostics& own)
    : m_options(tree.m_options), m_build(tree.m_build, own) {
    m_dialect = tree.m_dialect;
    m_v3_marker = tree.m_v3_marker;
    m_top_dir = tree.m_top_dir;
    m_halt = &tree.m_stop_ahead;
}

Parser::~Parser() { stop_ahead(); }

SceneDesc Parser::run(std::string_view text, const std::string& name, const std::string& dir) {
    const std::string canonical = canonical_path(name);
    count_text(text.size());
    detect_dialect(text, name, canonical, dir);
    start_ahead();
    parse_text(text, name, canonical, dir, nullptr);
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

void Parser::parse_text(std::string_view text, const std::string& name,
                        const std::string& canonical, const std::string& dir,
                        const SceneBuilder::Include* from) {
    SceneBuilder::File file{name, canonical, dir, from};
    if (auto it = m_sizes.find(canonical); it != m_sizes.end()) {
        // No more than the text can hold when every one is well formed (a #vertex or a shape
        // takes >= 24 bytes), whatever a hostile file's directives count.
        const size_t fit = text.size() / 24;
        file.vertices = std::min(it->second.vertices, fit);
        file.top_shapes = std::min(it->second.top_shapes, fit);
    }
    m_build.open_file(file);
    Reading r{Lexer(text, intern_file_name(name)), !from && !m_halt};
    walk_file(r, name, canonical);
    const Token end = r.lex.next();
    m_build.close_file(r.lex.loc(end));
}

// An included file is read once: the dialect pre-scan kept its text (or parsed it ahead).
void Parser::include(const SceneBuilder::Include& inc) {
    std::string why;
    const auto ahead = m_ahead.find(inc.canonical);
    if (ahead == m_ahead.end() && !cached_text(inc.resolved, inc.canonical, &why))
        m_build.fail(inc.path_loc, read_failure("cannot read ray file", inc.resolved, why));
    if (ahead != m_ahead.end()) {
        AheadJob& job = *ahead->second;
        if (!job.claimed.exchange(true)) parse_ahead(job);  // no thread has started it
        job.ready.wait();
        // Its parse is this one's when the walk names it as the pre-scan did.
        if (job.name == inc.resolved && job.parser) {
            while (m_build.merge(job.parser->m_build, &inc, job.error))
                if (auto sub = m_build.take_include()) include(*sub);
            return;
        }
    }
    // Read again when parsed ahead under another name.
    if (!cached_text(inc.resolved, inc.canonical, &why))
        throw SceneError({intern_file_name(inc.resolved), 0, 0}, why);
    const FileBytes text = std::move(m_texts.at(inc.canonical));
    m_texts.erase(inc.canonical);
    const std::string sub_dir = fs::path(inc.resolved).parent_path().string();
    parse_text(text_of(text), inc.resolved, inc.canonical, sub_dir.empty() ? "." : sub_dir, &inc);
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

// A copy of the tree's builder parses the file; the tree merges it in its order (include()).
void Parser::parse_ahead(AheadJob& job) const {
    if (!m_stop_ahead) {
        job.parser.reset(new Parser(*this, job.diag));
        Parser& file = *job.parser;
        if (auto it = m_sizes.find(job.canonical); it != m_sizes.end()) file.m_sizes.emplace(*it);
        try {
            file.parse_text(text_of(job.text), job.name, job.canonical, job.dir, nullptr);
        } catch (...) {
            job.error = std::current_exception();
        }
    }
    FileBytes().swap(job.text);
    job.done.set_value();
}

void Parser::stop_ahead() {
    m_stop_ahead = true;
    for (std::thread& t : m_ahead_threads) t.join();
    m_ahead_threads.clear();
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
