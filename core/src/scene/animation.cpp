#include "rt/scene/animation.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "rt/util/enum_names.h"

namespace rt {

namespace {

constexpr double kTwoPi = 2 * kPi;

// A key's parameter vector P_k (spec §14.4): the rotation part, then the translation.
struct Param {
    std::array<double, 12> v{};
    int n = 0;  // rotation components: 9 (matrix, closest), 3 (euler, log), 4 (quaternion)
    Vec3 translation() const { return {v[n], v[n + 1], v[n + 2]}; }
};

// R(row, col) of a glm (column-major) matrix.
double at(const Mat3& m, int row, int col) { return m[col][row]; }

Mat3 rot_x(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return Mat3(1, 0, 0, 0, c, s, 0, -s, c);  // columns
}
Mat3 rot_y(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return Mat3(c, 0, -s, 0, 1, 0, s, 0, c);
}
Mat3 rot_z(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return Mat3(c, s, 0, -s, c, 0, 0, 0, 1);
}

// The unit quaternion (w, x, y, z) of a rotation (Shepperd's method), principal: w > 0, or
// w = 0 with its first non-zero of x, y, z positive.
std::array<double, 4> quaternion_of(const Mat3& r) {
    const double r00 = at(r, 0, 0), r11 = at(r, 1, 1), r22 = at(r, 2, 2);
    const double tr = r00 + r11 + r22;
    std::array<double, 4> q{};
    if (tr > 0) {
        const double s = 2 * std::sqrt(tr + 1);
        q = {s / 4, (at(r, 2, 1) - at(r, 1, 2)) / s, (at(r, 0, 2) - at(r, 2, 0)) / s,
             (at(r, 1, 0) - at(r, 0, 1)) / s};
    } else if (r00 > r11 && r00 > r22) {
        const double s = 2 * std::sqrt(1 + r00 - r11 - r22);
        q = {(at(r, 2, 1) - at(r, 1, 2)) / s, s / 4, (at(r, 0, 1) + at(r, 1, 0)) / s,
             (at(r, 0, 2) + at(r, 2, 0)) / s};
    } else if (r11 > r22) {
        const double s = 2 * std::sqrt(1 + r11 - r00 - r22);
        q = {(at(r, 0, 2) - at(r, 2, 0)) / s, (at(r, 0, 1) + at(r, 1, 0)) / s, s / 4,
             (at(r, 1, 2) + at(r, 2, 1)) / s};
    } else {
        const double s = 2 * std::sqrt(1 + r22 - r00 - r11);
        q = {(at(r, 1, 0) - at(r, 0, 1)) / s, (at(r, 0, 2) + at(r, 2, 0)) / s,
             (at(r, 1, 2) + at(r, 2, 1)) / s, s / 4};
    }
    double sign = q[0] > 0 ? 1 : q[0] < 0 ? -1 : 0;
    for (int k = 1; k < 4 && sign == 0; ++k) sign = q[k] > 0 ? 1 : q[k] < 0 ? -1 : 0;
    for (double& c : q) c *= sign == 0 ? 1 : sign;
    return q;
}

Mat3 matrix_of_quaternion(double w, double x, double y, double z) {
    return Mat3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y),  // column 0
                2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x),  // column 1
                2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y));
}

