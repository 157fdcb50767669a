#include "rt/render/camera.h"

#include "rt/render/mistakes.h"

namespace rt {

namespace {

// The camera's own switches: none in a render, the camera's mistakes in a teaching render
// (rt/render/mistakes.h).
struct NoCameraMistakes {
    static bool has(Mistake) { return false; }
};

template <class Mistakes>
Camera camera_with(const CameraPose& desc, int width, int height, const Mistakes& mistakes) {
    Camera c;
    c.position = desc.position;
    c.forward = glm::normalize(desc.direction);
    c.right = glm::normalize(glm::cross(c.forward, desc.up));
    c.up = glm::cross(c.right, c.forward);  // up re-orthogonalised
    c.width = width;
    c.height = height;
    // Spec: ha is the half-height angle, in radians, not the full field of view (full-angle:
    // read as the full one; angle-degrees: converted as if in degrees; angle-on-width: applied
    // to the width).
    double ha = desc.half_height_angle_rad;
    if (mistakes.has(Mistake::AngleDegrees)) ha = ha * kPi / 180.0;
    if (mistakes.has(Mistake::FullAngle)) ha = 0.5 * ha;
    c.tan_h = std::tan(ha);
    c.tan_w = c.tan_h * static_cast<double>(width) / static_cast<double>(height);
    if (mistakes.has(Mistake::AngleOnWidth)) {
        c.tan_w = c.tan_h;
        c.tan_h = c.tan_w * static_cast<double>(height) / static_cast<double>(width);
    }
    return c;
}

}  // namespace

Camera make_camera(const CameraPose& desc, int width, int height) {
    return camera_with(desc, width, height, NoCameraMistakes{});
}

Camera make_camera(const CameraPose& desc, int width, int height, const MistakeSet& mistakes) {
    return camera_with(desc, width, height, mistakes);
}

double framing_distance(double radius, double half_height_angle_rad, double aspect) {
    const double tan_w = std::tan(half_height_angle_rad) * aspect;
    const double phi = std::min(half_height_angle_rad, std::atan(tan_w));
    return radius / std::sin(phi);
}

CameraPose default_camera(const Bounds3& world, int width, int height) {
    CameraPose d;
    d.half_height_angle_rad = kPi / 6;
    Vec3 centre(0.0);
    double radius = 1.0;
    if (!world.empty()) {
        centre = world.centre();
        radius = 0.5 * glm::length(world.diagonal());
        if (!(radius > 0.0)) centre = Vec3(0.0), radius = 1.0;  // spec §6.3: C = 0, R = 1
    }
    d.position = centre + Vec3(0.0, 0.0,
                               framing_distance(radius, d.half_height_angle_rad,
                                                static_cast<double>(width) / height));
    d.direction = Vec3(0.0, 0.0, -1.0);
    d.up = Vec3(0.0, 1.0, 0.0);
    return d;
}

Camera make_camera(const RenderScene& scene, int width, int height) {
    return make_camera(
        scene.camera ? *scene.camera : default_camera(scene.world_bounds, width, height), width,
        height);
}

}  // namespace rt
