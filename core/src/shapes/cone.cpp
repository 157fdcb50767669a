// Cone (spec §5): axis along +y, apex (cx, y1, cz), side sqrt(q_x^2 + q_z^2) = r (y1 - y)/h for
// y in [y0, y1], closed base disc at y0 (normal -y). Side normal
// normalize(h q_x/rho, r, h q_z/rho), (0, 1, 0) at the apex; uv as the cylinder's.
// Inside: y0 < y < y1 and sqrt(q_x^2 + q_z^2) < r (y1 - y)/h.
#include "common.h"

namespace rt {

namespace {
enum ConePart { kConeSide = 0, kConeBase = 2 };

// The apex is a point of the solid that the side roots find only as an ill-conditioned double
// root (its error is the square root of the rounding). A ray passing the apex within the
// rounding of its own position touches it there (*ta): the apex is a candidate of its own. f: the
// ray's origin relative to the apex.
bool passes_apex(const Vec3& f, const Vec3& d, const Vec3& apex, double* ta) {
    const double dd = glm::dot(d, d);
    *ta = dd > 0.0 ? -glm::dot(f, d) / dd : 0.0;
    const Vec3 miss = f + *ta * d;
    auto l1 = [](const Vec3& v) { return std::abs(v.x) + std::abs(v.y) + std::abs(v.z); };
    const double err = gamma(7) * (l1(f) + std::abs(*ta) * l1(d) + l1(apex));
    return glm::dot(miss, miss) <= err * err;
}
}  // namespace

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
    // Work relative to the apex: Q(p) = x^2 + z^2 - k^2 y^2 = 0 with y in [-h, 0], k = r/h.
    const Vec3 apex = c.centre + Vec3(0.0, 0.5 * c.height, 0.0);
    const Vec3 f = ray.o - apex;
    const Vec3& d = ray.d;
    const double h = c.height, k = c.radius / c.height, k2 = k * k;
    auto quad = [&](const Vec3& p) { return p.x * p.x + p.z * p.z - k2 * p.y * p.y; };
    double cand[5];
    int part[5];
    int n = 0;
    // Side roots keep y in [-h, 0] up to the rounding of y (and of the apex): a ray through the
    // apex or the base rim is never lost between the side and the base (see convex_hits).
    auto side_ok = [&](double tr) {
        const double y = f.y + tr * d.y;
        const double e = gamma(4) * (std::abs(f.y) + std::abs(tr * d.y) + std::abs(apex.y) + h);
        return y >= -h - e && y <= e;
    };
    // Q(f + t d) = a t^2 + 2 b t + cc.
    const double a = quad(d);
    const double b = f.x * d.x + f.z * d.z - k2 * f.y * d.y;
    const double cc = quad(f);
    const double a_scale = d.x * d.x + d.z * d.z + k2 * d.y * d.y;
    if (std::abs(a) > 1e-6 * a_scale) {
        // Stable discriminant (Haines et al., Ray Tracing Gems ch. 7, for any quadric):
        // b^2 - a cc = -a Q(l), l = f - (b/a) d the point where Q is stationary along the line,
        // which avoids the cancellation of b^2 - a cc for thin or distant cones.
        const double s = b / a;
        const Vec3 l = f - s * d;
        double disc = -a * quad(l);
        // A double root within rounding (a tangent, or a ray through the apex: Q restricted to a
        // line through the apex is a (t - t_apex)^2) touches the cone; the known miss of grazing
        // apex rays came from this rounding turning the discriminant negative.
        if (disc < 0.0) {
            const Vec3 l_err =
                gamma(4) * (glm::abs(f) + std::abs(s) * glm::abs(d) + glm::abs(apex));
            const double q_err = 2.0 * (std::abs(l.x) * l_err.x + std::abs(l.z) * l_err.z +
                                        k2 * std::abs(l.y) * l_err.y) +
                                 l_err.x * l_err.x + l_err.z * l_err.z + k2 * l_err.y * l_err.y +
                                 gamma(3) * (l.x * l.x + l.z * l.z + k2 * l.y * l.y);
            if (disc >= -std::abs(a) * q_err * (1.0 + gamma(2))) disc = 0.0;
        }
        if (disc >= 0.0) {
            const double q = -(b + std::copysign(std::sqrt(disc), b));
            const double roots[2] = {q != 0.0 ? cc / q : -s, q / a};
            for (double tr : roots)
                if (side_ok(tr)) cand[n] = tr, part[n++] = kConeSide;
        }
    } else if (a != 0.0 || b != 0.0) {
        // Nearly parallel to a generating line: a t^2 + 2 b t + cc with a tiny a. The root that
        // stays finite is -cc / (b + sign(b) sqrt(b^2 - a cc)); the other one is far away.
        const double disc = b * b - a * cc;
        if (disc >= 0.0) {
            const double q = -(b + std::copysign(std::sqrt(disc), b));
            if (q != 0.0 && side_ok(cc / q)) cand[n] = cc / q, part[n++] = kConeSide;
            if (a != 0.0 && side_ok(q / a)) cand[n] = q / a, part[n++] = kConeSide;
        }
    } else if (cc == 0.0 && d.y != 0.0) {
        // The line lies on the cone (a = b = cc = 0): it touches from the apex down to the base.
        const double ta = -f.y / d.y;
        cand[n] = ta, part[n++] = kConeSide;
    }
    if (double ta = 0.0; passes_apex(f, d, apex, &ta)) cand[n] = ta, part[n++] = kConeSide;
    if (d.y != 0.0) {
        const double tb = (-c.height - f.y) / d.y;
        const double x = f.x + tb * d.x, z = f.z + tb * d.z;
        const double ex = gamma(5) * (std::abs(f.x) + std::abs(tb * d.x) + std::abs(apex.x));
        const double ez = gamma(5) * (std::abs(f.z) + std::abs(tb * d.z) + std::abs(apex.z));
        if (within_disc(x, z, ex, ez, c.radius)) cand[n] = tb, part[n++] = kConeBase;
    }
    return convex_hits(cand, part, n, t);
}

