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
    } else {
        for (const LightNumber& n : kLightNumbers)
            if (what == n.name && n.of(l->kind)) {
                l->*n.field = std::clamp(a, n.lo, n.hi);
                return true;
            }
        return false;
    }
    return true;
}

}  // namespace rt::view
