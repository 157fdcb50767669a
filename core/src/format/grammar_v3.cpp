// The V3 grammar (spec §13): a table of directives, each with the part of the file it belongs
// to (global, local, shapes) and what reads it into values for the SceneBuilder: the camera, the
// three-colour and sphere lights, #shader, the definitions V3 shares with V1 (grammar_v1.cpp),
// and the shapes part: lists, #static_affine and #dynamic_affine, #shape_triangles, the V3-only
// shape kinds and the CSG nodes. The shapes part is read with an explicit stack of open
// constructs (V3Frame), so its nesting costs no recursion; each finished construct is handed to
// the one below it (SceneBuilder::v3_deliver).
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <variant>

#include "format/grammar.h"

namespace rt::parser_impl {

namespace v3 {
namespace {

// ---- the directives -----------------------------------------------------------------------------
// Spec §13.3: the last #camera wins (SceneBuilder::camera). Included files: any 10 reals.
void camera(Directive& d) { d.b.camera(d.f, shared::camera(d)); }

// Spec §13.3: ambient, diffuse and specular colours, then the V1 arguments; #light_sphere:
// centre, radius, attenuation.
void light(Directive& d) {
    const std::string_view n = d.name();
    LightDesc l;
    l.loc = d.loc();
    const int count = n == "#light_dir"     ? 12
                      : n == "#light_point" ? 15
                      : n == "#light_spot"  ? 20
                                            : 16;
    const bool dir = n == "#light_dir";
    // Directional colours must be >= 0 (as V1); the others need only be finite.
    auto rgb = [&]() { return dir ? d.colour(count, "light colour") : d.vec3(count); };
    l.ambient = rgb();
    l.diffuse = rgb();
    l.specular = rgb();
    if (dir) {
        l.kind = LightKind::Directional;
        l.direction = d.vec3(count);
        if (glm::length(l.direction) == 0.0) d.fail("light direction is zero");
    } else {
        l.kind = n == "#light_spot"     ? LightKind::Spot
                 : n == "#light_sphere" ? LightKind::Sphere
                                        : LightKind::Point;
        l.position = d.vec3(count);
        if (l.kind == LightKind::Spot) l.direction = d.vec3(count);
        if (l.kind == LightKind::Sphere) {
            const Token rt = d.f.lex.peek();
            l.radius = d.real(count);
            if (l.radius < 0)
                d.fail(rt, "negative sphere light radius " + SceneBuilder::fmt(l.radius));
            if (l.radius == 0) {
                d.b.warn(l.loc, "light-sphere-zero",
                         "#light_sphere of radius 0 acts as a point light");
                l.kind = LightKind::Point;
            }
        }
        l.constant_atten = d.real(count);
        l.linear_atten = d.real(count);
        l.quadratic_atten = d.real(count);
        d.b.attenuation(l);
    }
    if (l.kind == LightKind::Spot) {
        const Token cut_tok = d.f.lex.peek();
        l.cutoff_rad = d.real(count);
        const Token dor_tok = d.f.lex.peek();
        l.spot_exponent = d.real(count);  // p = dropoff
        if (glm::length(l.direction) == 0.0) d.fail("spot light direction is zero");
        if (l.cutoff_rad < 0)
            d.fail(cut_tok, "negative spot cutoff " + SceneBuilder::fmt(l.cutoff_rad));
        if (l.spot_exponent < 0)
            d.fail(dor_tok, "negative spot drop-off " + SceneBuilder::fmt(l.spot_exponent));
        d.b.spot_cutoff(l);
    }
    d.b.light(d.f, l);
}

// Spec §13.3: recorded (the last one wins), never opened. Included files: ignored.
void shader(Directive& d) {
    std::string vs = d.word("a vertex shader path");
    std::string fs = d.word("a fragment shader path");
    d.b.shader(d.f, std::move(vs), std::move(fs));
}

void list_begin(Directive& d) { d.b.v3_open(d.f, d.loc(), d.name(), V3Frame::List); }

void list_end(Directive& d) {
    FileState& f = d.f;
    const V3Frame& top = f.v3.back();
    if (top.kind == V3Frame::Root) d.fail("#shape_list_end without #shape_list_begin");
    if (top.kind == V3Frame::Affine || top.kind == V3Frame::Difference)
        d.fail(SceneBuilder::v3_open_message(top, "#shape_list_end"));
    d.b.v3_close(f);
}

// Spec §13.6: 16 reals, column by column; then one shape.
void static_affine(Directive& d) {
    Mat4 m(1.0);
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = d.real(16);  // GLM's m[column][row]
    d.b.check_matrix(m, d.loc(), "#static_affine matrix");
    d.b.v3_open(d.f, d.loc(), d.name(), V3Frame::Affine).group.matrix = m;
}

// Spec §14.2: the DOF NAME of this file's key files; its matrix is key 0 as read (§14.7).
void dynamic_affine(Directive& d) {
    const SourceLoc at = d.next_loc();
    const std::string name = d.word("a DOF name", true);
    const int track = d.b.dynamic_dof(d.f, d.loc(), at, name);
    GroupDesc& g = d.b.v3_open(d.f, d.loc(), d.name(), V3Frame::Affine).group;
    g.joint = name;
    g.track = track;
    if (track >= 0) g.matrix = d.b.scene().tracks[static_cast<size_t>(track)].keys[0];
}

void triangles(Directive& d) {
    const int m = shared::material_index(d);
    d.b.v3_open(d.f, d.loc(), d.name(), V3Frame::TrianglesHead).material = m;
}

// Spec §13.5: v1 v2 v3 of this file, with the list's material.
void triangle(Directive& d) {
    if (d.f.v3.back().kind != V3Frame::Triangles)
        d.fail("#shape_triangle outside #shape_triangles");
    ShapeDesc s;
    s.loc = d.loc();
    s.material = d.f.v3.back().material;
    s.geometry = shared::triangle(d);
    if (d.b.keep_shape(d.f, s)) d.b.add_shape(d.f, d.f.v3.back().group.shapes, std::move(s));
}

void csg(Directive& d) {
    const std::string_view n = d.name();
    if (n == "#shape_difference") {
        d.b.v3_open(d.f, d.loc(), d.name(), V3Frame::Difference).csg.op = CsgOp::Difference;
        return;
    }
    d.b.v3_open(d.f, d.loc(), d.name(), V3Frame::CsgHead).csg.op =
        n == "#shape_union" ? CsgOp::Union : CsgOp::Intersection;
}

void instance(Directive& d) {
    SourceLoc at;
    const int i = d.integer("ray file index", &at);
    d.b.instance_index(d.f, at, i);
    V3Node node;
    node.kind = V3Node::Instance;
    node.loc = d.loc();
    node.instance = {node.loc, i};
    d.b.v3_deliver(d.f, std::move(node));
}

// #shape_<kind> of an analytic kind.
void shape(Directive& d) {
    V3Node node;
    node.loc = d.loc();
    node.shape.loc = node.loc;
    node.shape.material = shared::material_index(d);
    node.kind = shared::shape(d, node.shape) ? V3Node::Shape : V3Node::Empty;
    d.b.v3_deliver(d.f, std::move(node));
}

enum Part { kGlobalPart, kLocalPart, kShapesPart };

struct Entry {
    std::string_view name;
    Part part;
    void (*read)(Directive&);
};
// Then #shape_<kind> of every analytic kind, in the shapes part.
constexpr std::array<Entry, 21> kDirectives = {{
    {"#camera", kGlobalPart, camera},
    {"#light_dir", kGlobalPart, light},
    {"#light_point", kGlobalPart, light},
    {"#light_spot", kGlobalPart, light},
    {"#light_sphere", kGlobalPart, light},
    {"#shader", kGlobalPart, shader},
    {"#texture", kLocalPart, shared::texture},
    {"#material", kLocalPart, shared::material},
    {"#vertex", kLocalPart, shared::vertex},
    {"#ray_file", kLocalPart, shared::ray_file},
    {"#key_file", kLocalPart, shared::key_file},
    {"#shape_triangles", kShapesPart, triangles},
    {"#shape_triangle", kShapesPart, triangle},
    {"#shape_list_begin", kShapesPart, list_begin},
    {"#shape_list_end", kShapesPart, list_end},
    {"#static_affine", kShapesPart, static_affine},
    {"#dynamic_affine", kShapesPart, dynamic_affine},
    {"#shape_union", kShapesPart, csg},
    {"#shape_intersection", kShapesPart, csg},
    {"#shape_difference", kShapesPart, csg},
    {"#ray_file_instance", kShapesPart, instance},
}};
constexpr Entry kAnalyticShape = {"#shape_<kind>", kShapesPart, shape};

// Spec §13.1: global, then local, then shapes.
void order(Directive& d, Part part) {
    static constexpr std::array<const char*, 3> kPart = {"global", "local", "shapes"};
    FileState& f = d.f;
    if (part < f.v3_part) {
        const SourceLoc& start = f.v3_part == 1 ? f.v3_local_start : f.v3_shapes_start;
        d.fail(quote(d.name()) + " after the " + kPart[static_cast<size_t>(f.v3_part)] +
               " part started at " + start.str() + " (V3 order: global, local, shapes)");
    }
    if (part == kLocalPart && f.v3_part < 1) f.v3_local_start = d.loc();
    if (part == kShapesPart && f.v3_part < 2) f.v3_shapes_start = d.loc();
    f.v3_part = std::max<int>(f.v3_part, part);
}

// Directives that close a list or must open one (spec §13.5): the head of #shape_triangles or
// a CSG node takes only #shape_list_begin, the list of #shape_triangles only triangles.
// True when `d` was the list's opening.
bool list_rules(Directive& d) {
    V3Frame& top = d.f.v3.back();
    const std::string_view n = d.name();
    if (top.kind == V3Frame::TrianglesHead || top.kind == V3Frame::CsgHead) {
        if (n != "#shape_list_begin") d.fail(SceneBuilder::v3_open_message(top, quote(n)));
        top.kind = top.kind == V3Frame::TrianglesHead ? V3Frame::Triangles : V3Frame::CsgList;
        return true;
    }
    if (top.kind == V3Frame::Triangles && n != "#shape_triangle" && n != "#shape_list_end")
        d.fail(quote(n) + " inside the list of #shape_triangles at " + top.loc.str() +
               " (only #shape_triangle may be there)");
    return false;
}

}  // namespace
}  // namespace v3

void V3Grammar::directive(FileState& f, const Token& t) {
    using namespace v3;
    Directive d{m_b, f, t};
    const Entry* entry = nullptr;
    for (const Entry& e : kDirectives)
        if (e.name == t.text) entry = &e;
    if (!entry) {
        const std::optional<ShapeKind> kind = shape_directive_kind(t.text);
        if (kind && *kind != ShapeKind::Triangle) entry = &kAnalyticShape;
    }
    if (!entry) {
        // The pre-scan refuses other-dialect constructs first; kept as a safeguard.
        if (is_v01_directive(t.text))
            d.fail(quote(t.text) + " is V0/V1 syntax; " +
                   (m_b.v3_marker().empty() ? "the tree was forced to V3 by --dialect v3"
                                            : "this tree is V3 (V3 " + m_b.v3_marker() + ")"));
        d.fail("unknown directive " + quote(t.text));
    }
    order(d, entry->part);
    if (entry->part == kShapesPart && list_rules(d)) return;
    entry->read(d);
}

void V3Grammar::end_of_file(FileState& f, const SourceLoc& eof) { m_b.v3_end_of_file(f, eof); }

}  // namespace rt::parser_impl
