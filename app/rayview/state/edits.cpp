#include "state/edits.h"

#include "rt/util/charconv.h"

namespace rt::view {

bool same_materials(const std::vector<Material>& a, const std::vector<Material>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        const Material &x = a[i], &y = b[i];
        if (x.emissive != y.emissive || x.ambient != y.ambient || x.diffuse != y.diffuse ||
            x.specular != y.specular || x.specular_exponent != y.specular_exponent ||
            x.transparent != y.transparent || x.refractive_index != y.refractive_index ||
            x.texture != y.texture)
            return false;
    }
    return true;
}

std::vector<MaterialOrigin> material_origins(const SceneDesc& desc) {
    std::vector<MaterialOrigin> out;
    int first_texture = 0;
    for (size_t f = 0; f < desc.files.size(); ++f) {
        const FileDesc& file = desc.files[f];
        const int textures = static_cast<int>(file.textures.size());
        for (size_t m = 0; m < file.materials.size(); ++m)
            out.push_back({static_cast<int>(f), static_cast<int>(m), first_texture, textures});
        first_texture += textures;
    }
    return out;
}

bool same_lights(const std::vector<LightDesc>& a, const std::vector<LightDesc>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        const LightDesc &x = a[i], &y = b[i];
        if (x.kind != y.kind || x.ambient != y.ambient || x.diffuse != y.diffuse ||
            x.specular != y.specular || x.position != y.position || x.direction != y.direction ||
            x.constant_atten != y.constant_atten || x.linear_atten != y.linear_atten ||
            x.quadratic_atten != y.quadratic_atten || x.cutoff_rad != y.cutoff_rad ||
            x.spot_exponent != y.spot_exponent || x.radius != y.radius)
            return false;
    }
    return true;
}

void keep_window_settings(ViewSettings* s, const ViewSettings& window) {
    s->render.width = window.render.width;
    s->render.height = window.render.height;
    s->panel_w = window.panel_w;
    s->ui_scale = window.ui_scale;
    s->show_panel = window.show_panel;
}

double float_as_decimal(float f) {
    char buf[32];
    const auto r = to_chars_shortest(buf, buf + sizeof buf, f);
    double d = f;
    from_chars_double(buf, r.ptr, d);
    return d;
}

LightDesc headlight_desc(const OrbitCamera& camera) {
    LightDesc l;
    l.kind = LightKind::Directional;
    l.direction = camera.forward();
    l.set_colour(Vec3(1.0));
    return l;
}

}  // namespace rt::view
