#include "rt/render/camera.h"

namespace rt {

Camera make_camera(const CameraPose& desc, int width, int height) {
    Camera c;
    c.position = desc.position;
    c.forward = glm::normalize(desc.direction);
    c.right = glm::normalize(glm::cross(c.forward, desc.up));
    c.up = glm::cross(c.right, c.forward);  // up re-orthogonalised
    c.width = width;
    c.height = height;
    // Spec: ha is the half-height angle, not the full field of view.
    c.tan_h = std::tan(desc.half_height_angle_rad);
    c.tan_w = c.tan_h * static_cast<double>(width) / static_cast<double>(height);
    return c;
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
