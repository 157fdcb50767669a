// Cone (spec §5): axis along +y, apex (cx, y1, cz), side sqrt(q_x^2 + q_z^2) = r (y1 - y)/h for
// y in [y0, y1], closed base disc at y0 (normal -y). Side normal
// normalize(h q_x/rho, r, h q_z/rho), (0, 1, 0) at the apex; uv as the cylinder's.
#include "rt/shapes.h"

namespace rt {

namespace {
enum Part { kSide = 0, kBase = 2 };
}

Bounds3 bounds(const Cone& c) {
    const Vec3 e(c.radius, 0.5 * c.height, c.radius);
    return {c.centre - e, c.centre + e};
}

Bounds3 bounds(const Cone& c, const Mat4& m) {
    // The hull of the base disc and the apex.
    Bounds3 b = transformed_disc_bounds(c.centre - Vec3(0, 0.5 * c.height, 0), c.radius, m);
    b.extend(Vec3(m * glm::dvec4(c.centre + Vec3(0, 0.5 * c.height, 0), 1.0)));
    return b;
}

ShapeHits intersect(const Cone& c, const Ray& ray, Interval t) {
    // Work relative to the apex: x^2 + z^2 = k^2 y^2 with y in [-h, 0], k = r/h.
    const Vec3 apex = c.centre + Vec3(0.0, 0.5 * c.height, 0.0);
    const Vec3 f = ray.o - apex;
    const Vec3& d = ray.d;
    const double k = c.radius / c.height, k2 = k * k;
    double cand[3];
    int part[3];
    int n = 0;
    auto side_ok = [&](double tr) {
        const double y = f.y + tr * d.y;
        return y >= -c.height && y <= 0.0;
    };
    const double a = d.x * d.x + d.z * d.z - k2 * d.y * d.y;
    const double b = f.x * d.x + f.z * d.z - k2 * f.y * d.y;
    const double cc = f.x * f.x + f.z * f.z - k2 * f.y * f.y;
    if (a != 0.0) {
        const double disc = b * b - a * cc;
        if (disc >= 0.0) {
            const double q = -(b + std::copysign(std::sqrt(disc), b));
            const double roots[2] = {q != 0.0 ? cc / q : 0.0, q / a};
            for (double tr : roots)
                if (side_ok(tr)) cand[n] = tr, part[n++] = kSide;
        }
    } else if (b != 0.0) {
        // Ray parallel to a generating line: one root of the linear equation.
        const double tr = -cc / (2.0 * b);
        if (side_ok(tr)) cand[n] = tr, part[n++] = kSide;
    }
    if (d.y != 0.0) {
        const double tb = (-c.height - f.y) / d.y;
        const double x = f.x + tb * d.x, z = f.z + tb * d.z;
        if (x * x + z * z <= c.radius * c.radius) cand[n] = tb, part[n++] = kBase;
    }
    return convex_hits(cand, part, n, t);
}

SurfacePoint surface_at(const Cone& c, const Ray& ray, double t, int part) {
    SurfacePoint sp;
    Vec3 q = ray.at(t) - c.centre;
    const double h2 = 0.5 * c.height, r = c.radius, h = c.height;
    if (part == kSide) {
        q.y = std::clamp(q.y, -h2, h2);
        const double rho = std::sqrt(q.x * q.x + q.z * q.z);
        const double rho_surface = r * (h2 - q.y) / h;
        if (rho > 0) {
            q.x *= rho_surface / rho, q.z *= rho_surface / rho;  // re-project onto the side
            sp.n_geometric = glm::normalize(Vec3(h * q.x / rho_surface, r, h * q.z / rho_surface));
        } else {
            sp.n_geometric = Vec3(0.0, 1.0, 0.0);  // the apex
        }
        if (rho_surface == 0.0) sp.n_geometric = Vec3(0.0, 1.0, 0.0);
        sp.uv = {azimuth(q) / (2 * kPi), (q.y + h2) / h};
    } else {
        q.y = -h2;
        sp.n_geometric = Vec3(0.0, -1.0, 0.0);
        sp.uv = disc_uv(false, q.x, q.z, r);
    }
    sp.p = c.centre + q;
    sp.p_error = kAnalyticRetestMargin * gamma(6) * (glm::abs(c.centre) + glm::abs(q));
    sp.n_shading = sp.n_geometric;
    return sp;
}

}  // namespace rt
