// The V3 directives (spec §13): the three-part file order, the camera, the three-colour and
// sphere lights, #shader, and the shapes part: lists, #static_affine and #dynamic_affine,
// #shape_triangles, the V3-only shape kinds and the CSG nodes. The shapes part is read with an
// explicit stack of open constructs (V3Frame), so its nesting costs no recursion; each finished
// construct is handed to the one below it (v3_deliver). The definitions V3 shares with V1 are
// parser.cpp's.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <variant>

#include "format/parser_impl.h"

namespace rt::parser_impl {

namespace {

constexpr std::array<std::string_view, 6> kGlobal = {"#camera",     "#light_dir",    "#light_point",
                                                     "#light_spot", "#light_sphere", "#shader"};
constexpr std::array<std::string_view, 5> kLocal = {"#texture", "#material", "#vertex", "#ray_file",
                                                    "#key_file"};
// The shapes part: these and #shape_<kind> of every analytic kind (is_analytic_shape).
constexpr std::array<std::string_view, 10> kShapes = {
    "#shape_triangles",  "#shape_triangle",   "#shape_list_begin", "#shape_list_end",
    "#static_affine",    "#dynamic_affine",   "#shape_union",      "#shape_intersection",
    "#shape_difference", "#ray_file_instance"};

template <size_t N>
bool in(const std::array<std::string_view, N>& names, std::string_view n) {
    return std::find(names.begin(), names.end(), n) != names.end();
}

// #shape_<kind> of the analytic kinds (every kind but the triangle): the directives
// primitive() reads.
bool is_analytic_shape(std::string_view n) {
    const std::optional<ShapeKind> kind = shape_directive_kind(n);
    return kind && *kind != ShapeKind::Triangle;
}

// The part of a V3 file a directive belongs to (spec §13.1): 0 global, 1 local, 2 shapes; -1
// when it is not a V3 directive.
int part_of(std::string_view n) {
    if (in(kGlobal, n)) return 0;
    if (in(kLocal, n)) return 1;
    if (in(kShapes, n) || is_analytic_shape(n)) return 2;
    return -1;
}

// What an unfinished construct still needs, for the error at `what` (a directive or the end of
// the file).
std::string open_message(const V3Frame& fr, const std::string& what) {
    const std::string at = fr.name + " at " + fr.loc.str();
    switch (fr.kind) {
        case V3Frame::Affine:
            return at + " has no shape before " + what;
        case V3Frame::Difference:
            return at + " needs two shapes, got " + std::to_string(fr.csg.operands.size()) +
                   " before " + what;
        case V3Frame::CsgHead:
        case V3Frame::TrianglesHead:
            return at + " expects #shape_list_begin, got " + what;
        case V3Frame::List:
            return at + " is never closed";
        default:
            break;
    }
    return "the #shape_list_begin of " + at + " is never closed";
}

// Adds a finished shape to a list.
void add(GroupDesc& g, V3Node& node) {
    switch (node.kind) {
        case V3Node::Shape:
            g.shapes.push_back(std::move(node.shape));
            break;
        case V3Node::Instance:
            g.instances.push_back(node.instance);
            break;
        case V3Node::Group:
        case V3Node::List:
            g.groups.push_back(std::move(node.group));
            break;
        case V3Node::Csg:
            g.csgs.push_back(std::move(node.csg));
            break;
        case V3Node::Empty:
            break;
    }
}

}  // namespace

void ParserV3::v3_directive(FileState& f, const Token& d) {
    const std::string_view n = d.text;
    const int part = part_of(n);
    if (part < 0) {
        // The pre-scan refuses other-dialect constructs first; kept as a safeguard.
        if (is_v01_directive(n))
            fail(f, d,
                 quote(n) + " is V0/V1 syntax; " +
                     (m_v3_marker.empty() ? "the tree was forced to V3 by --dialect v3"
                                          : "this tree is V3 (V3 " + m_v3_marker + ")"));
        fail(f, d, "unknown directive " + quote(n));
    }
    v3_order(f, d, part);
    if (n == "#camera") return v3_camera(f, d);
    if (n == "#shader") return v3_shader(f, d);
    if (part == 0) return v3_light(f, d);
    if (n == "#texture") return texture(f, d);
    if (n == "#material") return material(f, d);
    if (n == "#vertex") return vertex(f, d);
    if (n == "#ray_file") return ray_file(f, d);
    if (n == "#key_file") return key_file(f, d);
    v3_shape(f, d);
}

// Spec §13.1: global, then local, then shapes.
void ParserV3::v3_order(FileState& f, const Token& d, int part) {
    static constexpr std::array<const char*, 3> kPart = {"global", "local", "shapes"};
    if (part < f.v3_part) {
        const SourceLoc& start = f.v3_part == 1 ? f.v3_local_start : f.v3_shapes_start;
        fail(f, d,
             quote(d.text) + " after the " + kPart[static_cast<size_t>(f.v3_part)] +
                 " part started at " + start.str() + " (V3 order: global, local, shapes)");
    }
    if (part == 1 && f.v3_part < 1) f.v3_local_start = f.lex.loc(d);
    if (part == 2 && f.v3_part < 2) f.v3_shapes_start = f.lex.loc(d);
    f.v3_part = std::max(f.v3_part, part);
}

// Spec §13.3: the last #camera wins; an all-zero one (the course's sub-file dummy) is the
// default camera. Included files: any 10 reals, ignored.
void ParserV3::v3_camera(FileState& f, const Token& d) {
    const CameraDesc c = read_camera(f, d);
    if (!f.top) return;
    if (m_camera_loc.file)
        warn(
            c.loc, "camera-repeat",
            "second #camera: the last one wins (the earlier one is at " + m_camera_loc.str() + ")");
    m_camera_loc = c.loc;
    if (dummy_camera(c)) {
        m_scene.camera.reset();
        return;
    }
    validate_camera(f, d, c);
    m_scene.camera = c;
}

// Spec §13.3: ambient, diffuse and specular colours, then the V1 arguments; #light_sphere:
// centre, radius, attenuation.
void ParserV3::v3_light(FileState& f, const Token& d) {
    const std::string_view n = d.text;
    LightDesc l;
    l.loc = f.lex.loc(d);
    const int count = n == "#light_dir"     ? 12
                      : n == "#light_point" ? 15
                      : n == "#light_spot"  ? 20
                                            : 16;
    const bool dir = n == "#light_dir";
    // Directional colours must be >= 0 (as V1); the others need only be finite.
    auto rgb = [&]() { return dir ? colour(f, d, count, "light colour") : vec3(f, d, count); };
    l.ambient = rgb();
    l.diffuse = rgb();
    l.specular = rgb();
    if (dir) {
        l.kind = LightKind::Directional;
        l.direction = vec3(f, d, count);
        if (glm::length(l.direction) == 0.0) fail(f, d, "light direction is zero");
    } else {
        l.kind = n == "#light_spot"     ? LightKind::Spot
                 : n == "#light_sphere" ? LightKind::Sphere
                                        : LightKind::Point;
        l.position = vec3(f, d, count);
        if (l.kind == LightKind::Spot) l.direction = vec3(f, d, count);
        if (l.kind == LightKind::Sphere) {
            const Token rt = f.lex.peek();
            l.radius = real(f, d, count);
            if (l.radius < 0) fail(f, rt, "negative sphere light radius " + fmt(l.radius));
            if (l.radius == 0) {
                warn(l.loc, "light-sphere-zero", "#light_sphere of radius 0 acts as a point light");
                l.kind = LightKind::Point;
            }
        }
        l.constant_atten = real(f, d, count);
        l.linear_atten = real(f, d, count);
        l.quadratic_atten = real(f, d, count);
        if (l.constant_atten == 0.0 && l.linear_atten == 0.0 && l.quadratic_atten == 0.0)
            warn(l.loc, "light-zero-atten",
                 "attenuation coefficients are all zero: the light never contributes");
    }
    if (l.kind == LightKind::Spot) {
        const Token cut_tok = f.lex.peek();
        l.cutoff_rad = real(f, d, count);
        const Token dor_tok = f.lex.peek();
        l.spot_exponent = real(f, d, count);  // p = dropoff
        if (glm::length(l.direction) == 0.0) fail(f, d, "spot light direction is zero");
        if (l.cutoff_rad < 0) fail(f, cut_tok, "negative spot cutoff " + fmt(l.cutoff_rad));
        if (l.spot_exponent < 0) fail(f, dor_tok, "negative spot drop-off " + fmt(l.spot_exponent));
        if (l.cutoff_rad > kPi / 2)
            warn(l.loc, "spot-cutoff",
                 "spot cutoff " + fmt(l.cutoff_rad) +
                     " rad is more than pi/2: the light never cuts off");
    }
    if (!f.top) {
        if (!f.warned_included_light)
            warn(l.loc, "included-light", "lights in included files are ignored");
        f.warned_included_light = true;
        return;
    }
    m_scene.lights.push_back(l);
}

// Spec §13.3: recorded (the last one wins), never opened. Included files: ignored.
void ParserV3::v3_shader(FileState& f, const Token& d) {
    std::string vs = word(f, d, "a vertex shader path");
    std::string fs = word(f, d, "a fragment shader path");
    if (!f.top) return;
    m_scene.shader_vertex = std::move(vs);
    m_scene.shader_fragment = std::move(fs);
}

// Directives that close a list or must open one (spec §13.5); true when `d` was one of them.
bool ParserV3::v3_list_directive(FileState& f, const Token& d) {
    V3Frame& top = f.v3.back();
    const std::string_view n = d.text;
    if (top.kind == V3Frame::TrianglesHead || top.kind == V3Frame::CsgHead) {
        if (n != "#shape_list_begin") fail(f, d, open_message(top, quote(n)));
        top.kind = top.kind == V3Frame::TrianglesHead ? V3Frame::Triangles : V3Frame::CsgList;
        return true;
    }
    if (top.kind == V3Frame::Triangles && n != "#shape_triangle" && n != "#shape_list_end")
        fail(f, d,
             quote(n) + " inside the list of #shape_triangles at " + top.loc.str() +
                 " (only #shape_triangle may be there)");
    if (n == "#shape_triangle") {
        if (top.kind != V3Frame::Triangles) fail(f, d, "#shape_triangle outside #shape_triangles");
        v3_triangle(f, d);
        return true;
    }
    if (n != "#shape_list_end") return false;
    if (top.kind == V3Frame::Root) fail(f, d, "#shape_list_end without #shape_list_begin");
    if (top.kind == V3Frame::Affine || top.kind == V3Frame::Difference)
        fail(f, d, open_message(top, "#shape_list_end"));
    V3Frame fr = std::move(f.v3.back());
    f.v3.pop_back();
    v3_deliver(f, v3_finish(f, fr));
    return true;
}

void ParserV3::v3_shape(FileState& f, const Token& d) {
    if (v3_list_directive(f, d)) return;
    const std::string_view n = d.text;
    if (n == "#shape_list_begin") return v3_push(f, d, V3Frame::List);
    if (n == "#static_affine") return v3_affine(f, d);
    if (n == "#dynamic_affine") return v3_dynamic(f, d);
    if (n == "#ray_file_instance") return v3_instance(f, d);
    if (n == "#shape_triangles") {
        const int m = material_index(f, d);
        v3_push(f, d, V3Frame::TrianglesHead);
        f.v3.back().material = m;
        return;
    }
    if (n == "#shape_union" || n == "#shape_intersection") {
        v3_push(f, d, V3Frame::CsgHead);
        f.v3.back().csg.op = n == "#shape_union" ? CsgOp::Union : CsgOp::Intersection;
        return;
    }
    if (n == "#shape_difference") {
        v3_push(f, d, V3Frame::Difference);
        f.v3.back().csg.op = CsgOp::Difference;
        return;
    }
    V3Node node;
    node.loc = f.lex.loc(d);
    node.shape.loc = node.loc;
    node.shape.material = material_index(f, d);
    const bool keep = primitive(f, d, node.shape);
    node.kind = keep ? V3Node::Shape : V3Node::Empty;
    v3_deliver(f, std::move(node));
}

// Opens a construct, within the nesting limits (no consumer recurses deeper than them).
void ParserV3::v3_push(FileState& f, const Token& d, V3Frame::Kind kind) {
    if (f.v3.size() > static_cast<size_t>(kMaxV3Depth))
        fail(f, d,
             quote(d.text) + " nests V3 shapes deeper than " + std::to_string(kMaxV3Depth) +
                 " levels");
    const bool csg = kind == V3Frame::CsgHead || kind == V3Frame::Difference;
    if (csg && f.v3_csg_depth >= kMaxCsgDepth)
        fail(f, d,
             quote(d.text) + " nests CSG nodes deeper than " + std::to_string(kMaxCsgDepth) +
                 " levels");
    if (csg) ++f.v3_csg_depth;
    V3Frame fr;
    fr.kind = kind;
    fr.loc = f.lex.loc(d);
    fr.name = std::string(d.text);
    fr.group.loc = fr.loc;
    fr.csg.loc = fr.loc;
    f.v3.push_back(std::move(fr));
}

// Hands a finished shape to the innermost open construct, closing every construct it completes
// (a transform after its one shape, a difference after its second).
void ParserV3::v3_deliver(FileState& f, V3Node node) {
    for (;;) {
        V3Frame& to = f.v3.back();
        v3_receive(f, to, node);
        const bool done = (to.kind == V3Frame::Affine && to.has_child) ||
                          (to.kind == V3Frame::Difference && to.csg.operands.size() == 2);
        if (!done) return;
        V3Frame fr = std::move(f.v3.back());
        f.v3.pop_back();
        node = v3_finish(f, fr);
    }
}

// The folding of scene_desc.h: a transform or CSG operand whose child is a #shape_list_begin
// list is that list.
void ParserV3::v3_receive(FileState&, V3Frame& to, V3Node& node) {
    if (to.kind == V3Frame::Affine) {
        to.has_child = true;
        if (node.kind != V3Node::List) return add(to.group, node);
        const Mat4 m = to.group.matrix;
        std::string joint = std::move(to.group.joint);
        const int track = to.group.track;
        const SourceLoc loc = to.group.loc;
        to.group = std::move(node.group);
        to.group.matrix = m;
        to.group.joint = std::move(joint);
        to.group.track = track;
        to.group.loc = loc;
        return;
    }
    if (to.kind == V3Frame::CsgList || to.kind == V3Frame::Difference) {
        GroupDesc operand;
        operand.loc = node.loc;
        if (node.kind == V3Node::List)
            operand = std::move(node.group);
        else
            add(operand, node);
        to.csg.operands.push_back(std::move(operand));
        return;
    }
    add(to.group, node);  // Root, List
}

V3Node ParserV3::v3_finish(FileState& f, V3Frame& fr) {
    V3Node node;
    node.loc = fr.loc;
    switch (fr.kind) {
        case V3Frame::List:
            node.kind = V3Node::List;
            node.group = std::move(fr.group);
            break;
        case V3Frame::CsgList:
        case V3Frame::Difference:
            if (fr.csg.operands.empty())
                warn(fr.loc, "csg-empty", fr.name + " with an empty list: the node is empty");
            --f.v3_csg_depth;
            node.kind = V3Node::Csg;
            node.csg = std::move(fr.csg);
            break;
        default:  // Affine, Triangles
            node.kind = V3Node::Group;
            node.group = std::move(fr.group);
            break;
    }
    return node;
}

// Spec §13.6: 16 reals, column by column; then one shape.
void ParserV3::v3_affine(FileState& f, const Token& d) {
    Mat4 m(1.0);
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = real(f, d, 16);  // GLM's m[column][row]
    check_matrix(m, f.lex.loc(d), "#static_affine matrix");
    v3_push(f, d, V3Frame::Affine);
    f.v3.back().group.matrix = m;
}

// Spec §14.2: the DOF NAME of this file's key files; its matrix is key 0 as read (§14.7).
void ParserV3::v3_dynamic(FileState& f, const Token& d) {
    const SourceLoc loc = f.lex.loc(d);
    const Token nt = f.lex.peek();
    const std::string name = word(f, d, "a DOF name", true);
    int track = -1;
    if (f.key_files.empty()) {
        if (!f.warned_dynamic_identity)
            warn(loc, "joint-no-key", "no #key_file: #dynamic_affine uses the identity");
        f.warned_dynamic_identity = true;
    } else {
        track = bind_dof(f, nt, name);
    }
    v3_push(f, d, V3Frame::Affine);
    GroupDesc& g = f.v3.back().group;
    g.joint = name;
    g.track = track;
    if (track >= 0) g.matrix = m_scene.tracks[static_cast<size_t>(track)].keys[0];
}

// Spec §13.5: v1 v2 v3 of this file, with the list's material.
void ParserV3::v3_triangle(FileState& f, const Token& d) {
    ShapeDesc s;
    s.loc = f.lex.loc(d);
    s.material = f.v3.back().material;
    const TriangleDesc g = triangle_indices(f, d);
    s.geometry = g;
    if (degenerate_triangle(f.defs(), g)) return skip_shape(s.loc, "degenerate triangle");
    add_shape(f, d, f.v3.back().group.shapes, std::move(s));
}

void ParserV3::v3_instance(FileState& f, const Token& d) {
    SourceLoc loc;
    const int i = integer(f, d, "ray file index", &loc);
    const int n = static_cast<int>(f.desc.ray_files.size());
    if (i < 0 || i >= n)
        fail(loc,
             "ray file index " + std::to_string(i) + " out of range [0," + std::to_string(n) + ")");
    V3Node node;
    node.kind = V3Node::Instance;
    node.loc = f.lex.loc(d);
    node.instance = {node.loc, i};
    v3_deliver(f, std::move(node));
}

void ParserV3::v3_end_of_file(FileState& f, const SourceLoc& eof) {
    if (f.v3.size() > 1) fail(eof, open_message(f.v3.back(), "end of file"));
    f.desc.root = std::move(f.v3.back().group);
    f.desc.root.loc = {};
    f.v3.clear();
}

}  // namespace rt::parser_impl
