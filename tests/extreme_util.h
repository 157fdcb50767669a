// Helpers of the extreme-case suites (test_intersect.cpp, test_shapes_robust.cpp,
// test_scenes.cpp): scene text built from exact numbers, materials whose transmittance counts
// crossings, and random directions and rotations.
#pragma once

#include <array>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <random>

#include "rt/accel/intersect.h"
#include "test_util.h"

namespace rt::test {

inline std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
inline std::string vec(const Vec3& v) {
    std::string s = num(v.x);
    s += ' ';
    s += num(v.y);
    s += ' ';
    s += num(v.z);
    return s;
}
inline std::string group_begin(const Mat4& m) {
    std::string s = "#group_begin";
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            s += ' ';
            s += num(m[c][r]);
        }
    s += '\n';
    return s;
}
// V1 materials: opaque grey, and half transparent (transmittance counts crossings: 0.5^k).
inline const char* kOpaque =
    "#material 0 0 0  0.2 0.2 0.2  0.8 0.8 0.8  0 0 0  10  0 0 0  1 -1 !!\n";
inline const char* kHalf = "#material 0 0 0  0 0 0  1 1 1  0 0 0  1  0.5 0.5 0.5  1 -1 !!\n";

inline std::string vertex(const Vec3& p) {
    std::string s = "#vertex ";
    s += vec(p);
    s += " 0 0 0 0 0\n";
    return s;
}
inline std::string triangle(int a, int b, int c, int m = 0) {
    std::string s = "#shape_triangle ";
    s += std::to_string(m);
    s += ' ';
    s += std::to_string(a);
    s += ' ';
    s += std::to_string(b);
    s += ' ';
    s += std::to_string(c);
    s += '\n';
    return s;
}

inline Vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    for (;;) {
        const Vec3 v(g(rng), g(rng), g(rng));
        const double l = glm::length(v);
        if (l > 1e-6) return v / l;
    }
}
// A random unit direction with dot(d, n) >= min_cos (n unit).
inline Vec3 random_in_hemisphere(std::mt19937& rng, const Vec3& n, double min_cos) {
    for (;;) {
        Vec3 d = random_unit(rng);
        if (glm::dot(d, n) < 0) d = -d;
        if (glm::dot(d, n) >= min_cos) return d;
    }
}
inline Mat4 random_rotation(std::mt19937& rng) {
    std::normal_distribution<double> g;
    glm::dquat q(g(rng), g(rng), g(rng), g(rng));
    return Mat4(glm::mat3_cast(glm::normalize(q)));
}

}  // namespace rt::test
