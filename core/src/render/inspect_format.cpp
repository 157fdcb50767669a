// The ray tree as text a student reads against the formulas of spec §7, §8 and §13.9, and as
// JSON (docs/inspect.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rt/render/inspect.h"
#include "rt/shapes/shapes.h"

namespace rt {

namespace {

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string vec(const Vec3& v) { return "(" + num(v.x) + " " + num(v.y) + " " + num(v.z) + ")"; }

const char* light_kind_text(LightKind k) {
    switch (k) {
        case LightKind::Directional:
            return "directional";
        case LightKind::Point:
            return "point";
        case LightKind::Spot:
            return "spot";
        case LightKind::Sphere:
            return "sphere";
    }
    return "";
}

const char* ray_kind_text(InspectRay::Kind k) {
    switch (k) {
        case InspectRay::Kind::Camera:
            return "camera";
        case InspectRay::Kind::Reflected:
            return "reflected";
        case InspectRay::Kind::Refracted:
            return "refracted";
    }
    return "";
}

std::string material_name(int m, const InspectNames& names) {
    std::string text = "material " + std::to_string(m);
    if (names.material_names && m >= 0 && static_cast<size_t>(m) < names.material_names->size() &&
        !(*names.material_names)[static_cast<size_t>(m)].empty())
        text += " !" + (*names.material_names)[static_cast<size_t>(m)] + "!";
    return text;
}

const SourceLoc* prim_loc(const InspectPrim& p, const InspectNames& names) {
    if (!names.prim_locs || p.set < 0) return nullptr;
    const auto& locs = *names.prim_locs;
    if (static_cast<size_t>(p.set) >= locs.size() ||
        p.prim >= locs[static_cast<size_t>(p.set)].size())
        return nullptr;
    return &locs[static_cast<size_t>(p.set)][p.prim];
}

std::string prim_path(const InspectPrim& p, const InspectNames& names) {
    const SourceLoc* loc = prim_loc(p, names);
    return loc && loc->file && names.desc ? group_path(*names.desc, *loc) : "";
}

// The text of one ray and its subtree, each line indented by `pad`.
class TextWriter {
public:
    TextWriter(const PixelTree& tree, const RenderScene& scene, const InspectNames& names)
        : m_tree(tree), m_scene(scene), m_names(names) {}

    void ray(int index, const std::string& pad) {
        const InspectRay& r = m_tree.rays[static_cast<size_t>(index)];
        line(pad, std::string(ray_kind_text(r.kind)) + " ray, depth " + std::to_string(r.depth) +
                      (r.kind == InspectRay::Kind::Camera ? "" : ", path weight " + vec(r.weight)) +
                      ": from " + vec(r.ray.o) + " along " + vec(r.ray.d));
        if (r.kind == InspectRay::Kind::Refracted)
            line(pad + "  ",
                 "Snell: eta " + num(r.eta) + ", cos of the incident angle " + num(r.cos_incident));
        if (!r.hit) {
            line(pad + "  ", "misses everything: background " + vec(r.color));
            return;
        }
        const std::string in = pad + "  ";
        line(in, "hits " + inspect_prim_name(r.prim, m_names) + " at distance " + num(r.distance) +
                     ", point " + vec(r.point));
        line(in,
             material_name(r.material, m_names) + "; the ray " +
                 (r.entering ? "enters (meets the outward side)" : "leaves (meets the inside)"));
        if (r.material >= 0 && static_cast<size_t>(r.material) < m_scene.materials.size()) {
            const Material& m = m_scene.materials[static_cast<size_t>(r.material)];
            line(in + "  ", "K_E " + vec(m.emissive) + ", K_A " + vec(m.ambient) + ", K_D " +
                                vec(m.diffuse) + ", K_S " + vec(m.specular) + ", n " +
                                num(m.specular_exponent) + ", T " + vec(m.transparent) +
                                ", index " + num(m.refractive_index) +
                                (m.texture >= 0 ? ", textured" : ""));
        }
        line(in, "n_g " + vec(r.n_geometric) + ", n_s " + vec(r.n_shading) + ", N " + vec(r.n) +
                     (r.entering ? "" : " (n_s flipped: two-sided rule)"));
        if (r.textured)
            line(in, "uv (" + num(r.uv.x) + " " + num(r.uv.y) + "), texel t " + vec(r.texel) +
                         " (multiplies K_A and K_D" +
                         (m_scene.texture_all_terms ? ", K_E and K_S)" : ")"));
        line(in, "emissive = K_E " + vec(r.emissive));
        line(in, "ambient  = K_A " + vec(r.k_a) + " x I_a " + vec(r.scene_ambient) + " = " +
                     vec(r.ambient));
        for (const InspectLight& l : r.lights) light(r, l, in);
        secondary(r, in);
        line(in, "sum = " + vec(r.color));
    }

