#include "state/edits.h"

#include <algorithm>

#include "rt/compile/compile.h"
#include "rt/util/charconv.h"

namespace rt::view {

namespace {

// Two lists alike in the part `Part` (Light, Material) of each element: where they were read
// and a material's name aside.
template <class Part, class T>
bool same_parts(const std::vector<T>& a, const std::vector<T>& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                      [](const Part& x, const Part& y) { return x == y; });
}

}  // namespace

bool same_materials(const std::vector<Material>& a, const std::vector<Material>& b) {
    return same_parts<Material>(a, b);
}

bool same_materials(const std::vector<MaterialDesc>& a, const std::vector<MaterialDesc>& b) {
    return same_parts<Material>(a, b);
}

bool same_lights(const std::vector<LightDesc>& a, const std::vector<LightDesc>& b) {
    return same_parts<Light>(a, b);
}

bool same_edits(const SceneEdits& a, const SceneEdits& b) {
    return a.camera == b.camera && a.light_on == b.light_on && same_lights(a.lights, b.lights) &&
           same_materials(a.materials, b.materials);
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

void SceneEdits::set_light(size_t i, const LightDesc& l, bool on) {
    if (i >= lights.size()) return;
    lights[i] = l;
    light_on[i] = on ? 1 : 0;
}

void SceneEdits::add_light(LightKind kind) {
    // At the eye, along the view: what the user looks at is lit.
    LightDesc l;
    l.kind = kind;
    l.position = camera.eye();
    l.direction = camera.forward();
    if (kind == LightKind::Spot) l.cutoff_rad = 0.5;
    if (kind == LightKind::Sphere) l.radius = 0.05 * camera.distance;
    lights.push_back(l);
    light_on.push_back(1);
}

void SceneEdits::remove_light(size_t i) {
    if (i >= lights.size()) return;
    lights.erase(lights.begin() + static_cast<long>(i));
    light_on.erase(light_on.begin() + static_cast<long>(i));
}

void SceneEdits::keep_headlight() {
    lights.push_back(headlight_desc(camera));
    light_on.push_back(1);
}

void SceneEdits::frame_light(size_t i, const Bounds3& world) {
    if (i >= lights.size()) return;
    const LightDesc& l = lights[i];
    if (l.kind == LightKind::Directional) {  // look the way its light travels
        CameraDesc d = camera.desc();
        d.direction = l.direction;
        if (glm::length(glm::cross(glm::normalize(d.direction), d.up)) < 1e-6)
            d.up = Vec3(1, 0, 0);  // straight up or down
        camera.set_from(d, world);
    } else {
        camera.target = l.position;  // the light at the centre of the view
    }
}

void SceneEdits::set_material(size_t i, const MaterialDesc& m) {
    if (i < materials.size()) materials[i] = m;
}

void apply_edits(const SceneEdits& edits, const std::vector<MaterialOrigin>& origins,
                 bool headlight, int trace_w, int trace_h, RenderScene* scene,
                 RenderSettings* settings) {
    scene->camera = compile_camera(edits.camera.desc());
    scene->lights.clear();
    for (size_t i = 0; i < edits.lights.size(); ++i)
        if (edits.light_on[i]) scene->lights.push_back(compile_light(edits.lights[i]));
    if (headlight) scene->lights.push_back(compile_light(headlight_desc(edits.camera)));
    // One edited material per material of the scene (SceneEdits::materials), as compile_scene
    // compiles it.
    for (size_t k = 0; k < scene->materials.size(); ++k)
        scene->materials[k] = compile_material(edits.materials.at(k), origins.at(k));
    settings->width = trace_w;
    settings->height = trace_h;
}

LightDesc headlight_desc(const OrbitCamera& camera) {
    LightDesc l;
    l.kind = LightKind::Directional;
    l.direction = camera.forward();
    l.set_colour(Vec3(1.0));
    return l;
}

}  // namespace rt::view
