// Cylinder (spec §5): axis along +y, side q_x^2 + q_z^2 = r^2 for y in [y0, y1], closed by caps
// at y1 (top, normal +y) and y0 (bottom, normal -y). Side uv: (azimuth/2pi, (y - y0)/h); caps:
// top (q_x + r)/2r, (r - q_z)/2r; bottom (q_x + r)/2r, (q_z + r)/2r. Inside: q_x^2 + q_z^2 < r^2
// and |q_y| < h/2.
#include "common.h"

namespace rt {

namespace {
enum Part { kSide = 0, kTop = 1, kBottom = 2 };
}

Bounds3 bounds(const Cylinder& c) {
    const Vec3 e(c.radius, 0.5 * c.height, c.radius);
    return {c.centre - e, c.centre + e};
}

Bounds3 bounds(const Cylinder& c, const Mat4& m) {
    // The hull of the two cap discs.
    Bounds3 b = transformed_disc_bounds(c.centre + Vec3(0, 0.5 * c.height, 0), c.radius, m);
    b.extend(transformed_disc_bounds(c.centre - Vec3(0, 0.5 * c.height, 0), c.radius, m));
    return b;
}

ShapeHits intersect(const Cylinder& c, const Ray& ray, Interval t) {
    const Vec3 f = ray.o - c.centre;
    const double y0 = -0.5 * c.height, y1 = 0.5 * c.height;
    // Rounding of a computed height f.y + t d.y (and of the shape's own numbers): side roots and
    // cap points within it of the rim are kept (closed surfaces; see convex_hits).
    auto y_err = [&](double tr) {
        return gamma(4) * (std::abs(f.y) + std::abs(tr * ray.d.y) + std::abs(c.centre.y) + y1);
    };
    // Candidates: two side roots and the two cap planes; a convex shape has at most two hits.
    double cand[4];
    int part[4];
    int n = 0;
    const double a = ray.d.x * ray.d.x + ray.d.z * ray.d.z;
    if (a > 0.0) {
        const double b = f.x * ray.d.x + f.z * ray.d.z;
        // Stable discriminant as for the sphere (Haines et al., Ray Tracing Gems ch. 7), in the
        // xz plane: a (r - |l|)(r + |l|) with l the closest approach, no b^2 - ac cancellation.
        const double lx = f.x - (b / a) * ray.d.x, lz = f.z - (b / a) * ray.d.z;
        const double l = std::sqrt(lx * lx + lz * lz);
        double disc = a * (c.radius - l) * (c.radius + l);
        // A tangent ray (|l| = r up to the rounding of l) is a double root: it touches.
        if (disc < 0.0) {
            const double l_err =
                gamma(5) * (std::abs(f.x) + std::abs(f.z) +
                            std::abs(b / a) * (std::abs(ray.d.x) + std::abs(ray.d.z)));
            if (disc >= -2.0 * a * (c.radius + l) * l_err) disc = 0.0;
        }
        if (disc >= 0.0) {
            const double cc = f.x * f.x + f.z * f.z - c.radius * c.radius;
            const double q = -(b + std::copysign(std::sqrt(disc), b));
            const double roots[2] = {q != 0.0 ? cc / q : 0.0, q / a};
            for (double tr : roots) {
                const double y = f.y + tr * ray.d.y, e = y_err(tr);
                if (y >= y0 - e && y <= y1 + e) cand[n] = tr, part[n++] = kSide;
            }
        }
    }
    if (ray.d.y != 0.0) {
        for (int cap = 0; cap < 2; ++cap) {
            const double yc = cap == 0 ? y1 : y0;
            const double tc = (yc - f.y) / ray.d.y;
            const double x = f.x + tc * ray.d.x, z = f.z + tc * ray.d.z;
            const double ex =
                gamma(5) * (std::abs(f.x) + std::abs(tc * ray.d.x) + std::abs(c.centre.x));
            const double ez =
                gamma(5) * (std::abs(f.z) + std::abs(tc * ray.d.z) + std::abs(c.centre.z));
            if (within_disc(x, z, ex, ez, c.radius))
                cand[n] = tc, part[n++] = cap == 0 ? kTop : kBottom;
        }
    }
    return convex_hits(cand, part, n, t);
}

SurfacePoint surface_at(const Cylinder& c, const Ray& ray, double t, int part, bool uv) {
    SurfacePoint sp;
    Vec3 q = ray.at(t) - c.centre;
    const double h2 = 0.5 * c.height, r = c.radius;
    if (part == kSide) {
        const double rho = std::sqrt(q.x * q.x + q.z * q.z);
        if (rho > 0) q.x *= r / rho, q.z *= r / rho;  // re-project onto the side
        q.y = std::clamp(q.y, -h2, h2);
        sp.n_geometric = Vec3(q.x / r, 0.0, q.z / r);
        if (uv) sp.uv = {azimuth(q) / (2 * kPi), (q.y + h2) / c.height};
    } else {
        on_disc(part == kTop, part == kTop ? h2 : -h2, r, uv, q, sp);
    }
    return placed(sp, c.centre, q, gamma(5));
}

bool inside(const Cylinder& c, const Vec3& p_object) {
    const Vec3 q = p_object - c.centre;
    return q.x * q.x + q.z * q.z < c.radius * c.radius && std::abs(q.y) < 0.5 * c.height;
}

PreviewMesh tessellate(const Cylinder& c, int detail) {
    const int segments = std::max(3, detail);
    const double h2 = 0.5 * c.height;
    MeshBuilder b;
    b.grid(1, segments, [&](int i, int j, Vec3* p, Vec3* n, Vec2* uv) {
        const double u = static_cast<double>(j) / segments;
        Vec3 q = around(2 * kPi * u, c.radius);
        q.y = i ? h2 : -h2;
        *p = c.centre + q;
        *n = Vec3(q.x, 0, q.z) / c.radius;
        *uv = {u, static_cast<double>(i)};
    });
    b.disc(c.centre + Vec3(0, h2, 0), c.radius, true, segments);
    b.disc(c.centre - Vec3(0, h2, 0), c.radius, false, segments);
    return std::move(b.mesh);
}

double csg_sign(const Cylinder& c, const Vec3& p_object) {
    const Vec3 q = p_object - c.centre;
    return std::max(std::hypot(q.x, q.z) - c.radius, std::abs(q.y) - 0.5 * c.height);
}

double csg_epsilon(const Cylinder& c) {
    return kCsgTolerance * (glm::length(c.centre) + std::max(c.radius, c.height));
}

}  // namespace rt
