// The .ray directives (spec §2-§4, §10). One Parser walks the whole file tree: each file is parsed
// once per canonical path into a FileDesc; the dialect is fixed by the material number counts of
// the whole tree (the pre-scan in dialect.cpp), and the checks that depend on it run when the tree
// is complete. The helpers that parser_impl.h declares for all three parts are defined here too.
#include "rt/format/parser.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "format/lexer.h"
#include "format/parser_impl.h"
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

namespace {

// Length in bytes of the valid UTF-8 sequence at s[i] (0 when it is not one).
size_t utf8_length(std::string_view s, size_t i) {
    const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    size_t n = 0;
    if (c >= 0xC2 && c <= 0xDF)
        n = 2;
    else if (c >= 0xE0 && c <= 0xEF)
        n = 3;
    else if (c >= 0xF0 && c <= 0xF4)
        n = 4;
    if (n == 0 || i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k)
        if ((b(i + k) & 0xC0) != 0x80) return 0;
    // No overlong forms, surrogates or code points above U+10FFFF.
    if ((c == 0xE0 && b(i + 1) < 0xA0) || (c == 0xED && b(i + 1) > 0x9F) ||
        (c == 0xF0 && b(i + 1) < 0x90) || (c == 0xF4 && b(i + 1) > 0x8F))
        return 0;
    return n;
}

}  // namespace

// A token or path in a message: quoted, control bytes and invalid UTF-8 written as \xNN, and
// cut after 200 bytes (a 100 MB token makes a short message).
std::string quote(std::string_view s) {
    constexpr size_t kMax = 200;
    static constexpr char kHex[] = "0123456789abcdef";
    std::string r = "'";
    size_t i = 0;
    while (i < s.size() && i < kMax) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        const size_t n = c >= 0x80 ? utf8_length(s, i) : (c < 0x20 || c == 0x7F ? 0 : 1);
        if (n == 0) {
            r += "\\x";
            r += kHex[c >> 4];
            r += kHex[c & 15];
            ++i;
        } else {
            r.append(s.substr(i, n));
            i += n;
        }
    }
    r += '\'';
    if (i < s.size()) {
        r += "... (";
        r += std::to_string(s.size());
        r += " bytes)";
    }
    return r;
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

// ---- token helpers ------------------------------------------------------------------------------
// Missing arguments point at the directive; a bad token points at itself (spec §2).
SourceLoc ParserBase::arg_loc(FileState& f, const Token& dir, const Token& bad) const {
    return (bad.kind == TokenKind::End || bad.kind == TokenKind::Directive) ? f.lex.loc(dir)
                                                                            : f.lex.loc(bad);
}

double ParserBase::real(FileState& f, const Token& dir, int count) {
    const Token t = f.lex.next();
    double v = 0.0;
    bool non_finite = false;
    if (t.kind == TokenKind::Word && parse_real(t.text, &v, &non_finite)) return v;
    if (non_finite) fail(f, t, "non-finite number " + quote(t.text));
    fail(arg_loc(f, dir, t), "expected " + std::to_string(count) +
                                 (count == 1 ? " number" : " numbers") + " after " +
                                 std::string(dir.text) + ", got " + describe(t));
}

Vec3 ParserBase::vec3(FileState& f, const Token& dir, int count) {
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = real(f, dir, count);
    return v;
}

int ParserBase::integer(FileState& f, const Token& dir, std::string_view what, SourceLoc* loc) {
    const Token t = f.lex.next();
    int v = 0;
    bool out_of_range = false;
    if (loc) *loc = f.lex.loc(t);
    if (t.kind == TokenKind::Word && parse_int(t.text, &v, &out_of_range)) return v;
    if (out_of_range) fail(f, t, "integer " + quote(t.text) + " out of range");
    fail(arg_loc(f, dir, t), "expected an integer (" + std::string(what) + "), got " + describe(t));
}

std::string ParserBase::word(FileState& f, const Token& dir, std::string_view what, bool ascii) {
    const Token t = f.lex.next();
    if (t.kind == TokenKind::Word) {
        // Spec §2: non-ASCII bytes only in comments, strings and paths.
        if (ascii)
            for (char c : t.text)
                if (static_cast<unsigned char>(c) >= 0x80)
                    fail(f, t, "non-ASCII byte in " + std::string(what) + " " + quote(t.text));
        return std::string(t.text);
    }
    fail(arg_loc(f, dir, t), "expected " + std::string(what) + " after " + std::string(dir.text) +
                                 ", got " + describe(t));
}

Vec3 ParserBase::colour(FileState& f, const Token& dir, int count, std::string_view what) {
    Vec3 c;
    for (int i = 0; i < 3; ++i) {
        const Token t = f.lex.peek();
        c[i] = real(f, dir, count);
        if (c[i] < 0) fail(f, t, "negative " + std::string(what) + " " + fmt(c[i]));
    }
    return c;
}

std::string ParserBase::fmt(double v) {
    std::ostringstream ss;
    ss << v;
    return ss.str();
}
std::string ParserBase::fmt(const Vec3& v) { return fmt(v.x) + " " + fmt(v.y) + " " + fmt(v.z); }