    std::string text() const { return m_out; }

private:
    void line(const std::string& pad, const std::string& s) { m_out += pad + s + "\n"; }

    void light(const InspectRay& r, const InspectLight& l, const std::string& pad) {
        std::string head = "light " + std::to_string(l.light) + " (" + light_kind_text(l.kind);
        if (l.kind != LightKind::Directional) head += " at " + vec(l.position);
        head += l.one_colour ? ", I " + vec(l.diffuse)
                             : ", A_l " + vec(l.ambient) + ", D_l " + vec(l.diffuse) + ", S_l " +
                                   vec(l.specular);
        line(pad, head + ")");
        const std::string in = pad + "  ";
        if (l.attenuated)
            line(in, "attenuation = 1 / (c0 " + num(l.constant) + " + c1 " + num(l.linear) +
                         " x d + c2 " + num(l.quadratic) + " x d^2), d " + num(l.distance) +
                         " = 1 / " + num(l.denominator) + " = " + num(1.0 / l.denominator));
        if (l.spot)
            line(in, "spot = cos a " + num(l.cos_angle) + " (a " +
                         num(std::acos(std::clamp(l.cos_angle, -1.0, 1.0)) * 180.0 / kPi) +
                         " deg, cut-off " + num(l.cutoff_deg) + " deg) ^ exponent " +
                         num(l.spot_exponent) + " = " + num(l.spot_factor));
        line(in, "f_l = " + num(l.factor));
        if (l.ambient_term != Vec3(0.0))
            line(in, "ambient = K_A " + vec(r.k_a) + " x A_l " + vec(l.ambient) +
                         " x f_l = " + vec(l.ambient_term));
        if (l.facing_known) line(in, "L " + vec(l.to_light) + ", N.L " + num(l.n_dot_l));
        if (l.shadow_tested) {
            line(in, "shadow S_l = " + vec(l.shadow) + " (" + std::to_string(l.shadow_ray_count) +
                         (l.shadow_ray_count == 1 ? " shadow ray" : " shadow rays") +
                         (l.shadow_ray_count > l.shadow_rays.size()
                              ? ", the first " + std::to_string(l.shadow_rays.size()) + " shown"
                              : "") +
                         ")");
            for (const InspectShadowRay& s : l.shadow_rays) shadow(s, in + "  ");
        }
        if (l.note.empty() || l.value != Vec3(0.0)) {
            if (l.one_colour) {
                const Vec3 i = l.diffuse * l.factor;
                line(in, "diffuse  = I_l " + vec(i) + " x K_D " + vec(r.k_d) + " x N.L " +
                             num(l.n_dot_l) + " = " + vec(l.diffuse_term));
                line(in, "specular = I_l " + vec(i) + " x K_S " + vec(r.k_s) + " x max(R.L " +
                             num(l.r_dot_l) + ", 0) ^ n " + num(r.exponent) +
                             " (= " + num(l.highlight) + ") = " + vec(l.specular_term));
            } else {
                line(in, "diffuse  = f_l x D_l x K_D " + vec(r.k_d) + " x N.L " + num(l.n_dot_l) +
                             " = " + vec(l.diffuse_term));
                line(in, "specular = f_l x S_l x K_S " + vec(r.k_s) + " x max(R.L " +
                             num(l.r_dot_l) + ", 0) ^ n " + num(r.exponent) +
                             " (= " + num(l.highlight) + ") = " + vec(l.specular_term));
            }
            line(in, "adds S_l x (diffuse + specular) = " + vec(l.value));
        } else {
            line(in, "adds nothing: " + l.note);
        }
    }

