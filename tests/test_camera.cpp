// Camera frame and pixel mapping (spec §6), including the spec's numeric check and the default
// camera of §6.3.
#include "rt/render/camera.h"
#include "test_util.h"

namespace rt {
namespace {

TEST(Camera, SpecCheckPixelZeroZero) {
    // matthew-richard__cg2/test.ray's camera at 640x480.
    CameraPose d;
    d.position = Vec3(0, 10, 10);
    d.direction = Vec3(0, -1, -1);
    d.up = Vec3(0, 1, -1);
    d.half_height_angle_rad = 0.523;
    const Camera c = make_camera(d, 640, 480);
    EXPECT_VEC_NEAR(c.forward, Vec3(0, -0.707107, -0.707107), 1e-6);
    EXPECT_VEC_NEAR(c.right, Vec3(1, 0, 0), 1e-12);
    EXPECT_VEC_NEAR(c.up, Vec3(0, 0.707107, -0.707107), 1e-6);
    EXPECT_NEAR(c.tan_h, 0.576552, 1e-6);
    EXPECT_NEAR(c.tan_w, 0.768736, 1e-6);
    const Ray r = c.generate(0, 0, 0.5, 0.5);
    EXPECT_VEC_NEAR(r.d, Vec3(-0.553901, -0.216695, -0.803889), 1e-6);
    EXPECT_EQ(r.o, d.position);
    // Row 0 is the top of the view: its rays point up relative to the last row's.
    EXPECT_GT(glm::dot(c.generate(320, 0, 0.5, 0.5).d, c.up),
              glm::dot(c.generate(320, 479, 0.5, 0.5).d, c.up));
}

TEST(Camera, UpIsReorthogonalised) {
    CameraPose d;
    d.direction = Vec3(0, 0, -1);
    d.up = Vec3(0, 1, 1);
    const Camera c = make_camera(d, 100, 100);
    EXPECT_VEC_NEAR(c.up, Vec3(0, 1, 0), 1e-12);
}

TEST(Camera, DefaultCameraFramesTheWorld) {
    Bounds3 b{{-1, -2, -3}, {3, 2, 1}};
    const CameraPose d = default_camera(b, 640, 480);
    const double r = 0.5 * glm::length(b.diagonal());
    // phi = min(ha, atan(tan_w)) = pi/6 for a landscape image.
    EXPECT_VEC_NEAR(d.position, Vec3(1, 0, -1 + r / std::sin(kPi / 6)), 1e-12);
    EXPECT_EQ(d.direction, Vec3(0, 0, -1));
    EXPECT_NEAR(d.half_height_angle_rad, kPi / 6, 1e-15);
    // Portrait: atan(tan_w) is the smaller angle.
    const CameraPose p = default_camera(b, 100, 400);
    const double phi = std::atan(std::tan(kPi / 6) * 0.25);
    EXPECT_NEAR(p.position.z, -1 + r / std::sin(phi), 1e-9);
    // Empty scene: C = 0, R = 1.
    EXPECT_VEC_NEAR(default_camera(Bounds3{}, 640, 480).position, Vec3(0, 0, 2), 1e-12);
}

TEST(Camera, DefaultCameraUsesTightWorldBounds) {
    // A unit sphere rotated 45 degrees about y: its world box is still [-1, 1]^3, not the
    // rotated local box (which would be sqrt(2) wider).
    const RenderScene s = test::compile(
        "#material 0 0 0 0 0 0 1 1 1 0 0 0 1 0 0 0 1 -1 !!\n"
        "#group_begin 0.707107 0 0.707107 0  0 1 0 0  -0.707107 0 0.707107 0  0 0 0 1\n"
        "#shape_sphere 0 0 0 0 1\n#group_end\n");
    EXPECT_NEAR(s.world_bounds.lo.x, -1, 1e-6);
    EXPECT_NEAR(s.world_bounds.hi.z, 1, 1e-6);
    const Camera c = make_camera(s, 640, 480);
    EXPECT_NEAR(c.position.z, std::sqrt(3.0) / std::sin(kPi / 6), 1e-5);
}

}  // namespace
}  // namespace rt
