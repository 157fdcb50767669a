// Random numbers for rendering: a counter-based stream per (seed, pixel, sample index), so an
// image never depends on which thread traced which pixel, plus the few warps the stochastic
// features need.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "rt/util/math.h"

namespace rt {

class Rng {
public:
    Rng(uint64_t seed, uint64_t pixel, uint64_t sample)
        : m_state(mix(seed ^ mix(pixel * 0x9E3779B97F4A7C15ull + sample + 1))) {}

    /// Uniform in [0, 1).
    double uniform() {
        m_state = m_state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(mix(m_state) >> 11) * 0x1.0p-53;
    }

    /// Uniform on the unit disc (concentric mapping keeps strata compact).
    Vec2 disc() {
        const double a = 2 * uniform() - 1, b = 2 * uniform() - 1;
        if (a == 0 && b == 0) return Vec2(0.0);
        double r, phi;
        if (std::abs(a) > std::abs(b)) {
            r = a;
            phi = (kPi / 4) * (b / a);
        } else {
            r = b;
            phi = (kPi / 2) - (kPi / 4) * (a / b);
        }
        return {r * std::cos(phi), r * std::sin(phi)};
    }

    /// Uniform in the unit ball.
    Vec3 ball() {
        for (;;) {
            const Vec3 v(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
            if (glm::dot(v, v) <= 1.0) return v;
        }
    }

private:
    // SplitMix64's finaliser.
    static uint64_t mix(uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    uint64_t m_state;
};

/// The area-uniform map of [0,1)^2 onto the unit sphere of spec §13.9:
/// w(xi) = (sqrt(1 - z^2) cos(2 pi xi2), z, sqrt(1 - z^2) sin(2 pi xi2)), z = 1 - 2 xi1.
inline Vec3 uniform_sphere(const Vec2& xi) {
    const double z = 1.0 - 2.0 * xi.x;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * kPi * xi.y;
    return {r * std::cos(phi), z, r * std::sin(phi)};
}

/// A point of stratum k of an m x m grid over [0,1)^2, strata row-major (k = row * m + column,
/// the column along xi1), at `offset` within the stratum ((0.5, 0.5): its centre).
inline Vec2 stratum_point(int k, int m, const Vec2& offset) {
    return {(k % m + offset.x) / m, (k / m + offset.y) / m};
}

/// Two unit vectors completing n to an orthonormal frame.
inline void orthonormal_basis(const Vec3& n, Vec3* a, Vec3* b) {
    const Vec3 helper = std::abs(n.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    *a = glm::normalize(glm::cross(helper, n));
    *b = glm::cross(n, *a);
}

}  // namespace rt
