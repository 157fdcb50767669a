// The ray tree as text a student reads against the formulas of spec §7, §8 and §13.9, and as
// JSON (docs/inspect.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ostream>
#include <sstream>
#include <string>
#include <string_view>

#include "rt/render/inspect.h"
#include "rt/shapes/shapes.h"
#include "rt/util/enum_names.h"
#include "rt/util/light_kind.h"
#include "rt/util/text.h"

namespace rt {

namespace {

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string vec(const Vec3& v) { return "(" + num(v.x) + " " + num(v.y) + " " + num(v.z) + ")"; }

// A spot light's cut-off angle in degrees, as the text and the JSON show it.
double cutoff_deg(const Light& l) { return l.cutoff_rad * 180.0 / kPi; }

const char* ray_kind_text(InspectRay::Kind k) {
    static constexpr const char* kText[] = {"camera", "reflected", "refracted"};  // Kind's order
    return enum_name(k, kText);
}

// A name from the scene as the text shows it: as it is, or, holding a control byte (which
// would move a terminal's cursor) or a byte that is not UTF-8, quoted and escaped as the
// parser's messages show it.
std::string shown(std::string_view s) { return printable_text(s) ? std::string(s) : quote(s); }

std::string material_name(int m, const InspectNames& names) {
    std::string text = "material " + std::to_string(m);
    if (names.material_names && m >= 0 && static_cast<size_t>(m) < names.material_names->size() &&
        !(*names.material_names)[static_cast<size_t>(m)].empty())
        text += " !" + shown((*names.material_names)[static_cast<size_t>(m)]) + "!";
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

// The text of one ray and its subtree, written out line by line; each line indented by `pad`
// spaces (a ray's lines two more than the ray, its children four, up to kMaxTextIndent).
class TextWriter {
public:
    TextWriter(std::ostream& out, const PixelTree& tree, const RenderScene& scene,
               const InspectNames& names)
        : m_out(out), m_tree(tree), m_scene(scene), m_names(names) {}

    void ray(int index, int pad) {
        const InspectRay& r = m_tree.rays[static_cast<size_t>(index)];
        line(pad, std::string(ray_kind_text(r.kind)) + " ray, depth " + std::to_string(r.depth) +
                      (r.kind == InspectRay::Kind::Camera ? "" : ", path weight " + vec(r.weight)) +
                      ": from " + vec(r.ray.o) + " along " + vec(r.ray.d));
        const int in = pad + 2;
        if (r.kind == InspectRay::Kind::Refracted)
            line(in,
                 "Snell: eta " + num(r.eta) + ", cos of the incident angle " + num(r.cos_incident));
        if (!r.hit) {
            line(in, "misses everything: background " + vec(r.color));
            return;
        }
        line(in, "hits " + inspect_prim_name(r.prim, m_names) + " at distance " + num(r.distance) +
                     ", point " + vec(r.point));
        line(in,
             material_name(r.material, m_names) + "; the ray " +
                 (r.entering ? "enters (meets the outward side)" : "leaves (meets the inside)"));
        if (r.material >= 0 && static_cast<size_t>(r.material) < m_scene.materials.size()) {
            const Material& m = m_scene.materials[static_cast<size_t>(r.material)];
            line(in + 2, "K_E " + vec(m.emissive) + ", K_A " + vec(m.ambient) + ", K_D " +
                             vec(m.diffuse) + ", K_S " + vec(m.specular) + ", n " +
                             num(m.specular_exponent) + ", T " + vec(m.transparent) + ", index " +
                             num(m.refractive_index) + (m.texture >= 0 ? ", textured" : ""));
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
        secondary(r, pad);
        // At kMaxTextIndent the children's lines come at the ray's own indentation, so its sum,
        // after them, names the ray it closes.
        line(in,
             (pad < kMaxTextIndent ? std::string("sum = ")
                                   : "sum of the depth " + std::to_string(r.depth) + " ray = ") +
                 vec(r.color));
    }

    void line(int pad, const std::string& s) {
        static const std::string spaces(kMaxTextIndent + 16, ' ');
        m_out.write(spaces.data(), std::min<std::streamsize>(pad, spaces.size()));
        m_out << s << '\n';
    }

private:
    void light(const InspectRay& r, const InspectLight& l, int pad) {
        std::string head = "light " + std::to_string(l.light) + " (" + light_kind_name(l.kind);
        if (l.kind != LightKind::Directional) head += " at " + vec(l.position);
        head += l.one_colour() ? ", I " + vec(l.diffuse)
                               : ", A_l " + vec(l.ambient) + ", D_l " + vec(l.diffuse) + ", S_l " +
                                     vec(l.specular);
        line(pad, head + ")");
        const int in = pad + 2;
        if (l.attenuated)
            line(in, "attenuation = 1 / (c0 " + num(l.constant_atten) + " + c1 " +
                         num(l.linear_atten) + " x d + c2 " + num(l.quadratic_atten) +
                         " x d^2), d " + num(l.distance) + " = 1 / " + num(l.denominator) + " = " +
                         num(1.0 / l.denominator));
        if (l.spot)
            line(in, "spot = cos a " + num(l.cos_angle) + " (a " +
                         num(std::acos(std::clamp(l.cos_angle, -1.0, 1.0)) * 180.0 / kPi) +
                         " deg, cut-off " + num(cutoff_deg(l)) + " deg) ^ exponent " +
                         num(l.spot_exponent) + " = " + num(l.spot_factor));
        line(in, "f_l = " + num(l.factor));
        if (l.ambient_term != Vec3(0.0))
            line(in, "ambient = K_A " + vec(r.k_a) + " x A_l " + vec(l.ambient) +
                         " x f_l = " + vec(l.ambient_term));
        if (l.facing_known) line(in, "L " + vec(l.to_light) + ", N.L " + num(l.n_dot_l));
        if (!l.no_shadow_ray.empty()) line(in, "no shadow ray: " + l.no_shadow_ray);
        if (l.shadow_tested && l.shadow_ray_count > 0) {
            line(in, "shadow S_l = " + vec(l.shadow) + " (" + std::to_string(l.shadow_ray_count) +
                         (l.shadow_ray_count == 1 ? " shadow ray" : " shadow rays") +
                         (l.shadow_ray_count > l.shadow_rays.size()
                              ? ", the first " + std::to_string(l.shadow_rays.size()) + " shown"
                              : "") +
                         ")");
            for (const InspectShadowRay& s : l.shadow_rays) shadow(r, s, in + 2);
        }
        if (l.terms_known) {
            if (l.one_colour()) {
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
            line(in, "adds S_l x (diffuse + specular) = " + vec(l.value) +
                         (l.note.empty() ? "" : ": " + l.note));
        } else {
            line(in, "adds nothing: " + l.note);
        }
    }

    void shadow(const InspectRay& r, const InspectShadowRay& s, int pad) {
        std::string to =
            std::isfinite(s.t_max) ? "to " + vec(s.ray.o + s.ray.d) : "along " + vec(s.ray.d);
        line(pad, "shadow ray from " + vec(s.ray.o) + " " + to + ": transmittance " +
                      vec(s.transmittance));
        if (s.offset == Vec3(0.0))
            line(pad + 2,
                 "origin offset 0 (the hit point's error bound is 0 there, spec §7.5): "
                 "the origin is the hit point " +
                     vec(s.hit) + " itself");
        else
            line(pad + 2, "origin offset " + vec(s.offset) + " (length " +
                              num(glm::length(s.offset)) + ", along " +
                              (glm::dot(s.offset, r.n_geometric) < 0.0 ? "-n_g" : "+n_g") +
                              ", spec §7.5): the origin is the hit point " + vec(s.hit) + " + it");
        for (const InspectOccluder& o : s.occluders)
            line(pad + 2, "meets " + inspect_prim_name(o.prim, m_names) + " at distance " +
                              num(o.distance) + ", " + material_name(o.material, m_names) + ", T " +
                              vec(o.transparent) +
                              (o.transparent == Vec3(0.0) ? " (opaque: blocked)" : ""));
    }

    // The reflected term, then the refracted one, each with the ray below it (recorded or not);
    // then the rays that were not traced. `pad` is the ray's own.
    void secondary(const InspectRay& r, int pad) {
        const int in = pad + 2;
        // Past kMaxTextIndent a child is not indented further (not even past its parent's
        // lines): its depth says where it is.
        const int below = std::min(pad + 4, kMaxTextIndent);
        for (const InspectRay::Kind kind :
             {InspectRay::Kind::Reflected, InspectRay::Kind::Refracted}) {
            const bool refl = kind == InspectRay::Kind::Reflected;
            const auto term = [&](const Vec3& colour) {
                line(in, std::string(refl ? "reflected = K_S " + vec(r.k_reflect)
                                          : "refracted = T " + vec(r.k_transmit)) +
                             " x the colour of the ray below " + vec(colour) + " = " +
                             vec(refl ? r.reflected : r.refracted));
            };
            for (int c : r.children) {
                const InspectRay& child = m_tree.rays[static_cast<size_t>(c)];
                if (child.kind != kind) continue;
                term(child.color);
                ray(c, below);
            }
            for (const InspectRay::NotRecorded& n : r.left_out) {
                if (n.kind != kind) continue;
                term(n.color);
                line(below, "left out (--inspect-depth " + std::to_string(m_tree.filter_depth) +
                                "): " + ray_kind_text(kind) + " ray, depth " +
                                std::to_string(n.depth) + ", path weight " + vec(n.weight) +
                                (n.rays > 1 ? ", with the " + std::to_string(n.rays - 1) +
                                                  (n.rays == 2 ? " ray below it" : " rays below it")
                                            : std::string()));
            }
            for (const InspectRay::NotRecorded& n : r.not_recorded) {
                if (n.kind != kind) continue;
                term(n.color);
                line(below, std::string("not recorded (past the tree's limits): ") +
                                ray_kind_text(kind) + " ray, depth " + std::to_string(n.depth) +
                                ", path weight " + vec(n.weight) +
                                (n.rays > 1 ? ", with the " + std::to_string(n.rays - 1) +
                                                  (n.rays == 2 ? " ray below it" : " rays below it")
                                            : std::string()));
            }
        }
        for (const InspectStop& s : r.stops)
            line(in, s.kind + " ray not traced: " + s.why + " (path weight " + vec(s.weight) + ")");
        if (r.lights_left_out > 0)
            line(in, std::to_string(r.lights_left_out) +
                         (r.lights_left_out == 1 ? " other light term" : " other light terms") +
                         " left out (--inspect-light " + std::to_string(m_tree.filter_light) +
                         "; the sum counts them)");
    }

    std::ostream& m_out;
    const PixelTree& m_tree;
    const RenderScene& m_scene;
    const InspectNames& m_names;
};

// A minimal JSON writer onto a stream: numbers round-trip, non-finite numbers are null, strings
// are strict UTF-8 (a byte that is not UTF-8 becomes U+FFFD; control characters and DEL are
// escaped).
class Json {
public:
    explicit Json(std::ostream& out) : m_out(out) {}

    void open(char c) {
        sep();
        m_out.put(c);
        m_first = true;
    }
    void close(char c) {
        m_out.put(c);
        m_first = false;
    }
    void key(const char* k) {
        sep();
        str(k);
        m_out.put(':');
        m_first = true;
    }
    void number(double v) {
        sep();
        if (!std::isfinite(v)) {
            m_out << "null";
            return;
        }
        // The shortest of 15 and 17 digits that reads back as v.
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.15g", v);
        if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
        m_out << buf;
    }
    void integer(long long v) {
        sep();
        m_out << v;
    }
    void boolean(bool b) {
        sep();
        m_out << (b ? "true" : "false");
    }
    void null() {
        sep();
        m_out << "null";
    }
    void string(std::string_view s) {
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
    void kv(const char* k, std::string_view v) { key(k), string(v); }
    void kv(const char* k, const std::string& v) { key(k), string(v); }
    void kv(const char* k, const char* v) { key(k), string(v); }
    void kb(const char* k, bool v) { key(k), boolean(v); }
    void ki(const char* k, long long v) { key(k), integer(v); }
    void end() { m_out.put('\n'); }

private:
    void sep() {
        if (!m_first) m_out.put(',');
        m_first = false;
    }
    void str(std::string_view s) {
        static constexpr char kHex[] = "0123456789abcdef";
        std::string o = "\"";
        for (size_t i = 0; i < s.size();) {
            const unsigned char c = static_cast<unsigned char>(s[i]);
            if (c == '"' || c == '\\') {
                o += '\\';
                o += static_cast<char>(c);
                ++i;
            } else if (c < 0x20 || c == 0x7F) {
                o += "\\u00";
                o += kHex[c >> 4];
                o += kHex[c & 15];
                ++i;
            } else if (c < 0x80) {
                o += static_cast<char>(c);
                ++i;
            } else if (const size_t n = utf8_length(s, i); n > 0) {
                o.append(s.substr(i, n));
                i += n;
            } else {
                o += "\\ufffd";  // not UTF-8: the replacement character, a byte for each
                ++i;
            }
        }
        o += '"';
        m_out << o;
    }
    std::ostream& m_out;
    bool m_first = true;
};

// The tree as JSON: the rays a flat array (each with its parent's and its children's indices),
// so that the nesting is the same whatever the depth of the tree.
class JsonWriter {
public:
    JsonWriter(std::ostream& out, const PixelTree& tree, const InspectNames& names)
        : m_j(out), m_tree(tree), m_names(names) {}

    void prim(const InspectPrim& p) {
        m_j.open('{');
        m_j.kv("shape", p.csg ? "csg" : shape_kind_name(p.kind));
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
        m_j.kv("kind", "shadow");
        m_j.ki("light", light);
        m_j.kv("origin", s.ray.o);
        m_j.kv("hit_point", s.hit);
        m_j.kv("origin_offset", s.offset);
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

    // "key": {what fill writes}, or "key": null when the term is absent.
    template <class F>
    void object_or_null(const char* key, bool present, F fill) {
        m_j.key(key);
        if (!present) return m_j.null();
        m_j.open('{');
        fill();
        m_j.close('}');
    }

    void light(const InspectLight& l) {
        m_j.open('{');
        m_j.ki("light", l.light);
        m_j.kv("kind", light_kind_name(l.kind));
        m_j.kb("one_colour", l.one_colour());
        m_j.kv("position", l.position);
        m_j.kv("ambient_colour", l.ambient);
        m_j.kv("colour", l.diffuse);
        m_j.kv("specular_colour", l.specular);
        object_or_null("attenuation", l.attenuated, [&] {
            m_j.kv("d", l.distance);
            m_j.kv("c0", l.constant_atten);
            m_j.kv("c1", l.linear_atten);
            m_j.kv("c2", l.quadratic_atten);
            m_j.kv("denominator", l.denominator);
            m_j.kv("value", 1.0 / l.denominator);
        });
        object_or_null("spot", l.spot, [&] {
            m_j.kv("cos_angle", l.cos_angle);
            m_j.kv("cutoff_deg", cutoff_deg(l));
            m_j.kv("exponent", l.spot_exponent);
            m_j.kv("value", l.spot_factor);
        });
        m_j.kv("factor", l.factor);
        m_j.kv("L", l.to_light);
        m_j.kv("n_dot_l", l.n_dot_l);
        m_j.kv("r_dot_l", l.r_dot_l);
        m_j.kv("highlight", l.highlight);
        m_j.kv("ambient", l.ambient_term);
        m_j.kv("diffuse", l.diffuse_term);
        m_j.kv("specular", l.specular_term);
        m_j.key("no_shadow_ray");
        if (l.no_shadow_ray.empty())
            m_j.null();
        else
            m_j.string(l.no_shadow_ray);
        object_or_null("shadow", l.shadow_tested, [&] {
            m_j.kv("value", l.shadow);
            m_j.ki("rays", static_cast<long long>(l.shadow_ray_count));
        });
        m_j.kv("value", l.value);
        m_j.kv("note", l.note);
        m_j.close('}');
    }

    // What a ray met: null on a miss.
    void hit(const InspectRay& r) {
        if (!r.hit) return m_j.null();
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
    }

    // The shading equation's terms and their sum (the background on a miss).
    void terms(const InspectRay& r) {
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
    }

    // The rays it did not trace, and why.
    void stops(const InspectRay& r) {
        m_j.open('[');
        for (const InspectStop& s : r.stops) {
            m_j.open('{');
            m_j.kv("kind", s.kind);
            m_j.kv("why", s.why);
            m_j.kv("weight", s.weight);
            m_j.close('}');
        }
        m_j.close(']');
    }

    // The rays it traced without recording them (past the tree's limits), or that a filter left
    // out.
    void not_recorded(const std::vector<InspectRay::NotRecorded>& list) {
        m_j.open('[');
        for (const InspectRay::NotRecorded& n : list) {
            m_j.open('{');
            m_j.kv("kind", ray_kind_text(n.kind));
            m_j.ki("depth", n.depth);
            m_j.kv("weight", n.weight);
            m_j.kv("color", n.color);
            m_j.ki("rays", static_cast<long long>(n.rays));
            m_j.close('}');
        }
        m_j.close(']');
    }

    void ray(int index) {
        const InspectRay& r = m_tree.rays[static_cast<size_t>(index)];
        m_j.open('{');
        m_j.ki("index", index);
        m_j.key("parent");
        if (r.parent >= 0)
            m_j.integer(r.parent);
        else
            m_j.null();
        m_j.kv("kind", ray_kind_text(r.kind));
        m_j.ki("depth", r.depth);
        m_j.kv("origin", r.ray.o);
        m_j.kv("direction", r.ray.d);
        m_j.kv("weight", r.weight);
        if (r.kind == InspectRay::Kind::Refracted) {
            m_j.kv("eta", r.eta);
            m_j.kv("cos_incident", r.cos_incident);
        }
        m_j.key("hit");
        hit(r);
        m_j.key("terms");
        terms(r);
        m_j.key("stopped");
        stops(r);
        m_j.key("shadow_rays");
        m_j.open('[');
        for (const InspectLight& l : r.lights)
            for (const InspectShadowRay& s : l.shadow_rays) shadow(s, l.light);
        m_j.close(']');
        m_j.key("children");
        m_j.open('[');
        for (int c : r.children) m_j.integer(c);
        m_j.close(']');
        m_j.key("not_recorded");
        not_recorded(r.not_recorded);
        m_j.key("left_out");
        not_recorded(r.left_out);
        m_j.ki("lights_left_out", static_cast<long long>(r.lights_left_out));
        m_j.close('}');
    }

    void write() {
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
        m_j.key("output");
        m_j.open('{');
        m_j.key("bytes");
        m_j.open('[');
        for (uint8_t b : m_tree.output.bytes) m_j.integer(b);
        m_j.close(']');
        m_j.kv("transfer", "floor(255 clamp(c, 0, 1) + 0.5)");
        m_j.close('}');
        const InspectCamera& c = m_tree.camera;
        m_j.key("camera");
        m_j.open('{');
        m_j.kb("from_file", c.from_file);
        m_j.kv("half_height_angle_deg", c.half_height_angle_rad * 180.0 / kPi);
        m_j.kv("tan_h", c.tan_h);
        m_j.kv("tan_w", c.tan_w);
        m_j.ki("width", c.width);
        m_j.ki("height", c.height);
        m_j.kv("position", c.position);
        m_j.kv("forward", c.forward);
        m_j.kv("right", c.right);
        m_j.kv("up", c.up);
        m_j.key("sample_offset");
        m_j.vec2(m_tree.position);
        m_j.key("image_point");
        m_j.vec2(c.image_point);
        m_j.close('}');
        m_j.key("filter");
        m_j.open('{');
        m_j.key("depth");
        if (m_tree.filter_depth > 0)
            m_j.integer(m_tree.filter_depth);
        else
            m_j.null();
        m_j.key("light");
        if (m_tree.filter_light >= 0)
            m_j.integer(m_tree.filter_light);
        else
            m_j.null();
        m_j.ki("rays_left_out", static_cast<long long>(m_tree.rays_left_out));
        m_j.close('}');
        m_j.ki("rays_recorded", static_cast<long long>(m_tree.rays.size()));
        m_j.ki("rays_not_recorded", static_cast<long long>(m_tree.rays_not_recorded));
        m_j.key("limits");
        m_j.open('{');
        m_j.ki("rays", static_cast<long long>(m_tree.max_rays));
        m_j.ki("records", static_cast<long long>(m_tree.max_records));
        m_j.close('}');
        m_j.key("rays");
        m_j.open('[');
        for (size_t i = 0; i < m_tree.rays.size(); ++i) ray(static_cast<int>(i));
        m_j.close(']');
        m_j.close('}');
        m_j.end();
    }

private:
    Json m_j;
    const PixelTree& m_tree;
    const InspectNames& m_names;
};

}  // namespace

std::string inspect_prim_name(const InspectPrim& p, const InspectNames& names) {
    std::string text = (p.csg ? std::string("CSG node") : std::string(shape_kind_name(p.kind))) +
                       " " + std::to_string(p.prim) + " of instance " + std::to_string(p.instance);
    const SourceLoc* loc = prim_loc(p, names);
    if (loc && loc->file) text += " at " + shown(loc->str());
    const std::string path = prim_path(p, names);
    if (!path.empty()) text += " (" + shown(path) + ")";
    return text;
}

void inspect_text(std::ostream& out, const PixelTree& tree, const RenderScene& scene,
                  const InspectNames& names) {
    TextWriter w(out, tree, scene, names);
    std::string head = "pixel " + std::to_string(tree.x) + "," + std::to_string(tree.y) +
                       ", sample " + std::to_string(tree.sample) + " of " +
                       std::to_string(tree.samples) + " at (" + num(tree.position.x) + " " +
                       num(tree.position.y) + ") in the pixel";
    if (tree.random) head += " (jittered; random numbers drawn)";
    w.line(0, head);
    const InspectCamera& c = tree.camera;
    w.line(0, std::string("camera (") + (c.from_file ? "the scene's" : "the default of spec §6.3") +
                  "): ha " + num(c.half_height_angle_rad * 180.0 / kPi) +
                  " deg (the half-height angle), tan_h = tan(ha) " + num(c.tan_h) +
                  ", tan_w = tan_h x " + std::to_string(c.width) + "/" + std::to_string(c.height) +
                  " " + num(c.tan_w));
    w.line(2, "at " + vec(c.position) + ", f " + vec(c.forward) + ", r " + vec(c.right) + ", up' " +
                  vec(c.up));
    w.line(2, "sample offset (sx sy) (" + num(tree.position.x) + " " + num(tree.position.y) +
                  "): x = (2 (i + sx) / w - 1) tan_w = " + num(c.image_point.x) +
                  ", y = (1 - 2 (j + sy) / h) tan_h = " + num(c.image_point.y) +
                  "; direction = normalize(f + x r + y up')");
    if (!tree.rays.empty()) w.ray(0, 0);
    if (tree.rays_not_recorded > 0)
        w.line(0, std::to_string(tree.rays_not_recorded) +
                      " more rays traced but not recorded: a tree records at most " +
                      std::to_string(tree.max_rays) + " rays and " +
                      std::to_string(tree.max_records) +
                      " light terms, shadow rays and surfaces on them (their colours count)");
    w.line(0, "sample colour " + vec(tree.color));
    w.line(0, "pixel value " + vec(tree.pixel) + " (the mean of " + std::to_string(tree.samples) +
                  (tree.samples == 1 ? " sample" : " samples") + ", linear)");
    if (tree.rays_left_out > 0)
        w.line(0, std::to_string(tree.rays_left_out) +
                      (tree.rays_left_out == 1 ? " ray" : " rays") + " deeper than level " +
                      std::to_string(tree.filter_depth) + " left out (--inspect-depth " +
                      std::to_string(tree.filter_depth) + "; their colours count)");
    const InspectOutput& o = tree.output;
    w.line(0, "written as 8 bits (" + std::to_string(o.bytes[0]) + " " +
                  std::to_string(o.bytes[1]) + " " + std::to_string(o.bytes[2]) +
                  ") = floor(255 x clamp(c, 0, 1) + 0.5) of each channel (spec §9: no gamma; the "
                  ".pfm output holds the linear value)");
}

std::string inspect_text(const PixelTree& tree, const RenderScene& scene,
                         const InspectNames& names) {
    std::ostringstream out;
    inspect_text(out, tree, scene, names);
    return std::move(out).str();
}

void inspect_json(std::ostream& out, const PixelTree& tree, const RenderScene&,
                  const InspectNames& names) {
    JsonWriter(out, tree, names).write();
}

std::string inspect_json(const PixelTree& tree, const RenderScene& scene,
                         const InspectNames& names) {
    std::ostringstream out;
    inspect_json(out, tree, scene, names);
    return std::move(out).str();
}

}  // namespace rt