// ---- counts -------------------------------------------------------------------------------------
void ParserBase::declare_count(FileState& f, const Token& dir, CountKind k) {
    SourceLoc loc;
    const int n = integer(f, dir, "count", &loc);
    Count& c = f.counts[k];
    if (c.declared)
        fail(f, dir,
             "second " + std::string(kCountDirective[k]) + " (first at " + c.loc.str() + ")");
    if (c.found > 0)
        fail(f, dir, std::string(kCountDirective[k]) + " after the first " + kItemDirective[k]);
    if (n < 0) fail(loc, "negative count " + std::to_string(n));
    c.declared = true;
    c.declared_n = n;
    c.loc = f.lex.loc(dir);
    // Reserve no more than the rest of the text can hold (a #vertex takes >= 24 bytes), so a
    // huge count cannot allocate before the file runs out.
    if (k == kVertices)
        f.desc.vertices.reserve(std::min(static_cast<size_t>(n), f.lex.remaining() / 24));
}

void ParserBase::count_item(FileState& f, const Token& dir, CountKind k) {
    Count& c = f.counts[k];
    ++c.found;
    if (c.declared && c.found > c.declared_n)
        fail(f, dir,
             "more " + std::string(k == kLights ? "lights" : kItemDirective[k]) +
                 " than declared by " + kCountDirective[k] + " at " + c.loc.str());
}

// ---- paths --------------------------------------------------------------------------------------
// Spec §4.2: relative to the naming file's directory, then the working directory. V3 (spec §13.2):
// the top-level file's directory first, then those two with a warning.
std::optional<std::string> ParserBase::try_resolve(FileState& f, const Token& at,
                                                   const std::string& path, std::string* tried) {
    const fs::path p(path);
    if (p.is_absolute()) {
        if (tried) tried->clear();
        return is_file(p) ? std::optional<std::string>(path) : std::nullopt;
    }
    const bool v3 = m_dialect == Dialect::V3;
    std::vector<fs::path> places;
    if (v3) places.push_back(fs::path(m_top_dir) / p);
    places.push_back(fs::path(f.dir) / p);
    places.push_back(fs::path(".") / p);
    std::vector<fs::path> unique;
    for (const fs::path& c : places)
        if (std::find_if(unique.begin(), unique.end(), [&](const fs::path& u) {
                return u.lexically_normal() == c.lexically_normal();
            }) == unique.end())
            unique.push_back(c);
    for (size_t i = 0; i < unique.size(); ++i) {
        if (!is_file(unique[i])) continue;
        const std::string found = unique[i].lexically_normal().string();
        if (v3 && i > 0)
            warn(f.lex.loc(at), "v3-path:" + path,
                 quote(path) + " found as " + found + ", not in " + m_top_dir +
                     " (V3 resolves paths against the top-level file's directory)");
        return found;
    }
    if (tried) {
        tried->clear();
        for (const fs::path& c : unique) *tried += (tried->empty() ? "" : ", ") + c.string();
    }
    return std::nullopt;
}

std::string ParserBase::resolve(FileState& f, const Token& at, const std::string& path,
                                const std::string& what) {
    std::string tried;
    if (auto found = try_resolve(f, at, path, &tried)) return *found;
    if (tried.empty()) fail(f, at, "cannot open " + what + " " + quote(path));
    fail(f, at, "cannot open " + what + " " + quote(path) + " (tried " + tried + ")");
}

CameraDesc ParserBase::read_camera(FileState& f, const Token& d) {
    CameraDesc c;
    c.loc = f.lex.loc(d);
    c.position = vec3(f, d, 10);
    c.direction = vec3(f, d, 10);
    c.up = vec3(f, d, 10);
    c.half_height_angle_rad = real(f, d, 10);
    return c;
}

bool ParserBase::dummy_camera(const CameraDesc& c) {
    if (c.position != Vec3(0.0) || c.direction != Vec3(0.0) || c.up != Vec3(0.0) ||
        c.half_height_angle_rad != 0.0)
        return false;
    warn(c.loc, "camera-zero", "all-zero #camera (a sub-file's dummy): using the default camera");
    v3_all_zero_camera = true;
    return true;
}

void ParserBase::validate_camera(FileState& f, const Token& d, const CameraDesc& c) {
    if (glm::length(c.direction) == 0.0) fail(f, d, "camera view direction is zero");
    if (glm::length(c.up) == 0.0) fail(f, d, "camera up vector is zero");
    if (glm::length(glm::cross(glm::normalize(c.direction), glm::normalize(c.up))) < 1e-6)
        fail(f, d, "camera up vector is parallel to the view direction");
    if (!(c.half_height_angle_rad > 0.0 && c.half_height_angle_rad < kPi / 2))
        fail(f, d,
             "camera half-height angle " + fmt(c.half_height_angle_rad) +
                 " is outside (0, pi/2) radians");
}

