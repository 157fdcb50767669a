// The dialect pre-scan (spec §10): before any material is interpreted, the whole file tree is
// scanned for V3 markers, V0/V1 markers, #material number counts (16 = V0, 18 = V1) and uses of
// the V0 default material. The texts it reads are kept for the parse (cached_text).
#include <algorithm>
#include <array>
#include <filesystem>
#include <optional>
#include <utility>
#include <variant>

#include "format/driver.h"
#include "rt/util/file_io.h"

namespace fs = std::filesystem;

namespace rt {

const char* dialect_name(Dialect d) {
    static constexpr std::array<const char*, 3> kNames = {"V0", "V1", "V3"};  // Dialect's order
    return kNames[static_cast<size_t>(d)];
}

namespace parser_impl {

std::optional<ShapeKind> shape_directive_kind(std::string_view d) {
    constexpr std::string_view prefix = "#shape_";
    if (d.substr(0, prefix.size()) != prefix) return std::nullopt;
    const std::string_view name = d.substr(prefix.size());
    std::optional<ShapeKind> kind;
    [&]<size_t... I>(std::index_sequence<I...>) {
        ((name == std::variant_alternative_t<I, Shape>::kName
              ? void(kind = std::variant_alternative_t<I, Shape>::kKind)
              : void()),
         ...);
    }
    (std::make_index_sequence<kShapeKinds>{});
    return kind;
}

bool is_v01_directive(std::string_view d) {
    static constexpr std::array<std::string_view, 6> names = {
        "#group_begin", "#group_end", "#joint_begin", "#joint_end", "#background", "#ambient"};
    for (std::string_view n : names)
        if (n == d) return true;
    return d.size() > 4 && d.substr(d.size() - 4) == "_num";
}

namespace {

// Directives that exist only in the V3 dialect (spec §10 step 1).
bool is_v3_directive(std::string_view d) {
    if (d == "#vertex" || d == "#shape_triangle") return false;  // the mesh directives, first
    static constexpr std::array<std::string_view, 10> names = {
        "#static_affine",   "#dynamic_affine", "#shape_list_begin",   "#shape_list_end",
        "#shape_triangles", "#shape_union",    "#shape_intersection", "#shape_difference",
        "#light_sphere",    "#shader"};
    for (std::string_view n : names)
        if (n == d) return true;
    // And #shape_<kind> for the shape kinds that exist in V3 only (kV3Only, shapes.h).
    const std::optional<ShapeKind> kind = shape_directive_kind(d);
    return kind &&
           visit_kind(*kind, [](auto tag) { return kV3OnlyShape<typename decltype(tag)::type>; });
}

// Whether `s` is a number and an integer, as parse_real and parse_int decide, without converting
// the common forms: a sign, digits and at most one point (no exponent, under 300 characters) is a
// finite real, and with no point and at most 9 digits an int. Other words take the parsers.
void classify_number(std::string_view s, bool* real, bool* integer) {
    const size_t first = !s.empty() && (s[0] == '+' || s[0] == '-') ? 1 : 0;
    size_t digits = 0, points = 0;
    bool plain = s.size() < 300;
    for (size_t k = first; k < s.size() && plain; ++k) {
        if (s[k] >= '0' && s[k] <= '9')
            ++digits;
        else if (s[k] == '.' && points == 0)
            ++points;
        else
            plain = false;
    }
    if (plain && digits > 0 && (points > 0 || digits <= 9)) {
        *real = true;
        *integer = points == 0;
        return;
    }
    double v = 0;
    int k = 0;
    bool flag = false;
    *real = parse_real(s, &v, &flag);
    *integer = parse_int(s, &k, &flag);
}

// Consumes the words up to the next directive: how many, and whether all are reals / ints.
int count_words(Lexer& lex, bool* reals, bool* ints) {
    int n = 0;
    *reals = *ints = true;
    for (Token a = lex.peek(); a.kind == TokenKind::Word; a = lex.peek()) {
        lex.next();
        bool real = false, integer = false;
        classify_number(a.text, &real, &integer);
        *reals = *reals && real;
        *ints = *ints && integer;
        ++n;
    }
    return n;
}

const char* forced_name(Dialect d) {
    return d == Dialect::V0 ? "v0" : d == Dialect::V1 ? "v1" : "v3";
}

}  // namespace

struct Parser::Scan {
    bool v3_paths = false;  // locate #ray_file paths by spec §13.2 rather than §4.2
    bool follow = true;     // follow #ray_file
    bool includes = false;  // the scan met a #ray_file (followed or not)
    std::vector<std::string> visited;
    std::vector<std::pair<std::string, SourceLoc>> found;  // #ray_file resolutions, in order
    SourceLoc v3_loc, v01_loc;                             // first marker of each kind
    std::vector<SourceLoc> v3_chain, v01_chain;            // and the includes that led there
    std::string v3_what, v01_what;
    int v3_order = 0, v01_order = 0, order = 0;
};

std::optional<std::string> Parser::find_file(const std::string& dir, const std::string& path,
                                             bool v3) const {
    const fs::path p(path);
    if (p.is_absolute()) return is_file(p) ? std::optional<std::string>(path) : std::nullopt;
    std::vector<fs::path> candidates;
    if (v3) candidates.push_back(fs::path(m_top_dir) / p);
    candidates.push_back(fs::path(dir) / p);
    candidates.push_back(fs::path(".") / p);
    for (const fs::path& c : candidates)
        if (is_file(c)) return c.lexically_normal().string();
    return std::nullopt;
}

// Whether prescan_marker has anything to do with a marker of this kind: the first of its kind, or
// any under --dialect (so the location and the text are made only then).
bool Parser::wants_marker(bool v3, const Scan& scan) const {
    return m_options.dialect || !(v3 ? scan.v3_loc : scan.v01_loc).file;
}

// Spec §10 step 1 and step 5: records the first marker of each kind, or refuses it under
// --dialect of the other kind.
void Parser::prescan_marker(const SourceLoc& loc, std::string_view what, bool v3, Scan& scan) {
    if (m_options.dialect) {
        const Dialect forced = *m_options.dialect;
        const std::string by =
            std::string(dialect_name(forced)) + " by --dialect " + forced_name(forced);
        if (v3 && forced != Dialect::V3)
            scan_fail(loc, std::string(what) + " is V3 syntax; the tree was forced to " + by);
        if (!v3 && forced == Dialect::V3)
            scan_fail(loc, std::string(what) + " is V0/V1 syntax; the tree was forced to " + by);
        return;
    }
    SourceLoc& first = v3 ? scan.v3_loc : scan.v01_loc;
    if (first.file) return;
    first = loc;
    (v3 ? scan.v3_chain : scan.v01_chain).assign(m_scan_locs.rbegin(), m_scan_locs.rend());
    (v3 ? scan.v3_what : scan.v01_what) = std::string(what);
    (v3 ? scan.v3_order : scan.v01_order) = ++scan.order;
}

// Runs for every directive of the tree: its location and quoted name are made only where a
// marker or an error needs them.
void Parser::prescan_directive(Lexer& lex, const Token& t, const std::string& dir, Scan& scan) {
    const auto loc = [&] { return lex.loc(t); };
    const auto marker = [&](bool v3, const std::string& suffix = {}) {
        if (wants_marker(v3, scan)) prescan_marker(loc(), quote(t.text) + suffix, v3, scan);
    };
    if (t.text == "#version")
        scan_fail(loc(), "'#version' belongs to the HMC CS155 ray format, not a Kazhdan .ray file");
    if (is_v3_directive(t.text)) return marker(true);
    if (is_v01_directive(t.text)) return marker(false);
    bool reals = false, ints = false;
    if (t.text == "#light_dir" || t.text == "#light_point" || t.text == "#light_spot") {
        const int v01 = t.text == "#light_dir" ? 6 : t.text == "#light_point" ? 9 : 14;
        const int v3 = t.text == "#light_dir" ? 12 : t.text == "#light_point" ? 15 : 20;
        const int n = count_words(lex, &reals, &ints);
        if (!reals) return;  // the parse reports the bad token at its place
        if (n != v01 && n != v3)
            scan_fail(loc(), std::string(t.text) + " needs " + std::to_string(v01) +
                                 " (V0/V1) or " + std::to_string(v3) + " (V3) numbers, got " +
                                 std::to_string(n));
        return marker(n == v3, " with " + std::to_string(n) + " numbers");
    }
    if (t.text == "#material") {
        const SourceLoc mloc = loc();
        bool numbers = true, integers = true;
        const int n = count_words(lex, &numbers, &integers);
        // A bad token or a missing string is reported by the parse at its place.
        if (!numbers || (lex.peek().kind != TokenKind::String && (n == 16 || n == 18))) return;
        if (n != 16 && n != 18)
            scan_fail(mloc,
                      "#material needs 16 (V0) or 18 (V1) numbers before its "
                      "!…! string, got " +
                          std::to_string(n));
        const Dialect d = n == 16 ? Dialect::V0 : Dialect::V1;
        if (m_options.dialect && *m_options.dialect != d &&
            !(*m_options.dialect == Dialect::V3 && d == Dialect::V1))
            scan_fail(mloc, "#material has " + std::to_string(n) + " numbers, but --dialect " +
                                (*m_options.dialect == Dialect::V0   ? "v0 needs 16"
                                 : *m_options.dialect == Dialect::V1 ? "v1 needs 18"
                                                                     : "v3 needs 18"));
        if (d == Dialect::V0) prescan_marker(mloc, "'#material' with 16 numbers", false, scan);
        SourceLoc& first = d == Dialect::V0 ? m_first_v0 : m_first_v1;
        if (!first.file) {
            first = mloc;
            const SourceLoc& other = d == Dialect::V0 ? m_first_v1 : m_first_v0;
            if (other.file && !scan.v3_loc.file)
                scan_fail(first, "mixed dialects: V0 material at " + m_first_v0.str() +
                                     ", V1 material at " + m_first_v1.str());
        }
    } else if (t.text.substr(0, 7) == "#shape_") {
        if (lex.peek().text == "-1") m_default_use = true;
        // Once the first V0/V1 marker is known a triangle tells nothing more: its words are
        // skipped by the loop without being classified (most of a mesh's text).
        if (t.text == "#shape_triangle" && wants_marker(false, scan) &&
            count_words(lex, &reals, &ints) == 4 && ints)
            prescan_marker(loc(), "'#shape_triangle' with 4 integers", false, scan);
    } else if (t.text == "#ray_file") {
        scan.includes = true;
        if (!scan.follow) return;
        const Token pt = lex.next();
        if (pt.kind != TokenKind::Word) return;
        const auto resolved = find_file(dir, std::string(pt.text), scan.v3_paths);
        scan.found.emplace_back(resolved ? *resolved : std::string(), lex.loc(pt));
        if (!resolved) return;
        const std::string canon = canonical_path(*resolved);
        if (std::find(scan.visited.begin(), scan.visited.end(), canon) != scan.visited.end())
            return;
        // Too deep: the parse reports it at this directive.
        if (m_scan_locs.size() + 1 >= static_cast<size_t>(kMaxIncludeDepth)) return;
        const FileBytes* sub = cached_text(*resolved, canon);
        if (!sub) return;
        const std::string sub_dir = fs::path(*resolved).parent_path().string();
        m_scan_locs.push_back(loc());
        prescan(text_of(*sub), *resolved, canon, sub_dir.empty() ? "." : sub_dir, scan);
        m_scan_locs.pop_back();
    }
}

// Follows the #ray_file paths it can resolve; the parse reports the others.
void Parser::prescan(std::string_view text, const std::string& name, const std::string& canonical,
                     const std::string& dir, Scan& scan) {
    scan.visited.push_back(canonical);
    const std::string* file = intern_file_name(name);
    // Spec §10 step 0: other formats named .ray.
    const std::string_view body = text.substr(text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0);
    if (body.substr(0, 13) == "SBT-raytracer")
        scan_fail(
            {file, 1, 1},
            "this is an SBT-raytracer scene (U. Washington CSE 457 / UT Austin CS 354 format), "
            "not a Kazhdan .ray file");
    Lexer lex(text, file);
    // What the parse reserves room for: the file's vertices and the shapes outside its groups
    // (most of a mesh), so its arrays are allocated once rather than doubled and copied.
    size_t vertices = 0, top_shapes = 0;
    int depth = 0;
    // The runs of one mesh directive, marked every `piece` directives (mesh_runs.cpp).
    std::vector<MeshRun> runs;
    MeshRun run;
    std::string_view run_name;
    const size_t piece = std::max<size_t>(1, m_options.piece);
    size_t directives = 0;
    const auto end_run = [&](size_t end) {
        if (run.marks.size() >= 2) {
            run.end = end;
            runs.push_back(std::move(run));
        }
        run = MeshRun{};
    };
    for (;;) {
        lex.skip_words();  // what the loop would read and drop, most of a mesh's text
        const Token t = lex.next();
        if (t.kind == TokenKind::End) break;
        if (t.kind != TokenKind::Directive) continue;
        const std::string_view d = t.text;
        const size_t at = lex.offset(t);
        if (m_options.progress && ++directives % 1024 == 0) check_cancel(m_build, lex.loc(t));
        if (d == run_name) {
            if (run.count % piece == 0) run.marks.push_back({at, t.line, t.col, run.count});
            ++run.count;
        } else {
            end_run(at);
            run_name = d == "#vertex" || d == "#shape_triangle" ? d : std::string_view();
            if (!run_name.empty()) {
                run.vertices = d == "#vertex";
                run.marks.push_back({at, t.line, t.col, 0});
                run.count = 1;
            }
        }
        if (d == "#vertex")
            ++vertices;
        else if (d.substr(0, 7) == "#shape_" && depth == 0)
            ++top_shapes;
        else if (d == "#group_begin" || d == "#joint_begin")
            ++depth;
        else if ((d == "#group_end" || d == "#joint_end") && depth > 0)
            --depth;
        prescan_directive(lex, t, dir, scan);
    }
    end_run(SIZE_MAX);
    m_sizes[canonical] = {vertices, top_shapes, std::move(runs)};
}

void Parser::run_prescan(std::string_view text, const std::string& name,
                         const std::string& canonical, const std::string& dir, bool v3,
                         Scan& scan) {
    m_first_v0 = m_first_v1 = SourceLoc{};
    m_default_use = false;
    scan.v3_paths = v3;
    prescan(text, name, canonical, dir, scan);
}

void Parser::scan_fail(const SourceLoc& loc, const std::string& message) const {
    std::vector<SourceLoc> chain(m_scan_locs.rbegin(), m_scan_locs.rend());
    throw SceneError(loc, message, std::move(chain));
}

// Included files' texts by canonical path, read by the pre-scan and handed to the parse.
const FileBytes* Parser::cached_text(const std::string& path, const std::string& canonical,
                                     std::string* why) {
    auto it = m_texts.find(canonical);
    if (it != m_texts.end()) return &it->second;
    FileBytes text;
    if (!read_file(path, &text, why)) return nullptr;
    count_text(text.size());
    m_text_names.emplace(canonical, path);
    return &m_texts.emplace(canonical, std::move(text)).first->second;
}

void Parser::detect_dialect(std::string_view text, const std::string& name,
                            const std::string& canonical, const std::string& dir) {
    m_top_dir = dir;
    const bool forced_v3 = m_options.dialect == Dialect::V3;
    // Spec §10 step 6: §13.2 paths once the top-level file itself is V3.
    Scan top;
    top.follow = false;
    if (!forced_v3) run_prescan(text, name, canonical, dir, false, top);
    Scan scan;
    if (!forced_v3 && !top.includes) {  // a file alone: the scan that follows includes is the same
        scan = std::move(top);
        scan.follow = true;
        scan.v3_paths = scan.v3_loc.file != nullptr;
    } else {
        run_prescan(text, name, canonical, dir, forced_v3 || top.v3_loc.file != nullptr, scan);
    }
    if (scan.v3_loc.file && !scan.v3_paths) {
        // V3 only through an included file: locate the paths again by §13.2.
        Scan again;
        run_prescan(text, name, canonical, dir, true, again);
        size_t i = 0;
        while (i < scan.found.size() && i < again.found.size() &&
               scan.found[i].first == again.found[i].first)
            ++i;
        if (i < scan.found.size() || i < again.found.size()) {
            if (!again.v3_loc.file)
                scan_fail(i < again.found.size() ? again.found[i].second : scan.found[i].second,
                          "the dialect of this tree depends on path resolution");
            scan = std::move(again);
        }
    }
    if (scan.v3_loc.file && scan.v01_loc.file) {
        const bool v3_later = scan.v3_order > scan.v01_order;
        const bool v0 = scan.v01_what.find("16 numbers") != std::string::npos;
        std::string v01 = scan.v01_what.substr(0, scan.v01_what.find(" with "));
        // Reported at the later marker, with the includes that led to it.
        throw SceneError(
            v3_later ? scan.v3_loc : scan.v01_loc,
            "mixed dialects: V3 " + scan.v3_what.substr(0, scan.v3_what.find(" with ")) + " at " +
                scan.v3_loc.str() + ", " + (v0 ? "V0 " : "V1 ") + v01 + " at " + scan.v01_loc.str(),
            v3_later ? scan.v3_chain : scan.v01_chain);
    }
    std::string marker;
    if (scan.v3_loc.file)
        marker = scan.v3_what.substr(0, scan.v3_what.find(" with ")) + " at " + scan.v3_loc.str();
    if (m_options.dialect)
        m_dialect = *m_options.dialect;
    else if (scan.v3_loc.file)
        m_dialect = Dialect::V3;
    else if (m_first_v0.file)
        m_dialect = Dialect::V0;
    else if (m_first_v1.file)
        m_dialect = Dialect::V1;
    else
        m_dialect = m_default_use ? Dialect::V0 : Dialect::V1;
    m_v3_marker = std::move(marker);
    m_build.set_dialect(m_dialect, m_top_dir);
}

}  // namespace parser_impl
}  // namespace rt
