// Box (spec §5): the six faces of [c - l/2, c + l/2]. The face of a point is the axis with the
// largest |q_i|/h_i (ties: x, then y, then z); each face's (u, v) reads upright and unmirrored
// from outside. Inside: |q_i| < l_i/2 on every axis.
#include "common.h"

namespace rt {

Bounds3 bounds(const Box& b) { return {b.centre - b.half, b.centre + b.half}; }

Bounds3 bounds(const Box& b, const Mat4& m) {
    Bounds3 out;
    for (int i = 0; i < 8; ++i) {
        const Vec3 corner =
            b.centre + Vec3((i & 1) ? b.half.x : -b.half.x, (i & 2) ? b.half.y : -b.half.y,
                            (i & 4) ? b.half.z : -b.half.z);
        out.extend(Vec3(m * glm::dvec4(corner, 1.0)));
    }
    return out;
}

// Face part numbers: axis * 2 + (1 if the + side).
static int face_of(const Vec3& q, const Vec3& h) {
    int axis = 0;
    double best = std::abs(q.x) / h.x;
    for (int a = 1; a < 3; ++a) {
        const double r = std::abs(q[a]) / h[a];
        if (r > best) best = r, axis = a;
    }
    return axis * 2 + (q[axis] > 0 ? 1 : 0);
}

// Spec §5's box face table: (u, v) of local point q on `face` (axis * 2 + 1 for the + side),
// h the half side lengths. Each face reads upright and unmirrored from outside.
static Vec2 box_face_uv(int face, const Vec3& q, const Vec3& h) {
    const Vec3 l = 2.0 * h;
    switch (face) {
        case 1:
            return {(h.z - q.z) / l.z, (q.y + h.y) / l.y};  // +x
        case 0:
            return {(q.z + h.z) / l.z, (q.y + h.y) / l.y};  // -x
        case 3:
            return {(q.x + h.x) / l.x, (h.z - q.z) / l.z};  // +y
        case 2:
            return {(q.x + h.x) / l.x, (q.z + h.z) / l.z};  // -y
        case 5:
            return {(q.x + h.x) / l.x, (q.y + h.y) / l.y};  // +z
        default:
            return {(h.x - q.x) / l.x, (q.y + h.y) / l.y};  // -z
    }
}

ShapeHits intersect(const Box& b, const Ray& ray, Interval t) {
    double t0 = -kInf, t1 = kInf;
    for (int a = 0; a < 3; ++a) {
        const double lo = b.centre[a] - b.half[a], hi = b.centre[a] + b.half[a];
        if (ray.d[a] == 0.0) {
            // Parallel to this slab: inside it or a miss (no 0 * inf).
            if (ray.o[a] < lo || ray.o[a] > hi) return {};
            continue;
        }
        const double inv = 1.0 / ray.d[a];
        double tn = (lo - ray.o[a]) * inv, tf = (hi - ray.o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        t0 = std::max(t0, tn);
        t1 = std::min(t1, tf);
        if (t0 > t1) return {};
    }
    ShapeHits h;
    if (t.contains(t0)) h.add(t0, -1);
    if (t.contains(t1) && t1 != t0) h.add(t1, -1);
    return h;
}

SurfacePoint surface_at(const Box& b, const Ray& ray, double t, int /*part*/, bool uv) {
    SurfacePoint sp;
    Vec3 q = ray.at(t) - b.centre;
    const int face = face_of(q, b.half);
    const int axis = face / 2;
    const double sign = (face & 1) ? 1.0 : -1.0;
    // Snap the point onto its face plane and clamp it into the face rectangle.
    q[axis] = sign * b.half[axis];
    for (int a = 0; a < 3; ++a) q[a] = std::clamp(q[a], -b.half[a], b.half[a]);
    sp.p = b.centre + q;
    sp.p_error = kAnalyticRetestMargin * gamma(4) * (glm::abs(b.centre) + glm::abs(q));
    sp.n_geometric = Vec3(0.0);
    sp.n_geometric[axis] = sign;
    sp.n_shading = sp.n_geometric;
    if (uv) sp.uv = box_face_uv(face, q, b.half);
    return sp;
}

bool inside(const Box& b, const Vec3& p_object) {
    const Vec3 q = glm::abs(p_object - b.centre);
    return q.x < b.half.x && q.y < b.half.y && q.z < b.half.z;
}

PreviewMesh tessellate(const Box& box, int /*detail*/) {
    MeshBuilder b;
    const Vec3 h = box.half;
    // The six faces of spec §5's table: axis, sign, and the face's (u, v) at local q.
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const double sign = side ? 1.0 : -1.0;
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            Vec3 n(0.0);
            n[axis] = sign;
            uint32_t v[4];
            for (int k = 0; k < 4; ++k) {
                Vec3 q(0.0);
                q[axis] = sign * h[axis];
                q[a1] = (k & 1) ? h[a1] : -h[a1];
                q[a2] = (k & 2) ? h[a2] : -h[a2];
                v[k] = b.vertex(box.centre + q, n, box_face_uv(axis * 2 + side, q, h));
            }
            b.triangle(v[0], v[1], v[3]);
            b.triangle(v[0], v[3], v[2]);
        }
    return std::move(b.mesh);
}

double csg_sign(const Box& b, const Vec3& p_object) {
    const Vec3 d = glm::abs(p_object - b.centre) - b.half;
    return std::max(d.x, std::max(d.y, d.z));
}

double csg_epsilon(const Box& b) {
    return kCsgTolerance *
           (glm::length(b.centre) + 2.0 * std::max(b.half.x, std::max(b.half.y, b.half.z)));
}

}  // namespace rt