// Three vertex indices of this file (spec §3.3; V3 §13.5), each checked against its vertices.
TriangleDesc ParserBase::triangle_indices(FileState& f, const Token& d) {
    TriangleDesc g;
    const int nv = static_cast<int>(f.defs().vertices.size());
    for (int i = 0; i < 3; ++i) {
        SourceLoc loc;
        g.v[i] = integer(f, d, "vertex index", &loc);
        if (g.v[i] < 0 || g.v[i] >= nv)
            fail(loc, "vertex index " + std::to_string(g.v[i]) + " out of range [0," +
                          std::to_string(nv) + ")");
    }
    return g;
}

bool ParserBase::degenerate_triangle(const FileDesc& file, const TriangleDesc& t) {
    // Spec §3.3: a repeated index, or |e1 x e2| <= 1e-12 |e1| |e2|.
    if (t.v[0] == t.v[1] || t.v[1] == t.v[2] || t.v[0] == t.v[2]) return true;
    const Vec3& p0 = file.vertices[static_cast<size_t>(t.v[0])].position;
    const Vec3 e1 = file.vertices[static_cast<size_t>(t.v[1])].position - p0;
    const Vec3 e2 = file.vertices[static_cast<size_t>(t.v[2])].position - p0;
    return glm::length(glm::cross(e1, e2)) <= 1e-12 * glm::length(e1) * glm::length(e2);
}

// ---- matrices -----------------------------------------------------------------------------------
void ParserBase::check_matrix(const Mat4& m, const SourceLoc& loc, const std::string& what) {
    // Spec §3.3 / §4.1: affine (bottom row 0 0 0 1) and non-singular.
    if (std::abs(m[0][3]) > 1e-9 || std::abs(m[1][3]) > 1e-9 || std::abs(m[2][3]) > 1e-9 ||
        std::abs(m[3][3] - 1.0) > 1e-9)
        fail(loc, "projective " + what + ": the bottom row must be 0 0 0 1");
    const Mat3 a(m);
    if (!std::isfinite(glm::determinant(a)) ||
        !std::isfinite(std::hypot(a[0].x, a[0].y, a[0].z) * std::hypot(a[1].x, a[1].y, a[1].z) *
                       std::hypot(a[2].x, a[2].y, a[2].z)))
        fail(loc, what + " too large: its determinant overflows");
    if (singular_3x3(a)) fail(loc, "singular " + what);
}

namespace {

class Parser final : public ParserV3 {
public:
    Parser(Diagnostics& diag, const ParseOptions& options) : ParserV3(diag, options) {}

    SceneDesc run(std::string_view text, const std::string& name, const std::string& dir) {
        const std::string canonical = canonical_path(name);
        count_text(text.size());
        detect_dialect(text, name, canonical, dir);
        m_scene.files.emplace_back();
        parse_file(text, name, canonical, dir, 0);
        finish();
        return std::move(m_scene);
    }

    SceneDesc run_file(const std::string& path) {
        FileBytes text;
        std::string why;
        if (!read_file(path, &text, &why)) {
            SourceLoc loc{intern_file_name(path), 0, 0};
            throw SceneError(loc, read_failure("cannot open scene file", path, why));
        }
        const std::string dir = fs::path(path).parent_path().string();
        return run(text_of(text), path, dir.empty() ? "." : dir);
    }

private:
    // ---- the file loop -------------------------------------------------------------------
    void parse_file(std::string_view text, const std::string& name, const std::string& canonical,
                    const std::string& dir, int index) {
        const std::string* file_name = intern_file_name(name);
        m_open.push_back({canonical, name});

        FileState f(text, file_name);
        f.top = (index == 0);
        f.dir = dir;
        f.desc.path = name;
        f.desc.canonical_path = canonical;
        f.stack.push_back(&f.desc.root);
        f.stack_is_joint.push_back(0);

        const bool v3 = m_dialect == Dialect::V3;
        if (v3) f.v3.push_back({});  // the root list
        if (auto it = m_sizes.find(canonical); it != m_sizes.end()) {
            // No more than the text can hold when every one is well formed (a #vertex or a
            // shape takes >= 24 bytes), whatever a hostile file's directives count.
            const size_t fit = text.size() / 24;
            f.desc.vertices.reserve(std::min(it->second.vertices, fit));
            if (!v3) f.desc.root.shapes.reserve(std::min(it->second.top_shapes, fit));
        }
        walk_file(f);
        end_of_file(f);
        m_open.pop_back();
        m_scene.files[static_cast<size_t>(index)] = std::move(f.desc);
    }