SurfacePoint surface_at(const Cone& c, const Ray& ray, double t, int part, bool uv) {
    SurfacePoint sp;
    Vec3 q = ray.at(t) - c.centre;
    const double h2 = 0.5 * c.height, r = c.radius, h = c.height;
    if (part == kConeSide) {
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
        if (uv) sp.uv = {azimuth(q) / (2 * kPi), (q.y + h2) / h};
    } else {
        on_disc(false, -h2, r, uv, q, sp);
    }
    return placed(sp, c.centre, q, gamma(6));
}

bool inside(const Cone& c, const Vec3& p_object) {
    // Below the apex, above the base, and nearer the axis than the side at that height.
    const Vec3 q = p_object - c.centre;
    const double h2 = 0.5 * c.height;
    if (!(q.y > -h2 && q.y < h2)) return false;
    const double rho_side = c.radius * (h2 - q.y) / c.height;
    return q.x * q.x + q.z * q.z < rho_side * rho_side;
}

PreviewMesh tessellate(const Cone& c, int detail) {
    const int segments = std::max(3, detail);
    const double h2 = 0.5 * c.height, r = c.radius, h = c.height;
    MeshBuilder b;
    // Side: base ring to apex. The apex is one vertex per segment, with that segment's normal,
    // so the shading stays smooth around the axis.
    b.grid(1, segments, [&](int i, int j, Vec3* p, Vec3* n, Vec2* uv) {
        // The apex vertex j closes the segment (j - 1, j): it takes that segment's middle.
        const double u = (i ? (j - 0.5) : j) / static_cast<double>(segments);
        const double phi = 2 * kPi * u;
        Vec3 q = around(phi, i ? 0.0 : r);
        q.y = i ? h2 : -h2;
        *p = c.centre + q;
        const Vec3 dir = around(phi, 1.0);  // unit horizontal direction
        *n = glm::normalize(Vec3(h * dir.x, r, h * dir.z));
        *uv = {u, static_cast<double>(i)};
    });
    b.disc(c.centre - Vec3(0, h2, 0), r, false, segments);
    return std::move(b.mesh);
}

double csg_sign(const Cone& c, const Vec3& p_object) {
    const Vec3 q = p_object - c.centre;
    const double side = std::hypot(q.x, q.z) - c.radius * (0.5 * c.height - q.y) / c.height;
    return std::max(side, std::abs(q.y) - 0.5 * c.height);
}

double csg_epsilon(const Cone& c) {
    return kCsgTolerance * (glm::length(c.centre) + std::max(c.radius, c.height));
}

}  // namespace rt