// Spec §14.5's principal values.
Param principal(const Mat4& key, Rotation rotation) {
    const Mat3 a(key);
    Param p;
    switch (rotation) {
        case Rotation::Matrix:
        case Rotation::Closest:
            for (int c = 0; c < 3; ++c)
                for (int r = 0; r < 3; ++r) p.v[static_cast<size_t>(p.n++)] = a[c][r];
            break;
        case Rotation::Euler: {
            const Mat3 r = closest_rotation(a);
            double e0, e1, e2;
            const double r20 = at(r, 2, 0);
            if (std::hypot(at(r, 0, 0), at(r, 1, 0)) < 1e-12) {  // gimbal lock
                const double s = r20 > 0 ? 1 : r20 < 0 ? -1 : 0;
                e2 = 0;
                e1 = -s * kPi / 2;
                e0 = std::atan2(-s * at(r, 0, 1), at(r, 1, 1));
            } else {
                e1 = std::asin(std::clamp(-r20, -1.0, 1.0));
                e2 = std::atan2(at(r, 1, 0), at(r, 0, 0));
                e0 = std::atan2(at(r, 2, 1), at(r, 2, 2));
            }
            p.v = {e0, e1, e2};
            p.n = 3;
            break;
        }
        case Rotation::Log: {
            const auto q = quaternion_of(closest_rotation(a));
            const Vec3 axis(q[1], q[2], q[3]);
            const double s = glm::length(axis);
            const Vec3 w = s > 0 ? axis / s * (2 * std::atan2(s, q[0])) : Vec3(0.0);
            p.v = {w.x, w.y, w.z};
            p.n = 3;
            break;
        }
        case Rotation::Quaternion: {
            const auto q = quaternion_of(closest_rotation(a));
            p.v = {q[0], q[1], q[2], q[3]};
            p.n = 4;
            break;
        }
    }
    const Vec3 t(key[3]);
    for (int k = 0; k < 3; ++k) p.v[static_cast<size_t>(p.n + k)] = t[k];
    return p;
}

// Spec §14.5's window alignment of p to the aligned previous key.
void align(Param* p, const Param& prev, Rotation rotation) {
    if (rotation == Rotation::Euler) {
        for (int k = 0; k < 3; ++k) {
            const double e = p->v[static_cast<size_t>(k)], before = prev.v[static_cast<size_t>(k)];
            p->v[static_cast<size_t>(k)] = e + kTwoPi * std::floor((before - e) / kTwoPi + 0.5);
        }
    } else if (rotation == Rotation::Log) {
        const Vec3 w(p->v[0], p->v[1], p->v[2]), before(prev.v[0], prev.v[1], prev.v[2]);
        double theta = glm::length(w);
        Vec3 axis = theta > 0 ? w / theta : Vec3(0.0);
        if (theta == 0) {
            if (before == Vec3(0.0)) return;
            axis = glm::normalize(before);
        }
        // Among axis * (theta + 2 pi m), the nearest to prev (the smallest m on a tie).
        const double along = glm::dot(before, axis);
        const double m = std::ceil((along - theta) / kTwoPi - 0.5);
        const Vec3 aligned = axis * (theta + kTwoPi * m);
        p->v[0] = aligned.x, p->v[1] = aligned.y, p->v[2] = aligned.z;
    } else if (rotation == Rotation::Quaternion) {
        double dot = 0;
        for (size_t k = 0; k < 4; ++k) dot += p->v[k] * prev.v[k];
        if (dot < 0)
            for (size_t k = 0; k < 4; ++k) p->v[k] = -p->v[k];
    }
}

// Spec §14.4, component by component over the window (P_{i-1}, P_i, P_{i+1}, P_{i+2}).
Param interpolate(const std::array<Param, 4>& w, double t, Interpolation interpolation) {
    Param out = w[1];
    const size_t count = static_cast<size_t>(w[1].n + 3);
    for (size_t k = 0; k < count; ++k) {
        const double p0 = w[0].v[k], p1 = w[1].v[k], p2 = w[2].v[k], p3 = w[3].v[k];
        double x = 0;
        switch (interpolation) {
            case Interpolation::Nearest:
                x = t < 0.5 ? p1 : p2;
                break;
            case Interpolation::Linear:
                x = (1 - t) * p1 + t * p2;
                break;
            case Interpolation::CatmullRom:
                x = 0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t * t +
                           (-p0 + 3 * p1 - 3 * p2 + p3) * t * t * t);
                break;
            case Interpolation::BSpline:
                x = ((1 - t) * (1 - t) * (1 - t) * p0 + (3 * t * t * t - 6 * t * t + 4) * p1 +
                     (-3 * t * t * t + 3 * t * t + 3 * t + 1) * p2 + t * t * t * p3) /
                    6;
                break;
        }
        out.v[k] = x;
    }
    return out;
}

