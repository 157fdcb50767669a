#include "rt/format/writer.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <iterator>
#include <variant>

#include "rt/util/charconv.h"

namespace rt {

namespace {

class Writer {
public:
    Writer(const SceneDesc& desc, bool absolute, std::string base = "")
        : m_desc(desc), m_absolute(absolute), m_base(std::move(base)) {}

    std::string run() {
        m_out += "// Written by rayview/raytrace (";
        m_out += dialect_name(m_desc.dialect);
        m_out += " dialect).\n";
        if (m_desc.dialect == Dialect::V3) {
            run_v3();
        } else {
            run_v1();
        }
        return m_out;
    }

    /// One #material directive, without its newline.
    std::string material_only(const MaterialDesc& m) {
        material(m);
        m_out.pop_back();
        return m_out;
    }

private:
    // ---- V0 and V1 (spec §3) ----

    void run_v1() {
        const FileDesc& top = m_desc.files[0];
        if (!m_desc.shader_vertex.empty() || !m_desc.shader_fragment.empty())
            throw SceneError({}, "a shader cannot be written in V0 or V1 (#shader is V3 only)");
        camera();
        directive("#background"), vec(m_desc.background), end();
        directive("#ambient"), vec(m_desc.ambient), end();
        for (const LightDesc& l : m_desc.lights) light_v1(l);
        local_part(top, true);
        group_body_v1(top.root);
    }

    void light_v1(const LightDesc& l) {
        if (l.kind == LightKind::Sphere)
            throw SceneError(l.loc,
                             "a sphere light cannot be written in V0 or V1 "
                             "(#light_sphere is V3 only)");
        if (!l.one_colour())
            throw SceneError(l.loc,
                             "a light with an ambient colour or different diffuse and specular "
                             "colours cannot be written in V0 or V1 (three-colour lights are V3 "
                             "only)");
        // The parser scales V0 drop-offs by 128 (spec §7.2): write them back unscaled.
        const double dor =
            m_desc.dialect == Dialect::V0 ? l.spot_exponent / kV0ExponentScale : l.spot_exponent;
        switch (l.kind) {
            case LightKind::Directional:
                directive("#light_dir"), vec(l.diffuse), vec(l.direction);
                break;
            case LightKind::Point:
                directive("#light_point"), vec(l.diffuse), vec(l.position), attenuation(l);
                break;
            case LightKind::Spot:
                directive("#light_spot"), vec(l.diffuse), vec(l.position), vec(l.direction);
                attenuation(l), num(l.cutoff_rad), num(dor);
                break;
            case LightKind::Sphere:
                break;
        }
        end();
    }

    void group_body_v1(const GroupDesc& g) {
        if (!g.csgs.empty())
            throw SceneError(g.csgs[0].loc, std::string("a CSG ") + csg_op_name(g.csgs[0].op) +
                                                " cannot be written in V0 or V1 (#shape_" +
                                                csg_op_name(g.csgs[0].op) + " is V3 only)");
        for (const ShapeDesc& s : g.shapes) {
            std::visit(
                [&](const auto& geo) {
                    using T = std::decay_t<decltype(geo)>;
                    if constexpr (kV3OnlyShape<T>)
                        throw SceneError(s.loc, std::string("a ") + T::kName +
                                                    " cannot be written in V0 or V1 (#shape_" +
                                                    T::kName + " is V3 only)");
                },
                s.geometry);
            shape(s);
        }
        for (const InstanceDesc& i : g.instances) instance(i);
        for (const GroupDesc& child : g.groups) {
            if (!child.joint.empty()) {  // its matrix comes from the key files (spec §4.4)
                directive("#joint_begin"), word(child.joint), end();
                group_body_v1(child);
                line("#joint_end");
                continue;
            }
            directive("#group_begin");
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) num(child.matrix[c][r]);  // row-major in the file
            end();
            group_body_v1(child);
            line("#group_end");
        }
    }

    // ---- V3 (spec §13) ----