    void end_of_file(FileState& f) {
        const Token end = f.lex.next();
        const SourceLoc eof = f.lex.loc(end);
        const int ntex = static_cast<int>(f.desc.textures.size());
        for (const FileState::TextureRef& r : f.texture_refs)
            if (r.index < -1 || r.index >= ntex)
                fail(r.loc, "texture index " + std::to_string(r.index) + " out of range [-1," +
                                std::to_string(ntex) + ")");
        if (m_dialect == Dialect::V3) return v3_end_of_file(f, eof);
        if (f.stack.size() > 1) {
            const GroupDesc* g = f.stack.back();
            fail(eof, std::string(f.stack_is_joint.back() ? "#joint_begin" : "#group_begin") +
                          " at " + g->loc.str() + " is never closed");
        }
        for (int k = 0; k < kCountKinds; ++k) {
            const Count& c = f.counts[static_cast<size_t>(k)];
            if (c.declared && c.found < c.declared_n)
                fail(eof, std::string(kCountDirective[static_cast<size_t>(k)]) + " at " +
                              c.loc.str() + " declares " + std::to_string(c.declared_n) +
                              ", found " + std::to_string(c.found));
        }
    }

    void dispatch(FileState& f, const Token& d) override {
        if (m_dialect == Dialect::V3)
            v3_directive(f, d);
        else
            directive(f, d);
    }

    void definition(FileState& f, const Token& dir) {
        if (f.graph_started) fail(f, dir, "definition after the scene graph started");
    }

    void graph(FileState& f) { f.graph_started = true; }

    // The V0/V1 directives (spec §3, §4), each with what reads it, the mesh directives first;
    // then #shape_<kind> of every kind that is not V3 only (shapes.h).
    void directive(FileState& f, const Token& d) {
        using Read = void (Parser::*)(FileState&, const Token&);
        struct V1Directive {
            std::string_view name;
            Read read;
        };
        static constexpr std::array<V1Directive, 23> kV1Directives = {{
            {"#vertex", &Parser::vertex},
            {"#shape_triangle", &Parser::shape},
            {"#camera", &Parser::camera},
            {"#background", &Parser::global_colour},
            {"#ambient", &Parser::global_colour},
            {"#light_num", &Parser::count<kLights>},
            {"#light_dir", &Parser::light},
            {"#light_point", &Parser::light},
            {"#light_spot", &Parser::light},
            {"#texture_num", &Parser::count<kTextures>},
            {"#texture", &Parser::texture},
            {"#material_num", &Parser::count<kMaterials>},
            {"#material", &Parser::material},
            {"#vertex_num", &Parser::count<kVertices>},
            {"#ray_file_num", &Parser::count<kRayFiles>},
            {"#ray_file", &Parser::ray_file},
            {"#key_file_num", &Parser::count<kKeyFiles>},
            {"#key_file", &Parser::key_file},
            {"#group_begin", &Parser::group_begin},
            {"#group_end", &Parser::group_end},
            {"#joint_begin", &Parser::joint_begin},
            {"#joint_end", &Parser::joint_end},
            {"#ray_file_instance", &Parser::instance},
        }};
        for (const V1Directive& e : kV1Directives)
            if (e.name == d.text) return (this->*e.read)(f, d);
        const std::optional<ShapeKind> kind = shape_directive_kind(d.text);
        if (kind &&
            !visit_kind(*kind, [](auto tag) { return kV3OnlyShape<typename decltype(tag)::type>; }))
            return shape(f, d);
        fail(f, d, "unknown directive " + quote(d.text));
    }

    template <CountKind K>
    void count(FileState& f, const Token& d) {
        definition(f, d);
        declare_count(f, d, K);
    }

    // ---- definitions ---------------------------------------------------------------------
    void camera(FileState& f, const Token& d) {
        definition(f, d);
        const CameraDesc c = read_camera(f, d);
        // Included files: syntax only, so the dummy all-zero cameras of sub-files pass (§3.1, §12).
        if (!f.top) return;
        // The course's V3 sub-files without a V3 marker read as V1 (§10 step 4), and opened on
        // their own they should render as V3 ones do (§13.3): the dummy camera (never a valid
        // camera) is the default camera with a warning in every dialect.
        if (!m_scene.camera && dummy_camera(c)) return;
        validate_camera(f, d, c);
        if (m_scene.camera) {
            warn(c.loc, "camera-repeat",
                 "second #camera ignored; the first one (" + m_scene.camera->loc.str() + ") wins");
            return;
        }
        m_scene.camera = c;
    }

    void global_colour(FileState& f, const Token& d) {
        definition(f, d);
        const bool bg = d.text == "#background";
        if (!f.top) {  // included files: syntax only
            vec3(f, d, 3);
            return;
        }
        const Vec3 c = colour(f, d, 3, bg ? "background colour" : "ambient colour");
        bool& seen = bg ? m_seen_background : m_seen_ambient;
        if (seen) {
            warn(f.lex.loc(d), std::string(d.text) + "-repeat",
                 "repeated " + std::string(d.text) + " ignored; the first one wins");
            return;
        }
        seen = true;
        (bg ? m_scene.background : m_scene.ambient) = c;
    }

