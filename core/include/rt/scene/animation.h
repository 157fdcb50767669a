// Spec §14: the value of one degree of freedom (DOF) of a key file at a render time t, the joint
// matrix J(t). Keys are placed cyclically over the loop (§14.3), turned into parameter vectors
// by a rotation parametrization with the window alignment of §14.5, interpolated component by
// component (§14.4), and turned back into a matrix (§14.6). Pure math: no files, no scene.
#pragma once

#include <string>
#include <vector>

#include "rt/util/error.h"
#include "rt/util/math.h"

namespace rt {

enum class Interpolation { Nearest, Linear, CatmullRom, BSpline };
enum class Rotation { Matrix, Closest, Euler, Log, Quaternion };
inline constexpr int kInterpolations = 4, kRotations = 5;  // the values 0 .. k - 1

/// The command-line names of spec §14.7 ("nearest", "catmull-rom", ..., "quaternion"); false for
/// another name. The defaults are CatmullRom and Quaternion.
bool parse_interpolation(const std::string& name, Interpolation* out);
bool parse_rotation(const std::string& name, Rotation* out);
const char* interpolation_name(Interpolation i);
const char* rotation_name(Rotation r);
/// Every name, in the enum's order, joined by `separator` ("nearest, linear, ..."): what a
/// message lists as accepted.
std::string interpolation_names(const std::string& separator = ", ");
std::string rotation_names(const std::string& separator = ", ");

/// One DOF of a key file: its keys (frame 0 first; the bottom row is ignored) over a loop of
/// `duration` seconds (> 0). `loc` is where errors and warnings at a time point are reported
/// (the first joint bound to it).
struct KeyTrack {
    std::string name;  // the DOF's name in its key file
    double duration = 1;
    std::vector<Mat4> keys;
    SourceLoc loc;
};

/// Spec §14.3: the key interval i and the fraction tau in [0, 1) of time t with n keys.
struct KeyPlace {
    int i = 0;
    double tau = 0;
};
KeyPlace place_key(double t, double duration, int n);

/// The closest rotation to a 3x3 matrix (spec §14.5): U diag(1, 1, det(U V^T)) V^T of its SVD.
Mat3 closest_rotation(const Mat3& a);

/// J(t) of spec §14.6: the interpolated rotation part as a matrix and the interpolated
/// translation, bottom row (0, 0, 0, 1). Throws SceneError at the track's loc when a quaternion
/// interpolates to (near) zero.
Mat4 joint_matrix(const KeyTrack& track, double t, Interpolation interpolation, Rotation rotation);

}  // namespace rt