    void run_v3() {
        const FileDesc& top = m_desc.files[0];
        if (m_desc.background != Vec3(0.0))
            throw SceneError({}, "a background colour cannot be written in V3 (no #background)");
        if (m_desc.ambient != Vec3(0.0))
            throw SceneError({}, "a global ambient colour cannot be written in V3 (no #ambient)");
        // The global part, the local part, the shapes (spec §13.1).
        camera();
        for (const LightDesc& l : m_desc.lights) light_v3(l);
        if (!m_desc.shader_vertex.empty() || !m_desc.shader_fragment.empty()) {
            if (m_desc.shader_vertex.empty() || m_desc.shader_fragment.empty())
                throw SceneError({}, "#shader needs both a vertex and a fragment shader");
            directive("#shader"), word(m_desc.shader_vertex), word(m_desc.shader_fragment), end();
        }
        local_part(top, true);
        items(top.root);  // the root list (spec §13.1)
    }

    // A D S, then the kind's numbers (spec §13.3).
    void light_v3(const LightDesc& l) {
        static const char* const kDirective[] = {"#light_dir", "#light_point", "#light_spot",
                                                 "#light_sphere"};
        static_assert(std::size(kDirective) == kLightKinds);
        directive(kDirective[static_cast<int>(l.kind)]);
        vec(l.ambient), vec(l.diffuse), vec(l.specular);
        switch (l.kind) {
            case LightKind::Directional:
                vec(l.direction);
                break;
            case LightKind::Point:
                vec(l.position), attenuation(l);
                break;
            case LightKind::Spot:
                vec(l.position), vec(l.direction), attenuation(l);
                num(l.cutoff_rad), num(l.spot_exponent);
                break;
            case LightKind::Sphere:
                vec(l.position), num(l.radius), attenuation(l);
                break;
        }
        end();
    }

    // Every child of a list, one shape each (spec §13.5): the shapes (consecutive triangles of one
    // material as one #shape_triangles), the lists and transforms, the instances, the CSG nodes.
    void items(const GroupDesc& g) {
        for (size_t i = 0; i < g.shapes.size();) {
            if (!std::holds_alternative<TriangleDesc>(g.shapes[i].geometry)) {
                shape(g.shapes[i++]);
                continue;
            }
            const size_t n = triangle_run(g, i);
            triangles(g, i, n);
            i += n;
        }
        for (const GroupDesc& child : g.groups) group_v3(child);
        for (const InstanceDesc& i : g.instances) instance(i);
        for (const CsgDesc& c : g.csgs) csg(c);
    }

    // The number of consecutive triangles of one material from shapes[i].
    static size_t triangle_run(const GroupDesc& g, size_t i) {
        size_t n = 0;
        while (i + n < g.shapes.size() &&
               std::holds_alternative<TriangleDesc>(g.shapes[i + n].geometry) &&
               g.shapes[i + n].material == g.shapes[i].material)
            ++n;
        return n;
    }

    // How many shapes items(g) writes.
    static size_t item_count(const GroupDesc& g) {
        size_t n = g.groups.size() + g.instances.size() + g.csgs.size();
        for (size_t i = 0; i < g.shapes.size(); ++n)
            i +=
                std::holds_alternative<TriangleDesc>(g.shapes[i].geometry) ? triangle_run(g, i) : 1;
        return n;
    }

    // The parser's #shape_triangles list: identity, only triangles, all of one material.
    static bool is_triangle_list(const GroupDesc& g) {
        return g.matrix == Mat4(1.0) && g.joint.empty() && !g.shapes.empty() && g.groups.empty() &&
               g.instances.empty() && g.csgs.empty() &&
               std::holds_alternative<TriangleDesc>(g.shapes[0].geometry) &&
               triangle_run(g, 0) == g.shapes.size();
    }

    void triangles(const GroupDesc& g, size_t first, size_t n) {
        directive("#shape_triangles"), integer(g.shapes[first].material), end();
        open_list();
        for (size_t i = first; i < first + n; ++i) {
            directive("#shape_triangle");
            params(std::get<TriangleDesc>(g.shapes[i].geometry));
            end();
        }
        close_list();
    }

    // A child list: a joint, a transform, a #shape_triangles list or a plain list.
    void group_v3(const GroupDesc& g) {
        if (is_triangle_list(g)) {
            triangles(g, 0, g.shapes.size());
        } else if (!g.joint.empty()) {
            directive("#dynamic_affine"), word(g.joint), end();
            one_shape(g);
        } else if (g.matrix != Mat4(1.0)) {
            directive("#static_affine");
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) num(g.matrix[c][r]);  // column-major (spec §13.6)
            end();
            one_shape(g);
        } else {
            list(g);
        }
    }

    void list(const GroupDesc& g) {
        open_list();
        items(g);
        close_list();
    }

