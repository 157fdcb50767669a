// Camera frame and pixel mapping (spec §6): ha is the half-height angle, pixel rows count from
// the top, and the default camera frames the world bounding box (spec §6.3).
#pragma once

#include "rt/render_scene.h"

namespace rt {

struct Camera {
    Vec3 position{0.0};
    Vec3 forward{0.0, 0.0, -1.0}, right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0};  // orthonormal
    double tan_w = 0.0, tan_h = 0.0;
    int width = 1, height = 1;

    /// The ray through pixel (i, j) at sample offset (sx, sy) in [0,1)^2; (0.5, 0.5) = centre.
    Ray generate(int i, int j, double sx, double sy) const {
        const Vec2 p = image_point(i, j, sx, sy);
        return {position, glm::normalize(forward + p.x * right + p.y * up)};
    }
    /// Spec §6.2's (x, y) of pixel (i, j) at sample offset (sx, sy): the ray's direction is
    /// normalize(forward + x right + y up).
    Vec2 image_point(int i, int j, double sx, double sy) const {
        return {(2.0 * (i + sx) / width - 1.0) * tan_w, (1.0 - 2.0 * (j + sy) / height) * tan_h};
    }
};

/// Builds the camera from the position, view direction, up vector and half-height angle.
Camera make_camera(const CameraPose& desc, int width, int height);
/// The scene's camera, or the default camera of spec §6.3 when the file has none.
Camera make_camera(const RenderScene& scene, int width, int height);
/// Spec §6.3's framing: the distance from which a sphere of `radius` fits the view, with
/// phi = min(ha, atan(tan_w)), tan_w = aspect * tan(ha).
double framing_distance(double radius, double half_height_angle_rad, double aspect);
/// The default camera of spec §6.3 for the given world bounds.
CameraPose default_camera(const Bounds3& world, int width, int height);

}  // namespace rt