    void light(FileState& f, const Token& d) {
        definition(f, d);
        LightDesc l;
        l.loc = f.lex.loc(d);
        if (d.text == "#light_dir") {
            l.kind = LightKind::Directional;
            l.set_colour(colour(f, d, 6, "light colour"));
            l.direction = vec3(f, d, 6);
            if (glm::length(l.direction) == 0.0) fail(f, d, "light direction is zero");
        } else if (d.text == "#light_point") {
            l.kind = LightKind::Point;
            l.set_colour(vec3(f, d, 9));  // spec §3.1: point and spot colours need only be finite
            l.position = vec3(f, d, 9);
            l.constant_atten = real(f, d, 9);
            l.linear_atten = real(f, d, 9);
            l.quadratic_atten = real(f, d, 9);
        } else {
            l.kind = LightKind::Spot;
            l.set_colour(vec3(f, d, 14));
            l.position = vec3(f, d, 14);
            l.direction = vec3(f, d, 14);
            l.constant_atten = real(f, d, 14);
            l.linear_atten = real(f, d, 14);
            l.quadratic_atten = real(f, d, 14);
            const Token cut_tok = f.lex.peek();
            l.cutoff_rad = real(f, d, 14);
            const Token dor_tok = f.lex.peek();
            l.spot_exponent = real(f, d, 14);  // p = 128 dor (V0) or dor (V1)
            if (glm::length(l.direction) == 0.0) fail(f, d, "spot light direction is zero");
            if (l.cutoff_rad < 0) fail(f, cut_tok, "negative spot cutoff " + fmt(l.cutoff_rad));
            if (l.spot_exponent < 0)
                fail(f, dor_tok, "negative spot drop-off " + fmt(l.spot_exponent));
            if (m_dialect == Dialect::V0) l.spot_exponent *= kV0ExponentScale;
            if (l.cutoff_rad > kPi / 2)
                warn(l.loc, "spot-cutoff",
                     "spot cutoff " + fmt(l.cutoff_rad) +
                         " rad is more than pi/2: the light never cuts off");
        }
        if (l.kind != LightKind::Directional && l.constant_atten == 0.0 && l.linear_atten == 0.0 &&
            l.quadratic_atten == 0.0)
            warn(l.loc, "light-zero-atten",
                 "attenuation coefficients are all zero: the light never contributes");
        count_item(f, d, kLights);
        if (!f.top) {
            warn(l.loc, "included-light", "lights in included files are ignored");
            return;
        }
        m_scene.lights.push_back(l);
    }

    void texture(FileState& f, const Token& d) override {
        definition(f, d);
        const Token pt = f.lex.peek();
        const std::string path = word(f, d, "a texture file name");
        count_item(f, d, kTextures);
        TextureDesc t;
        t.loc = f.lex.loc(d);
        std::string tried, problem;
        const std::optional<std::string> found = try_resolve(f, pt, path, &tried);
        if (found) {
            t.path = *found;
            const DecodedTexture& decoded = decode_once(t.path);
            t.image = decoded.image;
            if (!t.image) problem = "cannot decode texture " + quote(t.path) + ": " + decoded.error;
        } else {
            t.path = path;
            problem = "cannot open texture " + quote(path) +
                      (tried.empty() ? std::string() : " (tried " + tried + ")");
        }
        if (!problem.empty()) {
            if (m_options.missing_textures != MissingTextures::Checker) fail(f, pt, problem);
            // --missing-textures checker: a loud stand-in, one warning per missing file.
            t.image = std::make_shared<const TextureImage>(checker_texture());
            const auto& missing = m_scene.missing_textures;
            if (std::find(missing.begin(), missing.end(), path) == missing.end()) {
                m_scene.missing_textures.push_back(path);
                warn(f.lex.loc(pt), "missing-texture:" + path, problem + "; a checker stands in");
            }
        }
        f.desc.textures.push_back(std::move(t));
    }

    // A texture file is decoded once per scene, however many #texture lines (in however many
    // files) name it: every naming shares the image, or the error.
    struct DecodedTexture {
        std::shared_ptr<const TextureImage> image;  // null when it does not decode
        std::string error;
    };
    const DecodedTexture& decode_once(const std::string& path) {
        const auto [it, added] = m_decoded.try_emplace(canonical_path(path));
        if (added) {
            auto image = std::make_shared<TextureImage>();
            if (load_texture_image(path, image.get(), &it->second.error))
                it->second.image = std::move(image);
        }
        return it->second;
    }

    void material(FileState& f, const Token& d) override {
        definition(f, d);
        count_item(f, d, kMaterials);
        const MaterialWords w = material_words(f, d);
        f.desc.materials.push_back(material_of(f, d, w));
    }

    // The syntax of #material (spec §3.1, §10): numbers up to the !…! string, whose count is
    // 16 (V0) or 18 (V1, V3).
    struct MaterialWords {
        std::array<double, 18> v{};
        std::array<Token, 18> tok{};
        int n = 0;
        Token name;  // the !…! string
    };
    MaterialWords material_words(FileState& f, const Token& d) {
        MaterialWords w;
        Token t = f.lex.next();
        for (; t.kind == TokenKind::Word; t = f.lex.next()) {
            double x = 0.0;
            bool non_finite = false;
            if (!parse_real(t.text, &x, &non_finite)) {
                if (non_finite) fail(f, t, "non-finite number " + quote(t.text));
                fail(f, t, "expected a number in #material, got " + quote(t.text));
            }
            if (w.n < 18) {
                w.v[static_cast<size_t>(w.n)] = x;
                w.tok[static_cast<size_t>(w.n)] = t;
            }
            ++w.n;
        }
        if (t.kind != TokenKind::String || (w.n != 16 && w.n != 18)) {
            if (t.kind != TokenKind::String && (w.n == 16 || w.n == 18))
                fail(arg_loc(f, d, t),
                     "#material needs its !…! string after the numbers, got " + describe(t));
            fail(f, d,
                 "#material needs 16 (V0) or 18 (V1) numbers before its !…! string, got " +
                     std::to_string(w.n));
        }
        w.name = t;
        return w;
    }

