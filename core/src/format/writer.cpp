#include "rt/format/writer.h"

#include <charconv>
#include <filesystem>
#include <variant>

namespace rt {

namespace {

class Writer {
public:
    Writer(const SceneDesc& desc, bool absolute) : m_desc(desc), m_absolute(absolute) {}

    std::string run() {
        const FileDesc& top = m_desc.files[0];
        m_out += "// Written by rayview/raytrace (";
        m_out += dialect_name(m_desc.dialect);
        m_out += " dialect).\n";
        if (m_desc.camera) {
            const CameraDesc& c = *m_desc.camera;
            directive("#camera");
            vec(c.position), vec(c.direction), vec(c.up), num(c.half_height_angle_rad);
            end();
        }
        directive("#background"), vec(m_desc.background), end();
        directive("#ambient"), vec(m_desc.ambient), end();
        for (const LightDesc& l : m_desc.lights) light(l);
        for (const TextureDesc& t : top.textures) directive("#texture"), word(path(t.path)), end();
        for (const MaterialDesc& m : top.materials) material(m);
        for (const VertexDesc& v : top.vertices) {
            directive("#vertex"), vec(v.position), vec(v.normal), num(v.uv.x), num(v.uv.y), end();
        }
        for (int f : top.ray_files)
            directive("#ray_file"), word(path(m_desc.files[static_cast<size_t>(f)].path)), end();
        group_body(top.root);
        return m_out;
    }

private:
    // Appends piece by piece (GCC 12 warns falsely, -Wrestrict, on "literal" + std::string).
    void line(const std::string& s) {
        m_out += s;
        m_out += '\n';
    }
    void directive(const char* d) { m_out += d; }
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
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        m_out += ' ';
        m_out.append(buf, r.ptr);
    }
    void vec(const Vec3& v) { num(v.x), num(v.y), num(v.z); }

    std::string path(const std::string& p) const {
        if (!m_absolute) return p;
        std::error_code ec;
        const auto abs = std::filesystem::absolute(p, ec);
        return ec ? p : abs.lexically_normal().string();
    }

    void light(const LightDesc& l) {
        // The parser scales V0 drop-offs by 128 (spec §7.2): write them back unscaled.
        const double dor =
            m_desc.dialect == Dialect::V0 ? l.spot_exponent / kV0ExponentScale : l.spot_exponent;
        switch (l.kind) {
            case LightKind::Directional:
                directive("#light_dir"), vec(l.diffuse), vec(l.direction);
                break;
            case LightKind::Point:
                directive("#light_point"), vec(l.diffuse), vec(l.position);
                num(l.constant_atten), num(l.linear_atten), num(l.quadratic_atten);
                break;
            case LightKind::Spot:
                directive("#light_spot"), vec(l.diffuse), vec(l.position), vec(l.direction);
                num(l.constant_atten), num(l.linear_atten), num(l.quadratic_atten);
                num(l.cutoff_rad), num(dor);
                break;
            case LightKind::Sphere:
                throw SceneError(l.loc,
                                 "a sphere light cannot be written in V0 or V1 "
                                 "(#light_sphere is V3 only)");
        }
        end();
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

    void group_body(const GroupDesc& g) {
        for (const ShapeDesc& s : g.shapes) shape(s);
        for (const InstanceDesc& i : g.instances)
            directive("#ray_file_instance"), integer(i.ray_file), end();
        for (const GroupDesc& child : g.groups) {
            directive("#group_begin");
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) num(child.matrix[c][r]);  // row-major in the file
            end();
            group_body(child);
            line("#group_end");
        }
    }

    void shape(const ShapeDesc& s) {
        std::visit(
            [&](const auto& geo) {
                directive(directive_of(geo)), integer(s.material), params(geo);
            },
            s.geometry);
        end();
    }

    // One directive name and one parameter list per kind (spec §5), in the file's order.
    static const char* directive_of(const Sphere&) { return "#shape_sphere"; }
    static const char* directive_of(const BoxDesc&) { return "#shape_box"; }
    static const char* directive_of(const Cylinder&) { return "#shape_cylinder"; }
    static const char* directive_of(const Cone&) { return "#shape_cone"; }
    static const char* directive_of(const TriangleDesc&) { return "#shape_triangle"; }
    // The torus is a V3 shape (spec §13.7): V0 and V1 have no directive for it.
    [[noreturn]] static const char* directive_of(const Torus&) {
        throw SceneError({}, "a torus cannot be written in V0 or V1 (#shape_torus is V3 only)");
    }
    void params(const Sphere& g) { vec(g.centre), num(g.radius); }
    void params(const BoxDesc& g) { vec(g.centre), vec(g.size); }
    void params(const Cylinder& g) { vec(g.centre), num(g.radius), num(g.height); }
    void params(const Cone& g) { vec(g.centre), num(g.radius), num(g.height); }
    void params(const Torus& g) { vec(g.centre), num(g.tube), num(g.ring); }
    void params(const TriangleDesc& g) {
        for (int v : g.v) integer(v);
    }

    const SceneDesc& m_desc;
    bool m_absolute;
    std::string m_out;
};

}  // namespace

std::string write_scene(const SceneDesc& desc, bool absolute_paths) {
    if (desc.files.empty()) return {};
    return Writer(desc, absolute_paths).run();
}

}  // namespace rt
