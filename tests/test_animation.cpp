// Spec §14's joint matrix J(t): key placement and looping (§14.3), the four interpolations
// (§14.4), the five rotation parametrizations with their window alignment (§14.5), against the
// whole table of worked example 4 (§14.8) and hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "rt/scene/animation.h"
#include "test_util.h"

namespace rt {
namespace {

constexpr double kDeg = kPi / 180;

// Column-major as a key file writes it (numbers 1-4 = column 1).
Mat4 key(std::initializer_list<double> v) {
    Mat4 m(1.0);
    int i = 0;
    for (double x : v) m[i / 4][i % 4] = x, ++i;
    return m;
}

// Worked example 4: one DOF, duration 2, four keys R_z(0, 90, 180, 270 degrees) with
// translations (0,0,0), (2,0,0), (2,2,0), (0,2,0).
KeyTrack example_four() {
    KeyTrack t;
    t.duration = 2;
    t.keys = {key({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}),
              key({0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1}),
              key({-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 2, 2, 0, 1}),
              key({0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 2, 0, 1})};
    return t;
}

struct Row {
    double t;
    Interpolation interpolation;
    Rotation rotation;
    double alpha_deg, scale;
    Vec3 translation;
};

TEST(Animation, WorkedExampleFourOfTheSpec) {
    using I = Interpolation;
    using R = Rotation;
    const Row rows[] = {
        {2.75, I::Nearest, R::Quaternion, 180, 1, {2, 2, 0}},
        {2.75, I::Nearest, R::Matrix, 180, 1, {2, 2, 0}},
        {2.75, I::Linear, R::Quaternion, 135, 1, {2, 1, 0}},
        {2.75, I::Linear, R::Euler, 135, 1, {2, 1, 0}},
        {2.75, I::Linear, R::Log, 135, 1, {2, 1, 0}},
        {2.75, I::Linear, R::Closest, 135, 1, {2, 1, 0}},
        {2.75, I::Linear, R::Matrix, 135, 0.707107, {2, 1, 0}},
        {2.75, I::CatmullRom, R::Quaternion, 135, 1, {2.25, 1, 0}},
        {2.75, I::CatmullRom, R::Matrix, 135, 0.883883, {2.25, 1, 0}},
        {2.75, I::BSpline, R::Quaternion, 135, 1, {1.916667, 1, 0}},
        {3.9, I::Nearest, R::Euler, 0, 1, {0, 0, 0}},
        {-0.1, I::Nearest, R::Quaternion, 0, 1, {0, 0, 0}},
        {3.9, I::Linear, R::Euler, -18, 1, {0, 0.4, 0}},
        {3.9, I::Linear, R::Log, -18, 1, {0, 0.4, 0}},
        {3.9, I::Linear, R::Quaternion, -17.086310, 1, {0, 0.4, 0}},
        {3.9, I::Linear, R::Closest, -14.036243, 1, {0, 0.4, 0}},
        {3.9, I::Linear, R::Matrix, -14.036243, 0.824621, {0, 0.4, 0}},
        {3.9, I::CatmullRom, R::Quaternion, -17.086310, 1, {-0.16, 0.304, 0}},
        {-0.1, I::CatmullRom, R::Quaternion, -17.086310, 1, {-0.16, 0.304, 0}},
        {3.9, I::CatmullRom, R::Euler, -18, 1, {-0.16, 0.304, 0}},
        {3.9, I::BSpline, R::Quaternion, -17.970791, 1, {0.173333, 0.568, 0}},
        {3.9, I::BSpline, R::Euler, -18, 1, {0.173333, 0.568, 0}},
    };
    const KeyTrack track = example_four();
    for (const Row& r : rows) {
        SCOPED_TRACE(std::string(interpolation_name(r.interpolation)) + ", " +
                     rotation_name(r.rotation) + " at t = " + std::to_string(r.t));
        const Mat4 j = joint_matrix(track, r.t, r.interpolation, r.rotation);
        const double alpha = std::atan2(j[0][1], j[0][0]) / kDeg;
        EXPECT_NEAR(std::remainder(alpha - r.alpha_deg, 360.0), 0.0, 1e-5);
        EXPECT_NEAR(glm::length(Vec3(j[0])), r.scale, 1e-6);
        EXPECT_VEC_NEAR(Vec3(j[3]), r.translation, 1e-6);
        EXPECT_EQ(j[0][3], 0.0);
        EXPECT_EQ(j[3][3], 1.0);
        if (r.rotation != Rotation::Matrix) {  // a rotation: orthonormal, det +1
            const Mat3 a(j);
            EXPECT_NEAR(glm::determinant(a), 1.0, 1e-12);
            EXPECT_NEAR(glm::dot(a[0], a[1]), 0.0, 1e-12);
        }
    }
}

TEST(Animation, TimeLoopsAndKeysSitAtTheirTimes) {
    const KeyPlace a = place_key(2.75, 2, 4);
    EXPECT_EQ(a.i, 1);
    EXPECT_DOUBLE_EQ(a.tau, 0.5);
    const KeyPlace b = place_key(-0.1, 2, 4);  // wraps to u = 0.95
    EXPECT_EQ(b.i, 3);
    EXPECT_NEAR(b.tau, 0.8, 1e-12);
    const KeyPlace c = place_key(4.0, 2, 4);  // a whole loop: key 0
    EXPECT_EQ(c.i, 0);
    EXPECT_EQ(c.tau, 0.0);
    EXPECT_EQ(place_key(std::nextafter(2.0, 0.0), 2, 4).i, 3);  // never N
    const KeyPlace one = place_key(123.4, 5, 1);
    EXPECT_EQ(one.i, 0);
    // Every interpolation but the B-spline passes through the keys; the B-spline approximates.
    const KeyTrack track = example_four();
    for (int k = 0; k < 4; ++k) {
        const double t = k * 0.5 + 2 * 3;  // key k, three loops later
        for (Interpolation i :
             {Interpolation::Nearest, Interpolation::Linear, Interpolation::CatmullRom}) {
            const Mat4 j = joint_matrix(track, t, i, Rotation::Quaternion);
            EXPECT_VEC_NEAR(Vec3(j[3]), Vec3(track.keys[static_cast<size_t>(k)][3]), 1e-12);
        }
        const Mat4 spline = joint_matrix(track, t, Interpolation::BSpline, Rotation::Quaternion);
        const Vec3 prev = Vec3(track.keys[static_cast<size_t>((k + 3) % 4)][3]);
        const Vec3 here = Vec3(track.keys[static_cast<size_t>(k)][3]);
        const Vec3 next = Vec3(track.keys[static_cast<size_t>((k + 1) % 4)][3]);
        EXPECT_VEC_NEAR(Vec3(spline[3]), (prev + 4.0 * here + next) / 6.0, 1e-12);
    }
}

// Keys stored with a quaternion sign flip or a 2 pi jump still move the short way.
TEST(Animation, AlignmentCrossesJumpsAndSeamsTheShortWay) {
    // Two keys about z: 170 and -170 degrees (20 degrees apart through 180).
    KeyTrack t;
    t.duration = 2;
    auto rz = [](double deg) {
        const double c = std::cos(deg * kDeg), s = std::sin(deg * kDeg);
        return key({c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    };
    t.keys = {rz(170), rz(-170)};
    for (Rotation r : {Rotation::Quaternion, Rotation::Euler, Rotation::Log}) {
        const Mat4 j = joint_matrix(t, 0.5, Interpolation::Linear, r);  // halfway: 180 degrees
        EXPECT_NEAR(std::abs(std::atan2(j[0][1], j[0][0])) / kDeg, 180.0, 1e-9) << rotation_name(r);
    }
    // The quaternion's principal value has w > 0; the window flips the next key's sign.
    KeyTrack q;
    q.duration = 1;
    q.keys = {rz(0), rz(359)};
    const Mat4 j = joint_matrix(q, 0.25, Interpolation::Linear, Rotation::Quaternion);
    EXPECT_NEAR(std::atan2(j[0][1], j[0][0]) / kDeg, -0.5, 1e-9);  // 0 -> -1 degree, not 359
}

TEST(Animation, ClosestRotationDropsScaleAndReflection) {
    const double c = std::cos(0.3), s = std::sin(0.3);
    const Mat3 scaled = Mat3(2.0) * Mat3(c, s, 0, -s, c, 0, 0, 0, 1);  // 2 R_z(0.3)
    const Mat3 r = closest_rotation(scaled);
    EXPECT_NEAR(std::atan2(r[0][1], r[0][0]), 0.3, 1e-12);
    EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
    const Mat3 mirror(1, 0, 0, 0, 1, 0, 0, 0, -1);  // det -1: the closest rotation has det +1
    EXPECT_NEAR(glm::determinant(closest_rotation(mirror)), 1.0, 1e-12);
    const Mat3 flat(1, 0, 0, 0, 1, 0, 0, 0, 0);  // singular: still a rotation
    EXPECT_NEAR(glm::determinant(closest_rotation(flat)), 1.0, 1e-12);
    EXPECT_EQ(closest_rotation(Mat3(0.0)), Mat3(1.0));
}

TEST(Animation, NamesAndAZeroQuaternion) {
    Interpolation i;
    Rotation r;
    EXPECT_TRUE(parse_interpolation("catmull-rom", &i));
    EXPECT_EQ(i, Interpolation::CatmullRom);
    EXPECT_TRUE(parse_rotation("log", &r));
    EXPECT_EQ(r, Rotation::Log);
    EXPECT_FALSE(parse_interpolation("cubic", &i));
    EXPECT_FALSE(parse_rotation("Quaternion", &r));
    // Under `matrix`, a key and its negation average to zero: a singular joint matrix, not an
    // error (the caller omits the shapes); quaternions never cancel after alignment.
    KeyTrack t;
    t.duration = 1;
    t.keys = {Mat4(1.0), key({-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1})};
    EXPECT_NEAR(
        glm::determinant(Mat3(joint_matrix(t, 0.25, Interpolation::Linear, Rotation::Matrix))), 0.0,
        1e-12);
    EXPECT_NO_THROW(joint_matrix(t, 0.25, Interpolation::Linear, Rotation::Quaternion));
}

}  // namespace
}  // namespace rt