    // What the numbers mean in the tree's dialect: the colours and terms by position, each
    // checked, and the texture index, whose range is checked at the end of the file.
    MaterialDesc material_of(FileState& f, const Token& d, const MaterialWords& w) {
        const Dialect dialect = w.n == 16 ? Dialect::V0 : Dialect::V1;
        if (dialect != (m_dialect == Dialect::V3 ? Dialect::V1 : m_dialect))  // pre-scan first
            fail(f, d,
                 "#material has " + std::to_string(w.n) + " numbers in a " +
                     dialect_name(m_dialect) + " scene");
        MaterialDesc m;
        m.loc = f.lex.loc(d);
        m.name = std::string(w.name.text.substr(1, w.name.text.size() - 2));
        const auto& v = w.v;
        const auto& tok = w.tok;
        auto rgb = [&](int i, const char* what) {
            const Vec3 c(v[static_cast<size_t>(i)], v[static_cast<size_t>(i) + 1],
                         v[static_cast<size_t>(i) + 2]);
            for (int k = 0; k < 3; ++k)
                if (c[k] < 0)
                    fail(f, tok[static_cast<size_t>(i + k)],
                         std::string("negative ") + what + " " + fmt(c[k]));
            return c;
        };
        auto nonneg = [&](int i, const char* what) {
            const double x = v[static_cast<size_t>(i)];
            if (x < 0)
                fail(f, tok[static_cast<size_t>(i)],
                     std::string("negative ") + what + " " + fmt(x));
            return x;
        };
        int ior_i = 0, tex_i = 0;
        if (dialect == Dialect::V0) {
            // ambient, diffuse, specular, emissive, kspec, ktran, refind, tex
            m.ambient = rgb(0, "ambient");
            m.diffuse = rgb(3, "diffuse");
            m.specular = rgb(6, "specular");
            m.emissive = rgb(9, "emissive");
            m.specular_exponent = kV0ExponentScale * nonneg(12, "kspec");
            m.transparent = Vec3(nonneg(13, "ktran"));
            ior_i = 14;
            tex_i = 15;
        } else {
            // emissive, ambient, diffuse, specular, n, transparent, refind, tex
            m.emissive = rgb(0, "emissive");
            m.ambient = rgb(3, "ambient");
            m.diffuse = rgb(6, "diffuse");
            m.specular = rgb(9, "specular");
            m.specular_exponent = nonneg(12, "specular exponent");
            m.transparent = rgb(13, "transparency");
            ior_i = 16;
            tex_i = 17;
        }
        m.refractive_index = v[static_cast<size_t>(ior_i)];
        if (m.refractive_index <= 0) {
            warn(f.lex.loc(tok[static_cast<size_t>(ior_i)]), "refind",
                 "refractive index " + fmt(m.refractive_index) + " <= 0; 1 is used");
            m.refractive_index = 1.0;
        }
        const Token& tt = tok[static_cast<size_t>(tex_i)];
        int ti = 0;
        bool oor = false;
        if (!parse_int(tt.text, &ti, &oor))
            fail(f, tt, "expected an integer (texture index), got " + quote(tt.text));
        // Definitions may come in any order: the range is checked at the end of the file.
        m.texture = ti;
        f.texture_refs.push_back({f.lex.loc(tt), ti});
        return m;
    }

    void vertex(FileState& f, const Token& d) override {
        definition(f, d);
        count_item(f, d, kVertices);
        VertexDesc v;
        v.position = vec3(f, d, 8);
        v.normal = vec3(f, d, 8);
        v.uv.x = real(f, d, 8);
        v.uv.y = real(f, d, 8);
        const double len = glm::length(v.normal);
        if (len > 0) v.normal /= len;
        add_vertex(f, d, v);
    }

