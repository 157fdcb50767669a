// The V0/V1 grammar (spec §3, §4): a table of directives, each read into values for the
// SceneBuilder; and the argument readers and the directives V3 shares with it.
#include <array>
#include <variant>

#include "format/grammar.h"

namespace rt::parser_impl {

// ---- arguments ----------------------------------------------------------------------------------
SourceLoc Directive::arg_loc(const Token& bad) const {
    return (bad.kind == TokenKind::End || bad.kind == TokenKind::Directive) ? loc() : loc(bad);
}

double Directive::real(int count, SourceLoc* at) {
    *at = lex.loc(lex.peek());
    return real(count);
}

double Directive::real(int count) {
    const Token t = lex.next();
    double v = 0.0;
    bool non_finite = false;
    if (t.kind == TokenKind::Word && parse_real(t.text, &v, &non_finite)) return v;
    if (non_finite) fail(t, "non-finite number " + quote(t.text));
    b.fail(arg_loc(t), "expected " + std::to_string(count) + (count == 1 ? " number" : " numbers") +
                           " after " + std::string(name()) + ", got " + describe(t));
}

Vec3 Directive::vec3(int count) {
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = real(count);
    return v;
}

Vec3 Directive::colour(int count, std::string_view what) {
    Vec3 c;
    for (int i = 0; i < 3; ++i) {
        const Token t = lex.peek();
        c[i] = real(count);
        if (c[i] < 0) fail(t, "negative " + std::string(what) + " " + fmt(c[i]));
    }
    return c;
}

int Directive::integer(std::string_view what, SourceLoc* at) {
    const Token t = lex.next();
    int v = 0;
    bool out_of_range = false;
    if (at) *at = loc(t);
    if (t.kind == TokenKind::Word && parse_int(t.text, &v, &out_of_range)) return v;
    if (out_of_range) fail(t, "integer " + quote(t.text) + " out of range");
    b.fail(arg_loc(t), "expected an integer (" + std::string(what) + "), got " + describe(t));
}

std::string Directive::word(std::string_view what, bool ascii) {
    const Token t = lex.next();
    if (t.kind == TokenKind::Word) {
        // Spec §2: non-ASCII bytes only in comments, strings and paths.
        if (ascii)
            for (char c : t.text)
                if (static_cast<unsigned char>(c) >= 0x80)
                    fail(t, "non-ASCII byte in " + std::string(what) + " " + quote(t.text));
        return std::string(t.text);
    }
    b.fail(arg_loc(t), "expected " + std::string(what) + " after " + std::string(name()) +
                           ", got " + describe(t));
}

// ---- the directives both dialects share ---------------------------------------------------------
namespace shared {

CameraDesc camera(Directive& d) {
    CameraDesc c;
    c.loc = d.loc();
    c.position = d.vec3(10);
    c.direction = d.vec3(10);
    c.up = d.vec3(10);
    c.half_height_angle_rad = d.real(10);
    return c;
}

namespace {

// A directive that names a file: its path (`what`), counted as item `k`, to the builder's `use`.
void file_path(Directive& d, const char* what, CountKind k,
               void (SceneBuilder::*use)(const SourceLoc&, const SourceLoc&, const std::string&)) {
    const SourceLoc at = d.next_loc();
    const std::string path = d.word(what);
    d.b.count_item(d.loc(), k);
    (d.b.*use)(d.loc(), at, path);
}

}  // namespace

void texture(Directive& d) {
    file_path(d, "a texture file name", kTextures, &SceneBuilder::texture);
}

// Spec §3.1, §10: numbers up to the !…! string, 16 (V0) or 18 (V1, V3) of them, the last the
// texture index.
void material(Directive& d) {
    d.b.count_item(d.loc(), kMaterials);
    MaterialNumbers m;
    m.loc = d.loc();
    Token t = d.lex.next();
    Token last;
    for (; t.kind == TokenKind::Word; t = d.lex.next()) {
        double x = 0.0;
        bool non_finite = false;
        if (!parse_real(t.text, &x, &non_finite)) {
            if (non_finite) d.fail(t, "non-finite number " + quote(t.text));
            d.fail(t, "expected a number in #material, got " + quote(t.text));
        }
        if (m.n < 18) {
            m.v[static_cast<size_t>(m.n)] = x;
            m.at[static_cast<size_t>(m.n)] = d.loc(t);
        }
        ++m.n;
        last = t;
    }
    if (t.kind != TokenKind::String || (m.n != 16 && m.n != 18)) {
        if (t.kind != TokenKind::String && (m.n == 16 || m.n == 18))
            d.b.fail(d.arg_loc(t),
                     "#material needs its !…! string after the numbers, got " + describe(t));
        d.fail("#material needs 16 (V0) or 18 (V1) numbers before its !…! string, got " +
               std::to_string(m.n));
    }
    m.name = std::string(t.text.substr(1, t.text.size() - 2));
    MaterialDesc desc = d.b.material(m);
    bool out_of_range = false;
    if (!parse_int(last.text, &desc.texture, &out_of_range))
        d.fail(last, "expected an integer (texture index), got " + quote(last.text));
    d.b.add_material(std::move(desc), d.loc(last));
}

void vertex(Directive& d) {
    d.b.count_item(d.loc(), kVertices);
    VertexDesc v;
    v.position = d.vec3(8);
    v.normal = d.vec3(8);
    v.uv.x = d.real(8);
    v.uv.y = d.real(8);
    d.b.vertex(v);
}

void ray_file(Directive& d) {
    file_path(d, "a .ray file name", kRayFiles, &SceneBuilder::ray_file);
}

void key_file(Directive& d) {
    file_path(d, "a .key file name", kKeyFiles, &SceneBuilder::key_file);
}

int material_index(Directive& d) {
    SourceLoc at;
    const int m = d.integer("material index", &at);
    return d.b.material_index(at, m);
}

TriangleDesc triangle(Directive& d) {
    TriangleDesc g;
    for (int i = 0; i < 3; ++i) {
        SourceLoc at;
        g.v[i] = d.integer("vertex index", &at);
        d.b.vertex_index(at, g.v[i]);
    }
    return g;
}

namespace {

// The numbers of one analytic shape: a negative size is an error at its number, a size of 0
// leaves the shape out with a warning (spec §3.3).
template <class T>
void analytic_shape(Directive& d, ShapeDesc&& s) {
    using Desc = typename DescOf<T>::type;
    struct Count {
        int n = 0;
        void point(Vec3&) { n += 3; }
        void size(double&, const char*) { ++n; }
    } count;
    Desc g;
    g.params(count);
    struct Read {
        Directive& d;
        int count;
        bool keep = true;
        void point(Vec3& v) { v = d.vec3(count); }
        void size(double& x, const char* what) {
            const Token t = d.lex.peek();
            x = d.real(count);
            if (x < 0) d.fail(t, std::string("negative ") + what + " " + fmt(x));
            keep = keep && x > 0;
        }
    } read{d, count.n};
    g.params(read);
    if constexpr (requires { g.file_warning(); }) {
        auto [kind, message] = g.file_warning();
        if (!message.empty()) d.b.warn(s.loc, std::move(kind), std::move(message));
    }
    s.geometry = g;
    d.b.shape(std::move(s), read.keep ? nullptr : T::kEmpty);
}

}  // namespace

void shape(Directive& d) {
    ShapeDesc s;
    s.loc = d.loc();
    s.material = material_index(d);
    if (d.name() == "#shape_triangle") {  // the mesh directive first: no look-up of the kind
        s.geometry = triangle(d);
        return d.b.shape(std::move(s));
    }
    visit_kind(*shape_directive_kind(d.name()), [&](auto tag) {
        using T = typename decltype(tag)::type;
        if constexpr (!std::is_same_v<typename DescOf<T>::type, TriangleDesc>)
            analytic_shape<T>(d, std::move(s));  // (a triangle is read above)
    });
}

void spot(Directive& d, LightDesc& l, int count) {
    SourceLoc cutoff_at, dropoff_at;
    l.cutoff_rad = d.real(count, &cutoff_at);
    l.spot_exponent = d.real(count, &dropoff_at);
    d.b.spot(l, cutoff_at, dropoff_at);
}

}  // namespace shared

// ---- V0/V1 --------------------------------------------------------------------------------------
namespace v1 {
namespace {

void definition(Directive& d) { d.b.place(d.loc(), d.name(), SceneBuilder::Definition); }

template <CountKind K>
void count(Directive& d) {
    definition(d);
    SourceLoc at;
    const int n = d.integer("count", &at);
    // No more than the rest of the text can hold (a #vertex takes >= 24 bytes).
    d.b.declare_count(d.loc(), K, n, at, d.lex.remaining() / 24);
}

void camera(Directive& d) {
    definition(d);
    d.b.camera(shared::camera(d));
}

void global_colour(Directive& d) {
    definition(d);
    const bool background = d.name() == "#background";
    // Included files: syntax only (any three numbers).
    const Vec3 c =
        d.top ? d.colour(3, background ? "background colour" : "ambient colour") : d.vec3(3);
    d.b.global_colour(background, d.loc(), c);
}

void light(Directive& d) {
    definition(d);
    LightDesc l;
    l.loc = d.loc();
    if (d.name() == "#light_dir") {
        l.kind = LightKind::Directional;
        l.set_colour(d.colour(6, "light colour"));
        l.direction = d.vec3(6);
        if (glm::length(l.direction) == 0.0) d.fail("light direction is zero");
    } else {
        const bool spot = d.name() == "#light_spot";
        const int count = spot ? 14 : 9;
        l.kind = spot ? LightKind::Spot : LightKind::Point;
        l.set_colour(d.vec3(count));  // spec §3.1: point and spot colours need only be finite
        l.position = d.vec3(count);
        if (spot) l.direction = d.vec3(count);
        l.constant_atten = d.real(count);
        l.linear_atten = d.real(count);
        l.quadratic_atten = d.real(count);
        if (spot) shared::spot(d, l, count);
    }
    d.b.attenuation(l);
    d.b.light(l);
}

// A definition both dialects read alike, after V0/V1's rule that none follows the scene graph.
template <void (*Read)(Directive&)>
void defined(Directive& d) {
    definition(d);
    Read(d);
}

void group_begin(Directive& d) {
    SceneBuilder::Construct c{SceneBuilder::Construct::Group, d.loc(), d.name()};
    for (int r = 0; r < 4; ++r)
        for (int col = 0; col < 4; ++col) c.matrix[col][r] = d.real(16);  // rows in the file
    d.b.open(c);
}

void joint_begin(Directive& d) {
    SceneBuilder::Construct c{SceneBuilder::Construct::Joint, d.loc(), d.name()};
    c.name_loc = d.next_loc();
    c.name = d.word("a joint name", true);
    d.b.open(c);
}

void group_end(Directive& d) { d.b.close(d.loc(), d.name()); }

void instance(Directive& d) {
    SourceLoc at;
    const int i = d.integer("ray file index", &at);
    d.b.instance(d.loc(), at, i);
}

// The V0/V1 directives, the mesh directives first; then #shape_<kind> of every kind that is not
// V3 only (shapes.h).
struct Entry {
    std::string_view name;
    void (*read)(Directive&);
};
constexpr std::array<Entry, 23> kDirectives = {{
    {"#vertex", defined<shared::vertex>},
    {"#shape_triangle", shared::shape},
    {"#camera", camera},
    {"#background", global_colour},
    {"#ambient", global_colour},
    {"#light_num", count<kLights>},
    {"#light_dir", light},
    {"#light_point", light},
    {"#light_spot", light},
    {"#texture_num", count<kTextures>},
    {"#texture", defined<shared::texture>},
    {"#material_num", count<kMaterials>},
    {"#material", defined<shared::material>},
    {"#vertex_num", count<kVertices>},
    {"#ray_file_num", count<kRayFiles>},
    {"#ray_file", defined<shared::ray_file>},
    {"#key_file_num", count<kKeyFiles>},
    {"#key_file", defined<shared::key_file>},
    {"#group_begin", group_begin},
    {"#group_end", group_end},
    {"#joint_begin", joint_begin},
    {"#joint_end", group_end},
    {"#ray_file_instance", instance},
}};

}  // namespace
}  // namespace v1

void read_v1(Directive& d) {
    using namespace v1;
    for (const Entry& e : kDirectives)
        if (e.name == d.name()) return e.read(d);
    const std::optional<ShapeKind> kind = shape_directive_kind(d.name());
    if (kind &&
        !visit_kind(*kind, [](auto tag) { return kV3OnlyShape<typename decltype(tag)::type>; }))
        return shared::shape(d);
    d.fail("unknown directive " + quote(d.name()));
}

}  // namespace rt::parser_impl