    // The contents of `g` as the one child shape of a transform or a CSG operand. The parser folds
    // a #shape_list_begin child into its parent, so a list is written for several children or
    // none, and around a single child that is itself a list (it would be folded otherwise).
    void one_shape(const GroupDesc& g) {
        const bool single_list =
            g.groups.size() == 1 && g.groups[0].joint.empty() && g.groups[0].matrix == Mat4(1.0);
        if (item_count(g) == 1 && !single_list) {
            items(g);
        } else {
            list(g);
        }
    }

    // A CSG node (spec §13.8): one shape per operand, in a list for union and intersection.
    void csg(const CsgDesc& c) {
        directive(c.op == CsgOp::Union          ? "#shape_union"
                  : c.op == CsgOp::Intersection ? "#shape_intersection"
                                                : "#shape_difference");
        end();
        if (c.op == CsgOp::Difference) {
            if (c.operands.size() != 2)
                throw SceneError(c.loc,
                                 "a CSG difference needs exactly two operands to be "
                                 "written, got " +
                                     std::to_string(c.operands.size()));
            operand(c.operands[0]), operand(c.operands[1]);
            return;
        }
        open_list();
        for (const GroupDesc& o : c.operands) operand(o);
        close_list();
    }

    // An operand is one child wrapped in an identity list; any other matrix is kept as a transform.
    void operand(const GroupDesc& o) {
        if (o.joint.empty() && o.matrix == Mat4(1.0)) {
            one_shape(o);
        } else {
            group_v3(o);
        }
    }

    void open_list() {
        line("#shape_list_begin");
        m_indent += "  ";
    }
    void close_list() {
        m_indent.resize(m_indent.size() - 2);
        line("#shape_list_end");
    }

    // ---- shared ----

    // Appends piece by piece (GCC 12 warns falsely, -Wrestrict, on "literal" + std::string).
    void line(const char* s) {
        m_out += m_indent;
        m_out += s;
        m_out += '\n';
    }
    void directive(const char* d) {
        m_out += m_indent;
        m_out += d;
    }
    void end() { m_out += "\n"; }
    void word(const std::string& w) {
        m_out += ' ';
        m_out += w;
    }
    void integer(int i) {
        m_out += ' ';
        m_out += std::to_string(i);
    }
    // Shortest text that reads back to the same double.
    void num(double v) {
        char buf[32];
        const auto r = to_chars_shortest(buf, buf + sizeof buf, v);
        m_out += ' ';
        m_out.append(buf, r.ptr);
    }
    void vec(const Vec3& v) { num(v.x), num(v.y), num(v.z); }
    void attenuation(const LightDesc& l) {
        num(l.constant_atten), num(l.linear_atten), num(l.quadratic_atten);
    }

    std::string path(const std::string& p) const {
        if (!m_absolute) return p;
        std::error_code ec;
        const auto abs = std::filesystem::absolute(p, ec).lexically_normal();
        if (ec) return p;
        if (m_base.empty()) return abs.string();
        // Relative to the saved file's directory, where the parser looks first (spec §13.2).
        const auto rel = abs.lexically_relative(m_base);
        return rel.empty() ? abs.string() : rel.string();
    }

    void camera() {
        if (!m_desc.camera) return;
        const CameraDesc& c = *m_desc.camera;
        directive("#camera");
        vec(c.position), vec(c.direction), vec(c.up), num(c.half_height_angle_rad);
        end();
    }

    // Textures, materials, vertices, included files and key files.
    void local_part(const FileDesc& top, bool key_files) {
        for (const TextureDesc& t : top.textures) directive("#texture"), word(path(t.path)), end();
        for (const MaterialDesc& m : top.materials) material(m);
        for (const VertexDesc& v : top.vertices) {
            directive("#vertex"), vec(v.position), vec(v.normal), num(v.uv.x), num(v.uv.y), end();
        }
        for (int f : top.ray_files)
            directive("#ray_file"), word(path(m_desc.files[static_cast<size_t>(f)].path)), end();
        if (key_files)
            for (const std::string& k : top.key_files) directive("#key_file"), word(path(k)), end();
    }

    void material(const MaterialDesc& m) {
        directive("#material");
        if (m_desc.dialect == Dialect::V0) {
            // ambient, diffuse, specular, emissive, kspec = e/128, ktran, refind, tex
            vec(m.ambient), vec(m.diffuse), vec(m.specular), vec(m.emissive);
            num(m.specular_exponent / kV0ExponentScale), num(m.transparent.x);
        } else {
            vec(m.emissive), vec(m.ambient), vec(m.diffuse), vec(m.specular);
            num(m.specular_exponent), vec(m.transparent);
        }
        num(m.refractive_index), integer(m.texture);
        m_out += " !";
        m_out += m.name;
        m_out += "!\n";
    }