    void ray_file(FileState& f, const Token& d) override {
        definition(f, d);
        const Token pt = f.lex.peek();
        const std::string path = word(f, d, "a .ray file name");
        count_item(f, d, kRayFiles);
        const std::string resolved = resolve(f, pt, path, "ray file");
        const std::string canonical = canonical_path(resolved);

        // A file that (transitively) includes itself is an error naming the chain.
        for (size_t i = 0; i < m_open.size(); ++i) {
            if (m_open[i].canonical == canonical) {
                std::string chain;
                for (size_t k = i; k < m_open.size(); ++k)
                    chain += fs::path(m_open[k].name).filename().string() + " -> ";
                chain += fs::path(resolved).filename().string();
                fail(f, pt, "include cycle: " + chain);
            }
        }
        if (m_open.size() >= static_cast<size_t>(kMaxIncludeDepth))
            fail(f, d,
                 "#ray_file includes nested deeper than " + std::to_string(kMaxIncludeDepth) +
                     " files");
        int index = -1;
        for (size_t i = 0; i < m_scene.files.size(); ++i)
            if (m_scene.files[i].canonical_path == canonical) index = static_cast<int>(i);
        if (index < 0) {
            // Read once: the dialect pre-scan kept the text.
            std::string why;
            if (!cached_text(resolved, canonical, &why))
                fail(f, pt, read_failure("cannot read ray file", resolved, why));
            const FileBytes text = std::move(m_texts[canonical]);
            m_texts.erase(canonical);
            index = static_cast<int>(m_scene.files.size());
            m_scene.files.emplace_back();
            m_scene.files.back().canonical_path = canonical;  // reserve the identity
            m_include_locs.push_back(f.lex.loc(d));
            const std::string sub_dir = fs::path(resolved).parent_path().string();
            parse_file(text_of(text), resolved, canonical, sub_dir.empty() ? "." : sub_dir, index);
            m_include_locs.pop_back();
        }
        f.desc.ray_files.push_back(index);
    }

    void key_file(FileState& f, const Token& d) override {
        definition(f, d);
        const Token pt = f.lex.peek();
        const std::string path = word(f, d, "a .key file name");
        count_item(f, d, kKeyFiles);
        const std::string resolved = resolve(f, pt, path, "key file");
        std::string text, why;
        if (!read_file(resolved, &text, &why))
            fail(f, pt, read_failure("cannot read key file", resolved, why));
        m_include_locs.push_back(f.lex.loc(d));
        f.key_files.push_back(parse_key_file(text, resolved));
        f.key_files.back().named = path;
        f.desc.key_files.push_back(resolved);
        m_include_locs.pop_back();
    }

    // ---- scene graph ---------------------------------------------------------------------
    void check_depth(FileState& f, const Token& d) {
        if (f.stack.size() > static_cast<size_t>(kMaxGroupDepth))
            fail(f, d,
                 std::string(d.text) + " nests groups deeper than " +
                     std::to_string(kMaxGroupDepth) + " levels");
    }

    void group_begin(FileState& f, const Token& d) {
        graph(f);
        check_depth(f, d);
        GroupDesc g;
        g.loc = f.lex.loc(d);
        Mat4 m(1.0);
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) m[c][r] = real(f, d, 16);  // rows in the file
        check_matrix(m, g.loc, "group matrix");
        g.matrix = m;
        GroupDesc* parent = f.stack.back();
        parent->groups.push_back(std::move(g));
        f.stack.push_back(&parent->groups.back());
        f.stack_is_joint.push_back(0);
    }

    void joint_begin(FileState& f, const Token& d) {
        graph(f);
        check_depth(f, d);
        GroupDesc g;
        g.loc = f.lex.loc(d);
        const Token nt = f.lex.peek();
        g.joint = word(f, d, "a joint name", true);
        // Spec §4.4, §14.2: the DOF of that name in the file's key files, key 0 as read.
        if (f.key_files.empty()) {
            if (!f.warned_joint_identity)
                warn(g.loc, "joint-no-key", "no #key_file: joints use the identity");
            f.warned_joint_identity = true;
        } else {
            g.track = bind_dof(f, nt, g.joint);
            g.matrix = m_scene.tracks[static_cast<size_t>(g.track)].keys[0];
        }
        GroupDesc* parent = f.stack.back();
        parent->groups.push_back(std::move(g));
        f.stack.push_back(&parent->groups.back());
        f.stack_is_joint.push_back(1);
    }

    void group_end(FileState& f, const Token& d) { end_group(f, d, false); }
    void joint_end(FileState& f, const Token& d) { end_group(f, d, true); }

    void end_group(FileState& f, const Token& d, bool joint) {
        graph(f);
        if (f.stack.size() <= 1 || (f.stack_is_joint.back() != 0) != joint) {
            if (f.stack.size() > 1)
                fail(f, d,
                     std::string(d.text) + " does not match " +
                         (f.stack_is_joint.back() ? "#joint_begin" : "#group_begin") + " at " +
                         f.stack.back()->loc.str());
            fail(f, d,
                 std::string(d.text) + " without " + (joint ? "#joint_begin" : "#group_begin"));
        }
        f.stack.pop_back();
        f.stack_is_joint.pop_back();
    }

    void instance(FileState& f, const Token& d) {
        graph(f);
        SourceLoc loc;
        const int i = integer(f, d, "ray file index", &loc);
        const int n = static_cast<int>(f.desc.ray_files.size());
        if (i < 0 || i >= n)
            fail(loc, "ray file index " + std::to_string(i) + " out of range [0," +
                          std::to_string(n) + ")");
        f.stack.back()->instances.push_back({f.lex.loc(d), i});
    }