// Spec §14.5's last column: the matrix of an interpolated rotation part.
Mat3 rotation_matrix(const Param& p, Rotation rotation, const SourceLoc& loc, double t) {
    switch (rotation) {
        case Rotation::Matrix:
        case Rotation::Closest: {
            Mat3 a;
            for (int c = 0; c < 3; ++c)
                for (int r = 0; r < 3; ++r) a[c][r] = p.v[static_cast<size_t>(c * 3 + r)];
            return rotation == Rotation::Matrix ? a : closest_rotation(a);
        }
        case Rotation::Euler:
            return rot_z(p.v[2]) * rot_y(p.v[1]) * rot_x(p.v[0]);
        case Rotation::Log: {
            const Vec3 w(p.v[0], p.v[1], p.v[2]);
            const double theta = glm::length(w);
            if (theta == 0) return Mat3(1.0);
            const Vec3 k = w / theta;
            const Mat3 kx(0, k.z, -k.y, -k.z, 0, k.x, k.y, -k.x, 0);  // [k]x, columns
            return Mat3(1.0) + std::sin(theta) * kx + (1 - std::cos(theta)) * (kx * kx);
        }
        case Rotation::Quaternion:
            break;
    }
    const double norm =
        std::sqrt(p.v[0] * p.v[0] + p.v[1] * p.v[1] + p.v[2] * p.v[2] + p.v[3] * p.v[3]);
    if (!(norm >= 1e-12))
        throw SceneError(loc, "the interpolated quaternion is zero at t = " + std::to_string(t) +
                                  " (keys turning by 180 degrees both ways?)");
    return matrix_of_quaternion(p.v[0] / norm, p.v[1] / norm, p.v[2] / norm, p.v[3] / norm);
}

// Eigen-decomposition of a symmetric 3x3 by cyclic Jacobi rotations: s = V diag(l) V^T.
void symmetric_eigen(Mat3 s, Mat3* v, Vec3* l) {
    Mat3 vec(1.0);
    for (int sweep = 0; sweep < 64; ++sweep) {
        const double off = s[1][0] * s[1][0] + s[2][0] * s[2][0] + s[2][1] * s[2][1];
        const double diag = s[0][0] * s[0][0] + s[1][1] * s[1][1] + s[2][2] * s[2][2];
        if (off <= 1e-36 * diag || off == 0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                const double apq = s[q][p];
                if (apq == 0) continue;
                const double theta = (s[q][q] - s[p][p]) / (2 * apq);
                const double t =
                    (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), sn = t * c;
                Mat3 j(1.0);  // the rotation in the (p, q) plane
                j[p][p] = c, j[q][q] = c, j[q][p] = sn, j[p][q] = -sn;
                s = glm::transpose(j) * s * j;
                vec = vec * j;
            }
    }
    *v = vec;
    *l = Vec3(s[0][0], s[1][1], s[2][2]);
}

}  // namespace

bool parse_interpolation(const std::string& name, Interpolation* out) {
    for (int i = 0; i < kInterpolations; ++i)
        if (name == interpolation_name(static_cast<Interpolation>(i)))
            return *out = static_cast<Interpolation>(i), true;
    return false;
}

bool parse_rotation(const std::string& name, Rotation* out) {
    for (int r = 0; r < kRotations; ++r)
        if (name == rotation_name(static_cast<Rotation>(r)))
            return *out = static_cast<Rotation>(r), true;
    return false;
}

std::string interpolation_names(const std::string& separator) {
    std::string s;
    for (int i = 0; i < kInterpolations; ++i)
        s += (i ? separator : "") + interpolation_name(static_cast<Interpolation>(i));
    return s;
}

