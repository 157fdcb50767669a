// The viewer's camera controller (no GL): a file's camera survives the round trip, and orbit,
// look, pan, dolly, move and frame do what their names say.
#include "state/camera_controller.h"
#include "test_util.h"

namespace rt::view {
namespace {

TEST(CameraController, FileCameraRoundTrip) {
    CameraDesc c;
    c.position = Vec3(1, 2, 10);
    c.direction = Vec3(-0.1, -0.2, -1);
    c.half_height_angle_rad = 0.4;
    OrbitCamera o;
    o.set_from(c, Bounds3{{-1, -1, -1}, {1, 1, 1}});
    const CameraDesc d = o.desc();
    EXPECT_VEC_NEAR(d.position, c.position, 1e-12);
    EXPECT_VEC_NEAR(d.direction, glm::normalize(c.direction), 1e-12);
    EXPECT_EQ(d.half_height_angle_rad, 0.4);
}

// The viewer shows raytrace's framing for any up vector: rolled, straight down, straight up
// (once: the file's up vector was dropped, so these showed upright or turned 180 degrees).
TEST(CameraController, FileCameraKeepsItsUpVector) {
    struct Case {
        const char* name;
        Vec3 direction, up;
    };
    const Case cases[] = {{"rolled 45 degrees", {0, -0.3, -1}, {1, 1, 0}},
                          {"straight down", {0, -1, 0}, {0, 0, -1}},
                          {"straight down, turned", {0, -2, 0}, {1, 0, 1}},
                          {"straight up", {0, 1, 0}, {1, 0, 0}},
                          {"upside down", {0.2, 0, -1}, {0, -1, 0}}};
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        CameraDesc c;
        c.position = Vec3(0, 3, 9);
        c.direction = k.direction;
        c.up = k.up;
        c.half_height_angle_rad = 0.5;
        OrbitCamera o;
        o.set_from(c, Bounds3{{-1, -1, -1}, {1, 1, 1}});
        const Camera file = make_camera(compile_camera(c), 64, 48);
        const Camera view = o.camera(64, 48);
        EXPECT_VEC_NEAR(view.position, file.position, 1e-12);
        EXPECT_VEC_NEAR(view.forward, file.forward, 1e-12);
        EXPECT_VEC_NEAR(view.right, file.right, 1e-12);
        EXPECT_VEC_NEAR(view.up, file.up, 1e-12);
        // Orbiting from there turns about the target and keeps a proper frame.
        o.orbit(0.3, -0.2);
        const Camera turned = o.camera(64, 48);
        EXPECT_NEAR(glm::length(turned.position - o.target), o.distance, 1e-9);
        EXPECT_NEAR(glm::dot(turned.up, turned.forward), 0.0, 1e-12);
        EXPECT_NEAR(glm::length(turned.right), 1.0, 1e-12);
    }
}

TEST(CameraController, OrbitKeepsTheTargetAndDistance) {
    OrbitCamera o;
    o.target = Vec3(1, 2, 3);
    o.distance = 5;
    const Vec3 t = o.target;
    o.orbit(0.7, 0.3);
    EXPECT_VEC_NEAR(o.target, t, 0);
    EXPECT_NEAR(glm::length(o.eye() - t), 5, 1e-12);
    o.orbit(0, 10);  // pitch stops at the pole, where the frame is still proper
    EXPECT_EQ(o.pitch, kPi / 2);
    const Camera top = o.camera(4, 3);
    EXPECT_NEAR(glm::length(top.right), 1.0, 1e-12);
}

TEST(CameraController, LookKeepsTheEyeAndPanMovesBoth) {
    OrbitCamera o;
    o.distance = 3;
    const Vec3 eye = o.eye();
    o.look(0.5, -0.2);
    EXPECT_VEC_NEAR(o.eye(), eye, 1e-12);
    const Vec3 before_eye = o.eye(), before_target = o.target;
    o.pan(0.1, 0.0);
    EXPECT_VEC_NEAR(o.eye() - before_eye, o.target - before_target, 1e-12);
    EXPECT_GT(glm::length(o.target - before_target), 0.0);
    // Pan moves along the image plane: no motion along the view.
    EXPECT_NEAR(glm::dot(o.target - before_target, o.forward()), 0.0, 1e-12);
}

TEST(CameraController, DollyMoveAndFrame) {
    OrbitCamera o;
    o.distance = 10;
    o.dolly(0.5);
    EXPECT_EQ(o.distance, 5);
    o.move(Vec3(1, 0, 0));
    EXPECT_EQ(o.target, Vec3(1, 0, 0));
    o.frame(Bounds3{{-2, -2, -2}, {2, 2, 2}}, 4.0 / 3.0);
    EXPECT_EQ(o.target, Vec3(0.0));
    // Landscape: the box's bounding sphere (radius 2 sqrt 3) fits the half-height angle.
    EXPECT_NEAR(o.distance * std::sin(o.half_height), 2 * std::sqrt(3.0), 1e-12);
    // Portrait: the width limits, as for the default camera.
    o.frame(Bounds3{{-2, -2, -2}, {2, 2, 2}}, 0.25);
    const double phi = std::atan(std::tan(o.half_height) * 0.25);
    EXPECT_NEAR(o.distance * std::sin(phi), 2 * std::sqrt(3.0), 1e-12);
}

}  // namespace
}  // namespace rt::view