    int material_index(FileState& f, const Token& d) override {
        SourceLoc loc;
        const int m = integer(f, d, "material index", &loc);
        const int n = static_cast<int>(f.defs().materials.size());
        const bool v0_default = (m == -1 && m_dialect == Dialect::V0);
        if (!v0_default && (m < 0 || m >= n)) {
            std::string msg = "material index " + std::to_string(m) + " out of range [" +
                              (m_dialect == Dialect::V0 ? "-1," : "0,") + std::to_string(n) + ")";
            if (m == -1) msg += " (-1 is V0 only; try --dialect v0)";
            fail(loc, msg);
        }
        return m;
    }

    void shape(FileState& f, const Token& d) {
        graph(f);
        ShapeDesc s;
        s.loc = f.lex.loc(d);
        s.material = material_index(f, d);
        if (primitive(f, d, s)) add_shape(f, d, f.stack.back()->shapes, std::move(s));
    }

    bool primitive(FileState& f, const Token& d, ShapeDesc& s) override {
        if (d.text == "#shape_triangle") {
            const TriangleDesc g = triangle_indices(f, d);
            s.geometry = g;
            if (!degenerate_triangle(f.defs(), g)) return true;
            skip_shape(s.loc, "degenerate triangle");
            return false;
        }
        // #shape_<kind> of an analytic kind: its numbers as the kind lists them (shapes.h).
        return visit_kind(*shape_directive_kind(d.text), [&](auto tag) {
            return analytic_shape<typename decltype(tag)::type>(f, d, s);
        });
    }

    // The numbers of one analytic shape: a negative size is an error at its number, a size of 0
    // leaves the shape out with a warning (spec §3.3).
    template <class T>
    bool analytic_shape(FileState& f, const Token& d, ShapeDesc& s) {
        using Desc = typename DescOf<T>::type;
        if constexpr (std::is_same_v<Desc, TriangleDesc>) {
            return false;  // primitive() reads triangles
        } else {
            struct Count {
                int n = 0;
                void point(Vec3&) { n += 3; }
                void size(double&, const char*) { ++n; }
            } count;
            Desc g;
            g.params(count);
            struct Read {
                Parser& p;
                FileState& f;
                const Token& d;
                int count;
                bool keep = true;
                void point(Vec3& v) { v = p.vec3(f, d, count); }
                void size(double& x, const char* what) {
                    const Token t = f.lex.peek();
                    x = p.real(f, d, count);
                    if (x < 0) p.fail(f, t, std::string("negative ") + what + " " + fmt(x));
                    keep = keep && x > 0;
                }
            } read{*this, f, d, count.n};
            g.params(read);
            if constexpr (requires { g.file_warning(); }) {
                auto [kind, message] = g.file_warning();
                if (!message.empty()) warn(s.loc, std::move(kind), std::move(message));
            }
            s.geometry = g;
            if (!read.keep) skip_shape(s.loc, T::kEmpty);
            return read.keep;
        }
    }

    // ---- whole tree ----------------------------------------------------------------------
    void finish() {
        check_placements();
        m_scene.dialect = m_dialect;
        if (!m_scene.camera && !m_scene.files.empty() && !v3_all_zero_camera)
            warn({intern_file_name(m_scene.files[0].path), 0, 0}, "no-camera",
                 "no #camera: using the default camera");
    }

    // Instancing multiplies: a file placed k times that instances another m times places it k*m
    // times. The compiler visits every placement, so their number is bounded here, where the
    // instance directives still have their locations. The recursion follows the include tree,
    // which is acyclic and at most kMaxIncludeDepth deep.
    void check_placements() {
        std::vector<long long> memo(m_scene.files.size(), -1);
        if (!m_scene.files.empty()) placements(0, memo);
    }

    long long placements(size_t fi, std::vector<long long>& memo) {
        if (memo[fi] >= 0) return memo[fi];
        const FileDesc& file = m_scene.files[fi];
        long long total = 1;  // the file itself
        std::vector<const GroupDesc*> todo = {&file.root};
        while (!todo.empty()) {
            const GroupDesc* g = todo.back();
            todo.pop_back();
            for (const InstanceDesc& in : g->instances) {
                const int sub = file.ray_files[static_cast<size_t>(in.ray_file)];
                total += placements(static_cast<size_t>(sub), memo);
                if (total > kMaxPlacements)
                    fail(in.loc, "instancing places more than " + std::to_string(kMaxPlacements) +
                                     " copies of files (nested instances multiply)");
            }
            for (const GroupDesc& c : g->groups) todo.push_back(&c);
            for (const CsgDesc& c : g->csgs)
                for (const GroupDesc& o : c.operands) todo.push_back(&o);
        }
        return memo[fi] = total;
    }

    struct Open {
        std::string canonical;
        std::string name;
    };

    std::vector<Open> m_open;                         // files being parsed below the top one
    std::map<std::string, DecodedTexture> m_decoded;  // by canonical path
    bool m_seen_background = false, m_seen_ambient = false;
};

}  // namespace
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
