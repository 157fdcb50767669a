// The V3 grammar (spec §13): a table of directives, each with the part of the file it belongs
// to (global, local, shapes) and what reads it into values for the SceneBuilder: the camera, the
// three-colour and sphere lights, #shader, the definitions V3 shares with V1 (grammar_v1.cpp),
// and the shapes part: lists, #static_affine and #dynamic_affine, #shape_triangles, the V3-only
// shape kinds and the CSG nodes. The shapes part is read with an explicit stack of open
// constructs (V3Frame), so its nesting costs no recursion; each finished construct is handed to
// the one below it by the builder.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <variant>

#include "format/grammar.h"

namespace rt::parser_impl {

namespace v3 {
namespace {

using Construct = SceneBuilder::Construct;

// ---- the directives -----------------------------------------------------------------------------
// Spec §13.3: the last #camera wins (SceneBuilder::camera). Included files: any 10 reals.
void camera(Directive& d) { d.b.camera(shared::camera(d)); }

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
            const Token rt = d.lex.peek();
            l.radius = d.real(count);
            if (l.radius < 0) d.fail(rt, "negative sphere light radius " + fmt(l.radius));
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
    if (l.kind == LightKind::Spot) shared::spot(d, l, count);
    d.b.light(l);
}

// Spec §13.3: recorded (the last one wins), never opened. Included files: ignored.
void shader(Directive& d) {
    std::string vs = d.word("a vertex shader path");
    std::string fs = d.word("a fragment shader path");
    d.b.shader(std::move(vs), std::move(fs));
}

void list_begin(Directive& d) { d.b.open({Construct::List, d.loc(), d.name()}); }

void list_end(Directive& d) { d.b.close(d.loc(), d.name()); }

// Spec §13.6: 16 reals, column by column; then one shape.
void static_affine(Directive& d) {
    Construct c{Construct::Affine, d.loc(), d.name()};
    for (int i = 0; i < 16; ++i) c.matrix[i / 4][i % 4] = d.real(16);  // GLM's m[column][row]
    d.b.open(c);
}

// Spec §14.2: the DOF NAME of this file's key files; its matrix is key 0 as read (§14.7).
void dynamic_affine(Directive& d) {
    Construct c{Construct::Dynamic, d.loc(), d.name()};
    c.name_loc = d.next_loc();
    c.name = d.word("a DOF name", true);
    d.b.open(c);
}

void triangles(Directive& d) {
    Construct c{Construct::Triangles, d.loc(), d.name()};
    c.material = shared::material_index(d);
    d.b.open(c);
}

// Spec §13.5: v1 v2 v3 of this file, with the list's material.
void triangle(Directive& d) {
    ShapeDesc s;
    s.loc = d.loc();
    s.geometry = shared::triangle(d);
    d.b.shape(std::move(s));
}

void csg(Directive& d) {
    const std::string_view n = d.name();
    Construct c{n == "#shape_difference" ? Construct::Difference : Construct::Csg, d.loc(), n};
    c.op = n == "#shape_difference" ? CsgOp::Difference
           : n == "#shape_union"    ? CsgOp::Union
                                    : CsgOp::Intersection;
    d.b.open(c);
}

void instance(Directive& d) {
    SourceLoc at;
    const int i = d.integer("ray file index", &at);
    d.b.instance(d.loc(), at, i);
}

using Part = SceneBuilder::Part;

struct Entry {
    std::string_view name;
    Part part;
    void (*read)(Directive&);
};
// Then #shape_<kind> of every analytic kind, in the shapes part.
constexpr std::array<Entry, 21> kDirectives = {{
    {"#camera", Part::Global, camera},
    {"#light_dir", Part::Global, light},
    {"#light_point", Part::Global, light},
    {"#light_spot", Part::Global, light},
    {"#light_sphere", Part::Global, light},
    {"#shader", Part::Global, shader},
    {"#texture", Part::Local, shared::texture},
    {"#material", Part::Local, shared::material},
    {"#vertex", Part::Local, shared::vertex},
    {"#ray_file", Part::Local, shared::ray_file},
    {"#key_file", Part::Local, shared::key_file},
    {"#shape_triangles", Part::Shapes, triangles},
    {"#shape_triangle", Part::Shapes, triangle},
    {"#shape_list_begin", Part::Shapes, list_begin},
    {"#shape_list_end", Part::Shapes, list_end},
    {"#static_affine", Part::Shapes, static_affine},
    {"#dynamic_affine", Part::Shapes, dynamic_affine},
    {"#shape_union", Part::Shapes, csg},
    {"#shape_intersection", Part::Shapes, csg},
    {"#shape_difference", Part::Shapes, csg},
    {"#ray_file_instance", Part::Shapes, instance},
}};
constexpr Entry kAnalyticShape = {"#shape_<kind>", Part::Shapes, shared::shape};

}  // namespace
}  // namespace v3

void read_v3(Directive& d, const std::string& marker) {
    using namespace v3;
    const std::string_view name = d.name();
    const Entry* entry = nullptr;
    for (const Entry& e : kDirectives)
        if (e.name == name) entry = &e;
    if (!entry) {
        const std::optional<ShapeKind> kind = shape_directive_kind(name);
        if (kind && *kind != ShapeKind::Triangle) entry = &kAnalyticShape;
    }
    if (!entry) {
        // The pre-scan refuses other-dialect constructs first; kept as a safeguard.
        if (is_v01_directive(name))
            d.fail(quote(name) + " is V0/V1 syntax; " +
                   (marker.empty() ? "the tree was forced to V3 by --dialect v3"
                                   : "this tree is V3 (V3 " + marker + ")"));
        d.fail("unknown directive " + quote(name));
    }
    // The directive that opens the list its construct expects is read.
    if (!d.b.place(d.loc(), name, entry->part)) entry->read(d);
}

}  // namespace rt::parser_impl