    void shadow(const InspectShadowRay& s, const std::string& pad) {
        std::string to =
            std::isfinite(s.t_max) ? "to " + vec(s.ray.o + s.ray.d) : "along " + vec(s.ray.d);
        line(pad, "shadow ray from " + vec(s.ray.o) + " " + to + ": transmittance " +
                      vec(s.transmittance));
        for (const InspectOccluder& o : s.occluders)
            line(pad + "  ", "meets " + inspect_prim_name(o.prim, m_names) + " at distance " +
                                 num(o.distance) + ", " + material_name(o.material, m_names) +
                                 ", T " + vec(o.transparent) +
                                 (o.transparent == Vec3(0.0) ? " (opaque: blocked)" : ""));
    }

    void secondary(const InspectRay& r, const std::string& pad) {
        for (int c : r.children) {
            const InspectRay& child = m_tree.rays[static_cast<size_t>(c)];
            const bool refl = child.kind == InspectRay::Kind::Reflected;
            line(pad, std::string(refl ? "reflected = K_S " + vec(r.k_reflect)
                                       : "refracted = T " + vec(r.k_transmit)) +
                          " x the colour of the ray below " + vec(child.color) + " = " +
                          vec(refl ? r.reflected : r.refracted));
            ray(c, pad + "  ");
        }
        for (const InspectStop& s : r.stops)
            line(pad,
                 s.kind + " ray not traced: " + s.why + " (path weight " + vec(s.weight) + ")");
    }

    const PixelTree& m_tree;
    const RenderScene& m_scene;
    const InspectNames& m_names;
    std::string m_out;
};

// A minimal JSON writer: numbers round-trip, non-finite numbers are null.
class Json {
public:
    void open(char c) {
        sep();
        m_out += c;
        m_first = true;
    }
    void close(char c) {
        m_out += c;
        m_first = false;
    }
    void key(const char* k) {
        sep();
        str(k);
        m_out += ':';
        m_first = true;
    }
    void number(double v) {
        sep();
        if (!std::isfinite(v)) {
            m_out += "null";
            return;
        }
        // The shortest of 15 and 17 digits that reads back as v.
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.15g", v);
        if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
        m_out += buf;
    }
    void integer(long long v) {
        sep();
        m_out += std::to_string(v);
    }
    void boolean(bool b) {
        sep();
        m_out += b ? "true" : "false";
    }
    void null() {
        sep();
        m_out += "null";
    }
    void string(const std::string& s) {
        sep();
        str(s);
    }
    void vec3(const Vec3& v) {
        open('[');
        number(v.x), number(v.y), number(v.z);
        close(']');
    }
    void vec2(const Vec2& v) {
        open('[');
        number(v.x), number(v.y);
        close(']');
    }
    // key: value shorthands.
    void kv(const char* k, double v) { key(k), number(v); }
    void kv(const char* k, const Vec3& v) { key(k), vec3(v); }
    void kv(const char* k, const std::string& v) { key(k), string(v); }
    void kb(const char* k, bool v) { key(k), boolean(v); }
    void ki(const char* k, long long v) { key(k), integer(v); }
    std::string text() const { return m_out + "\n"; }

private:
    void sep() {
        if (!m_first && !m_out.empty() && m_out.back() != ':') m_out += ',';
        m_first = false;
    }
    void str(const std::string& s) {
        m_out += '"';
        for (unsigned char ch : s) {
            if (ch == '"' || ch == '\\') {
                m_out += '\\';
                m_out += static_cast<char>(ch);
            } else if (ch < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", ch);
                m_out += buf;
            } else {
                m_out += static_cast<char>(ch);
            }
        }
        m_out += '"';
    }
    std::string m_out;
    bool m_first = true;
};

class JsonWriter {
public:
    JsonWriter(const PixelTree& tree, const InspectNames& names) : m_tree(tree), m_names(names) {}

    void prim(const InspectPrim& p) {
        m_j.open('{');
        m_j.kv("shape", p.csg ? std::string("csg") : std::string(shape_kind_name(p.kind)));
        m_j.ki("instance", p.instance);
        m_j.ki("set", p.set);
        m_j.ki("index", p.prim);
        const SourceLoc* loc = prim_loc(p, m_names);
        m_j.key("location");
        if (loc && loc->file)
            m_j.string(loc->str());
        else
            m_j.null();
        m_j.kv("path", prim_path(p, m_names));
        m_j.kv("name", inspect_prim_name(p, m_names));
        m_j.close('}');
    }

