// The viewer's camera controller: orbit about a target (yaw about +y from -z, pitch, and a roll
// about the view that orbiting keeps), pan, dolly, fly and frame, turned into the tracer's
// CameraDesc. No GL, no input handling: the
// viewer maps mouse and keys onto these calls, and the tests drive them directly.
#pragma once

#include <algorithm>
#include <cmath>

#include "rt/compile/compile.h"
#include "rt/render/camera.h"

namespace rt::view {

struct OrbitCamera {
    Vec3 target{0.0};
    double distance = 1, yaw = 0, pitch = 0;  // radians; yaw about +y, from -z
    double roll = 0;  // radians: the up vector turned about the view, towards the right
    double half_height = kPi / 6;
    bool operator==(const OrbitCamera&) const = default;

    /// Takes a file's camera: same eye, view direction, up vector and angle (the framing
    /// raytrace shows); the target lies along the view at the distance of the scene's centre.
    void set_from(const CameraDesc& c, const Bounds3& world) {
        const Vec3 d = glm::normalize(c.direction);
        const Vec3 centre = world.empty() ? c.position + d : world.centre();
        distance = glm::dot(centre - c.position, d);
        if (!(distance > 1e-6))
            distance = world.empty() ? 1.0 : std::max(1e-6, glm::length(world.diagonal()));
        target = c.position + distance * d;
        pitch = std::asin(std::clamp(d.y, -1.0, 1.0));
        // The up vector as make_camera() makes it: orthogonal to the view.
        const Vec3 up = glm::cross(glm::normalize(glm::cross(d, c.up)), d);
        if (std::abs(d.y) > 1.0 - 1e-12)  // along the y axis: the yaw turns the up vector
            yaw = d.y < 0 ? std::atan2(up.x, -up.z) : std::atan2(-up.x, up.z);
        else
            yaw = std::atan2(d.x, -d.z);
        roll = 0;
        const Vec3 u0 = up_vector(), r0 = glm::cross(forward(), u0);
        roll = std::atan2(glm::dot(up, r0), glm::dot(up, u0));
        half_height = c.half_height_angle_rad;
    }
    Vec3 forward() const {
        return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw)};
    }
    /// The up vector: the view's turn upwards in pitch (defined at the poles too), rolled.
    Vec3 up_vector() const {
        const Vec3 u0(-std::sin(pitch) * std::sin(yaw), std::cos(pitch),
                      std::sin(pitch) * std::cos(yaw));
        if (roll == 0) return u0;
        return std::cos(roll) * u0 + std::sin(roll) * glm::cross(forward(), u0);
    }
    Vec3 eye() const { return target - distance * forward(); }
    CameraDesc desc() const {
        CameraDesc c;
        c.direction = forward();
        c.position = eye();
        c.up = up_vector();
        c.half_height_angle_rad = half_height;
        return c;
    }
    /// The camera the renderer traces from this view, for an image of `w` x `h` pixels.
    Camera camera(int w, int h) const { return make_camera(compile_camera(desc()), w, h); }
    /// Orbit: turn about the target (radians), about +y and then up or down as far as the poles;
    /// the roll stays.
    void orbit(double d_yaw, double d_pitch) {
        yaw += d_yaw;
        pitch = std::clamp(pitch + d_pitch, -kPi / 2, kPi / 2);
    }
    /// Look around from the eye (fly): the eye stays, the target moves.
    void look(double d_yaw, double d_pitch) {
        const Vec3 e = eye();
        orbit(d_yaw, d_pitch);
        target = e + distance * forward();
    }
    /// Pan by a fraction of the view's height in the image plane (right, up).
    void pan(double right, double up) {
        const Camera cam = camera(1, 1);
        const double h = 2 * distance * cam.tan_h;
        target += (right * h) * cam.right + (up * h) * cam.up;
    }
    /// Dolly: scale the distance to the target.
    void dolly(double factor) { distance = std::max(1e-9, distance * factor); }
    /// Move eye and target together (fly), in world units.
    void move(const Vec3& delta) { target += delta; }
    /// Frame the box as the default camera does (spec §6.3): target its centre, back off until
    /// its bounding sphere fits the view of this aspect ratio.
    void frame(const Bounds3& b, double aspect) {
        if (b.empty()) return;
        target = b.centre();
        distance = framing_distance(0.5 * glm::length(b.diagonal()), half_height, aspect);
    }
};

}  // namespace rt::view
