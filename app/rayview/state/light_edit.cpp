#include "state/light_edit.h"

#include <algorithm>

namespace rt::view {

bool edit_light(const std::string& what, double a, double b, double c, LightDesc* l) {
    const Vec3 rgb(a, b, c);
    if (what == "colour") {
        l->set_colour(rgb);
    } else if (what == "ambient") {
        l->ambient = rgb;
    } else if (what == "diffuse") {
        l->diffuse = rgb;
    } else if (what == "specular") {
        l->specular = rgb;
    } else if (what == "radius" && l->kind == LightKind::Sphere) {
        l->radius = std::max(0.0, a);
    } else {
        return false;
    }
    return true;
}

}  // namespace rt::view