    void material(int m) {
        m_j.open('{');
        m_j.ki("index", m);
        const bool named = m_names.material_names && m >= 0 &&
                           static_cast<size_t>(m) < m_names.material_names->size();
        m_j.kv("name", named ? (*m_names.material_names)[static_cast<size_t>(m)] : std::string());
        m_j.close('}');
    }

    void shadow(const InspectShadowRay& s, int light) {
        m_j.open('{');
        m_j.kv("kind", std::string("shadow"));
        m_j.ki("light", light);
        m_j.kv("origin", s.ray.o);
        m_j.kv("direction", s.ray.d);
        m_j.kv("t_max", s.t_max);
        m_j.kv("transmittance", s.transmittance);
        m_j.key("occluders");
        m_j.open('[');
        for (const InspectOccluder& o : s.occluders) {
            m_j.open('{');
            m_j.key("primitive");
            prim(o.prim);
            m_j.kv("t", o.t);
            m_j.kv("distance", o.distance);
            m_j.key("material");
            material(o.material);
            m_j.kv("transparent", o.transparent);
            m_j.close('}');
        }
        m_j.close(']');
        m_j.close('}');
    }

    void light(const InspectLight& l) {
        m_j.open('{');
        m_j.ki("light", l.light);
        m_j.kv("kind", std::string(light_kind_text(l.kind)));
        m_j.kb("one_colour", l.one_colour);
        m_j.kv("position", l.position);
        m_j.kv("ambient_colour", l.ambient);
        m_j.kv("colour", l.diffuse);
        m_j.kv("specular_colour", l.specular);
        m_j.key("attenuation");
        if (l.attenuated) {
            m_j.open('{');
            m_j.kv("d", l.distance);
            m_j.kv("c0", l.constant);
            m_j.kv("c1", l.linear);
            m_j.kv("c2", l.quadratic);
            m_j.kv("denominator", l.denominator);
            m_j.kv("value", 1.0 / l.denominator);
            m_j.close('}');
        } else {
            m_j.null();
        }
        m_j.key("spot");
        if (l.spot) {
            m_j.open('{');
            m_j.kv("cos_angle", l.cos_angle);
            m_j.kv("cutoff_deg", l.cutoff_deg);
            m_j.kv("exponent", l.spot_exponent);
            m_j.kv("value", l.spot_factor);
            m_j.close('}');
        } else {
            m_j.null();
        }
        m_j.kv("factor", l.factor);
        m_j.kv("L", l.to_light);
        m_j.kv("n_dot_l", l.n_dot_l);
        m_j.kv("r_dot_l", l.r_dot_l);
        m_j.kv("highlight", l.highlight);
        m_j.kv("ambient", l.ambient_term);
        m_j.kv("diffuse", l.diffuse_term);
        m_j.kv("specular", l.specular_term);
        m_j.key("shadow");
        if (l.shadow_tested) {
            m_j.open('{');
            m_j.kv("value", l.shadow);
            m_j.ki("rays", static_cast<long long>(l.shadow_ray_count));
            m_j.close('}');
        } else {
            m_j.null();
        }
        m_j.kv("value", l.value);
        m_j.kv("note", l.note);
        m_j.close('}');
    }

