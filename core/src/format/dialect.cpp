// The dialect pre-scan (spec §10): before any material is interpreted, the whole file tree is
// scanned for #material number counts (16 = V0, 18 = V1), V3-only directives and uses of the V0
// default material. The texts it reads are kept for the parse (cached_text).
#include <algorithm>
#include <array>
#include <filesystem>

#include "format/parser_impl.h"
#include "rt/util/file_io.h"

namespace fs = std::filesystem;

namespace rt {

const char* dialect_name(Dialect d) {
    switch (d) {
        case Dialect::V0:
            return "V0";
        case Dialect::V1:
            return "V1";
        case Dialect::V3:
            break;
    }
    return "V3";
}

namespace parser_impl {

namespace {

// Directives that exist only in the planned V3 dialect (spec §10 step 1).
bool is_v3_directive(std::string_view d) {
    static constexpr std::array<std::string_view, 11> names = {"#static_affine",
                                                               "#dynamic_affine",
                                                               "#shape_list_begin",
                                                               "#shape_list_end",
                                                               "#shape_triangles",
                                                               "#shape_torus",
                                                               "#shape_union",
                                                               "#shape_intersection",
                                                               "#shape_difference",
                                                               "#light_sphere",
                                                               "#shader"};
    for (std::string_view n : names)
        if (n == d) return true;
    return false;
}

}  // namespace

std::optional<std::string> ParserBase::find_file(const std::string& dir, const std::string& path) {
    const fs::path p(path);
    if (p.is_absolute()) return is_file(p) ? std::optional<std::string>(path) : std::nullopt;
    for (const fs::path& c : {fs::path(dir) / p, fs::path(".") / p})
        if (is_file(c)) return c.lexically_normal().string();
    return std::nullopt;
}

// Follows the #ray_file paths it can resolve; the parse reports the others.
void ParserBase::prescan(const std::string& text, const std::string& name,
                         const std::string& canonical, const std::string& dir,
                         std::vector<std::string>& visited) {
    visited.push_back(canonical);
    Lexer lex(text, std::make_shared<const std::string>(name));
    for (Token t = lex.next(); t.kind != TokenKind::End; t = lex.next()) {
        if (t.kind != TokenKind::Directive) continue;
        if (is_v3_directive(t.text))
            fail(lex.loc(t), quote(t.text) + " is V3 syntax; V3 scenes are not supported yet");
        if (t.text == "#material") {
            int n = 0;
            bool numbers = true;
            for (Token a = lex.peek(); a.kind == TokenKind::Word; a = lex.peek()) {
                lex.next();
                double v = 0;
                bool nf = false;
                numbers = numbers && parse_real(a.text, &v, &nf);
                ++n;
            }
            // A bad token or a missing string is reported by the parse at its place.
            if (!numbers || (lex.peek().kind != TokenKind::String && (n == 16 || n == 18)))
                continue;
            if (n != 16 && n != 18)
                fail(lex.loc(t),
                     "#material needs 16 (V0) or 18 (V1) numbers before its "
                     "!…! string, got " +
                         std::to_string(n));
            const Dialect d = n == 16 ? Dialect::V0 : Dialect::V1;
            if (m_options.dialect && *m_options.dialect != d)
                fail(lex.loc(t),
                     "#material has " + std::to_string(n) + " numbers, but --dialect " +
                         (*m_options.dialect == Dialect::V0 ? "v0 needs 16" : "v1 needs 18"));
            SourceLoc& first = d == Dialect::V0 ? m_first_v0 : m_first_v1;
            if (!first.file) {
                first = lex.loc(t);
                const SourceLoc& other = d == Dialect::V0 ? m_first_v1 : m_first_v0;
                if (other.file)
                    fail(first, "mixed dialects: V0 material at " + m_first_v0.str() +
                                    ", V1 material at " + m_first_v1.str());
            }
        } else if (t.text.substr(0, 7) == "#shape_") {
            if (lex.peek().text == "-1") m_default_use = true;
        } else if (t.text == "#ray_file") {
            const Token pt = lex.next();
            if (pt.kind != TokenKind::Word) continue;
            const auto resolved = find_file(dir, std::string(pt.text));
            if (!resolved) continue;
            const std::string canon = canonical_path(*resolved);
            if (std::find(visited.begin(), visited.end(), canon) != visited.end()) continue;
            // Too deep: the parse reports it at this directive.
            if (m_include_locs.size() + 1 >= static_cast<size_t>(kMaxIncludeDepth)) continue;
            const std::string* sub = cached_text(*resolved, canon);
            if (!sub) continue;
            const std::string sub_dir = fs::path(*resolved).parent_path().string();
            m_include_locs.push_back(lex.loc(t));
            prescan(*sub, *resolved, canon, sub_dir.empty() ? "." : sub_dir, visited);
            m_include_locs.pop_back();
        }
    }
}

// Included files' texts by canonical path, read by the pre-scan and handed to the parse.
const std::string* ParserBase::cached_text(const std::string& path, const std::string& canonical) {
    auto it = m_texts.find(canonical);
    if (it != m_texts.end()) return &it->second;
    std::string text;
    if (!read_file(path, &text)) return nullptr;
    return &m_texts.emplace(canonical, std::move(text)).first->second;
}

void ParserBase::detect_dialect(const std::string& text, const std::string& name,
                                const std::string& canonical, const std::string& dir) {
    std::vector<std::string> visited;
    prescan(text, name, canonical, dir, visited);
    if (m_options.dialect)
        m_dialect = *m_options.dialect;
    else if (m_first_v0.file)
        m_dialect = Dialect::V0;
    else if (m_first_v1.file)
        m_dialect = Dialect::V1;
    else
        m_dialect = m_default_use ? Dialect::V0 : Dialect::V1;
}

}  // namespace parser_impl
}  // namespace rt