std::string rotation_names(const std::string& separator) {
    std::string s;
    for (int r = 0; r < kRotations; ++r)
        s += (r ? separator : "") + rotation_name(static_cast<Rotation>(r));
    return s;
}

const char* interpolation_name(Interpolation i) {
    static constexpr const char* kNames[kInterpolations] = {"nearest", "linear", "catmull-rom",
                                                            "bspline"};
    return enum_name(i, kNames, "bspline");
}

const char* rotation_name(Rotation r) {
    static constexpr const char* kNames[kRotations] = {"matrix", "closest", "euler", "log",
                                                       "quaternion"};
    return enum_name(r, kNames, "quaternion");
}

KeyPlace place_key(double t, double duration, int n) {
    double u = t / duration - std::floor(t / duration);
    if (!(u < 1)) u = 0;   // rounding gave 1
    if (!(u >= 0)) u = 0;  // t not finite
    const double x = u * n;
    int i = static_cast<int>(std::floor(x));
    if (i >= n) i = n - 1;
    return {i, std::clamp(x - i, 0.0, std::nextafter(1.0, 0.0))};
}

Mat3 closest_rotation(const Mat3& a) {
    Mat3 v;
    Vec3 l;
    symmetric_eigen(glm::transpose(a) * a, &v, &l);
    // Columns by decreasing singular value.
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int x, int y) { return l[x] > l[y]; });
    const Vec3 v0 = v[order[0]], v1 = v[order[1]], v2 = v[order[2]];
    const Vec3 a0 = a * v0, a1 = a * v1;
    if (glm::length(a0) == 0) return Mat3(1.0);  // A = 0: no rotation to speak of
    // U with det +1 (u2 = u0 x u1); then R = u0 v0^T + u1 v1^T + det(V) u2 v2^T whatever the
    // sign of the smallest singular value (U diag(1, 1, det(U V^T)) V^T of spec §14.5).
    const Vec3 u0 = glm::normalize(a0);
    Vec3 u1 = a1 - glm::dot(u0, a1) * u0;
    if (glm::length(u1) <= 1e-15 * glm::length(a0)) {  // rank 1: any unit vector across u0
        const Vec3 m = glm::abs(u0);
        const Vec3 axis = m.x <= m.y && m.x <= m.z ? Vec3(1, 0, 0)
                          : m.y <= m.z             ? Vec3(0, 1, 0)
                                                   : Vec3(0, 0, 1);
        u1 = glm::normalize(glm::cross(u0, axis));
    } else {
        u1 = glm::normalize(u1);
    }
    const Vec3 u2 = glm::cross(u0, u1);
    const double det_v = glm::dot(glm::cross(v0, v1), v2) < 0 ? -1.0 : 1.0;
    return glm::outerProduct(u0, v0) + glm::outerProduct(u1, v1) +
           det_v * glm::outerProduct(u2, v2);
}

Mat4 joint_matrix(const KeyTrack& track, double t, Interpolation interpolation, Rotation rotation) {
    const int n = static_cast<int>(track.keys.size());
    if (n == 0) return Mat4(1.0);
    const KeyPlace at_t = place_key(t, track.duration, n);
    std::array<Param, 4> w;
    for (int k = 0; k < 4; ++k) {
        const int index = ((at_t.i + k - 1) % n + n) % n;  // cyclic keys
        w[static_cast<size_t>(k)] = principal(track.keys[static_cast<size_t>(index)], rotation);
        if (k > 0) align(&w[static_cast<size_t>(k)], w[static_cast<size_t>(k - 1)], rotation);
    }
    const Param p = interpolate(w, at_t.tau, interpolation);
    Mat4 j(rotation_matrix(p, rotation, track.loc, t));
    j[3] = glm::dvec4(p.translation(), 1.0);
    return j;
}

}  // namespace rt