    void ray(int index) {
        const InspectRay& r = m_tree.rays[static_cast<size_t>(index)];
        m_j.open('{');
        m_j.kv("kind", std::string(ray_kind_text(r.kind)));
        m_j.ki("depth", r.depth);
        m_j.kv("origin", r.ray.o);
        m_j.kv("direction", r.ray.d);
        m_j.kv("weight", r.weight);
        if (r.kind == InspectRay::Kind::Refracted) {
            m_j.kv("eta", r.eta);
            m_j.kv("cos_incident", r.cos_incident);
        }
        m_j.key("hit");
        if (r.hit) {
            m_j.open('{');
            m_j.kv("t", r.t);
            m_j.kv("distance", r.distance);
            m_j.kv("point", r.point);
            m_j.key("primitive");
            prim(r.prim);
            m_j.key("material");
            material(r.material);
            m_j.kv("n_g", r.n_geometric);
            m_j.kv("n_s", r.n_shading);
            m_j.kv("n", r.n);
            m_j.kb("entering", r.entering);
            m_j.key("uv");
            m_j.vec2(r.uv);
            m_j.key("texel");
            if (r.textured)
                m_j.vec3(r.texel);
            else
                m_j.null();
            m_j.close('}');
        } else {
            m_j.null();
        }
        m_j.key("terms");
        m_j.open('{');
        if (r.hit) {
            m_j.kv("emissive", r.emissive);
            m_j.key("ambient");
            m_j.open('{');
            m_j.kv("k_a", r.k_a);
            m_j.kv("scene_ambient", r.scene_ambient);
            m_j.kv("value", r.ambient);
            m_j.close('}');
            m_j.kv("k_d", r.k_d);
            m_j.kv("k_s", r.k_s);
            m_j.kv("exponent", r.exponent);
            m_j.key("lights");
            m_j.open('[');
            for (const InspectLight& l : r.lights) light(l);
            m_j.close(']');
            m_j.key("reflected");
            m_j.open('{');
            m_j.kv("k_s", r.k_reflect);
            m_j.kv("value", r.reflected);
            m_j.close('}');
            m_j.key("refracted");
            m_j.open('{');
            m_j.kv("t", r.k_transmit);
            m_j.kv("value", r.refracted);
            m_j.close('}');
        } else {
            m_j.kv("background", r.color);
        }
        m_j.kv("sum", r.color);
        m_j.close('}');
        m_j.key("stopped");
        m_j.open('[');
        for (const InspectStop& s : r.stops) {
            m_j.open('{');
            m_j.kv("kind", s.kind);
            m_j.kv("why", s.why);
            m_j.kv("weight", s.weight);
            m_j.close('}');
        }
        m_j.close(']');
        m_j.key("children");
        m_j.open('[');
        for (const InspectLight& l : r.lights)
            for (const InspectShadowRay& s : l.shadow_rays) shadow(s, l.light);
        for (int c : r.children) ray(c);
        m_j.close(']');
        m_j.close('}');
    }

    std::string text() {
        m_j.open('{');
        m_j.key("pixel");
        m_j.open('[');
        m_j.integer(m_tree.x), m_j.integer(m_tree.y);
        m_j.close(']');
        m_j.ki("sample", m_tree.sample);
        m_j.ki("samples", m_tree.samples);
        m_j.key("position");
        m_j.vec2(m_tree.position);
        m_j.kv("color", m_tree.pixel);
        m_j.kv("sample_color", m_tree.color);
        m_j.key("rays");
        m_j.open('[');
        if (!m_tree.rays.empty()) ray(0);
        m_j.close(']');
        m_j.close('}');
        return m_j.text();
    }

private:
    const PixelTree& m_tree;
    const InspectNames& m_names;
    Json m_j;
};

}  // namespace

std::string inspect_prim_name(const InspectPrim& p, const InspectNames& names) {
    std::string text = (p.csg ? std::string("CSG node") : std::string(shape_kind_name(p.kind))) +
                       " " + std::to_string(p.prim) + " of instance " + std::to_string(p.instance);
    const SourceLoc* loc = prim_loc(p, names);
    if (loc && loc->file) text += " at " + loc->str();
    const std::string path = prim_path(p, names);
    if (!path.empty()) text += " (" + path + ")";
    return text;
}

std::string inspect_text(const PixelTree& tree, const RenderScene& scene,
                         const InspectNames& names) {
    TextWriter w(tree, scene, names);
    std::string head = "pixel " + std::to_string(tree.x) + "," + std::to_string(tree.y) +
                       ", sample " + std::to_string(tree.sample) + " of " +
                       std::to_string(tree.samples) + " at (" + num(tree.position.x) + " " +
                       num(tree.position.y) + ") in the pixel";
    if (tree.random) head += " (jittered; random numbers drawn)";
    w.ray(0, "");
    return head + "\n" + w.text() + "sample colour " + vec(tree.color) + "\npixel value " +
           vec(tree.pixel) + " (the mean of " + std::to_string(tree.samples) +
           (tree.samples == 1 ? " sample" : " samples") + ", linear)\n";
}

std::string inspect_json(const PixelTree& tree, const RenderScene&, const InspectNames& names) {
    return JsonWriter(tree, names).text();
}

}  // namespace rt