    void instance(const InstanceDesc& i) {
        directive("#ray_file_instance"), integer(i.ray_file), end();
    }

    // One shape directive with its material (V3 triangles: triangles()).
    void shape(const ShapeDesc& s) {
        const std::string name =
            std::string("#shape_") + shape_kind_name(static_cast<ShapeKind>(s.geometry.index()));
        directive(name.c_str()), integer(s.material);
        std::visit([&](const auto& geo) { params(geo); }, s.geometry);
        end();
    }

    // The numbers of #shape_<kind> in the order the kind lists them (shapes.h).
    void params(const TriangleDesc& g) {
        for (int v : g.v) integer(v);
    }
    template <class Desc>
    void params(Desc g) {
        struct Put {
            Writer& w;
            void point(const Vec3& v) { w.vec(v); }
            void size(double x, const char*) { w.num(x); }
        } put{*this};
        g.params(put);
    }

    const SceneDesc& m_desc;
    bool m_absolute;
    std::string m_base;  // the directory paths are written relative to, "" for absolute
    std::string m_out;
    std::string m_indent;  // V3 lists are indented
};

}  // namespace

std::string write_scene(const SceneDesc& desc, bool absolute_paths) {
    if (desc.files.empty()) return {};
    return Writer(desc, absolute_paths).run();
}

std::string write_scene_for(const SceneDesc& desc, const std::string& saved_path) {
    if (desc.files.empty()) return {};
    std::error_code ec;
    auto dir = std::filesystem::absolute(saved_path, ec).lexically_normal().parent_path();
    if (ec) return write_scene(desc);
    return Writer(desc, true, dir.string()).run();
}

std::string write_material(const MaterialDesc& m, Dialect dialect) {
    SceneDesc desc;
    desc.dialect = dialect;
    return Writer(desc, true).material_only(m);
}

std::string replace_materials(const std::string& text, const std::string& file,
                              std::vector<std::pair<SourceLoc, std::string>> edits) {
    // Each location as an offset into the text (lines and columns count from 1, in bytes).
    std::vector<size_t> line_start{0};
    for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') line_start.push_back(i + 1);
    struct Span {
        size_t begin, end;
        const std::string* with;
        SourceLoc at;
    };
    std::vector<Span> spans;
    for (const auto& [loc, with] : edits) {
        const SourceLoc at{&file, loc.line, loc.col};
        const auto fail = [&](const std::string& why) {
            return SceneError(at, "cannot write the edited material here: " + why);
        };
        if (loc.line < 1 || static_cast<size_t>(loc.line) > line_start.size() || loc.col < 1)
            throw fail("no such line in the file as it is now");
        const size_t begin =
            line_start[static_cast<size_t>(loc.line - 1)] + static_cast<size_t>(loc.col - 1);
        static constexpr std::string_view kDirective = "#material";
        if (text.compare(begin, kDirective.size(), kDirective) != 0)
            throw fail("the file no longer has its #material there");
        // Its numbers, then the !name! string: nothing else may come between (a comment would
        // be lost, and a '!' inside one would end the search early).
        size_t open = begin + kDirective.size();
        while (open < text.size() && text[open] != '!') {
            const char c = text[open];
            if (!(std::isspace(static_cast<unsigned char>(c)) || std::isdigit(c) || c == '.' ||
                  c == '-' || c == '+' || c == 'e' || c == 'E'))
                throw fail("it holds more than its numbers and name");
            ++open;
        }
        const size_t close = open < text.size() ? text.find('!', open + 1) : std::string::npos;
        if (close == std::string::npos) throw fail("its !name! string is not closed");
        spans.push_back({begin, close + 1, &with, at});
    }
    std::sort(spans.begin(), spans.end(),
              [](const Span& a, const Span& b) { return a.begin < b.begin; });
    std::string out;
    size_t from = 0;
    for (const Span& s : spans) {
        if (s.begin < from) throw SceneError(s.at, "two edits of one material");
        out.append(text, from, s.begin - from);
        out += *s.with;
        from = s.end;
    }
    out.append(text, from, std::string::npos);
    return out;
}

}  // namespace rt
