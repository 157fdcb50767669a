// The five shapes of the format in their local frame (spec §5), each with the same small API:
// bounds, intersect (every hit in an interval, nearest first) and surface_at (point, outward
// geometric normal, shading normal, texture coordinates, and a bound on the point's error).
#pragma once

#include <cstdint>

#include "rt/util/math.h"

namespace rt {

enum class ShapeKind : uint8_t { Sphere, Box, Cylinder, Cone, Triangle };
const char* shape_kind_name(ShapeKind k);

struct Sphere {
    Vec3 centre{0.0};
    double radius = 1.0;
};
struct Box {
    Vec3 centre{0.0};
    Vec3 half{0.5};  // half side lengths (the file gives full lengths)
};
/// Axis along +y, from centre.y - height/2 to centre.y + height/2, closed by two caps.
struct Cylinder {
    Vec3 centre{0.0};
    double radius = 1.0, height = 1.0;
};
/// Axis along +y: base disc (closed) at centre.y - height/2, apex at centre.y + height/2.
struct Cone {
    Vec3 centre{0.0};
    double radius = 1.0, height = 1.0;
};
struct Triangle {
    Vec3 p0{0.0}, p1{0.0}, p2{0.0};
};
/// Per-vertex attributes of a triangle, kept apart from the positions the traversal reads.
struct TriangleAttribs {
    Vec3 n[3]{Vec3(0.0), Vec3(0.0), Vec3(0.0)};
    Vec2 uv[3]{Vec2(0.0), Vec2(0.0), Vec2(0.0)};
    bool has_normals = false;  // all three vertices have non-zero normals
};

/// Up to two hits of a convex shape inside an interval, nearest first. `part` tells which
/// surface piece was hit (box face, cylinder side or cap, ...), for surface_at.
struct ShapeHits {
    int count = 0;
    double t[2] = {0.0, 0.0};
    int part[2] = {0, 0};
    void add(double tt, int p) {
        t[count] = tt;
        part[count] = p;
        ++count;
    }
};

/// Analytic shapes are tested in double, and the test of a ray spawned at a hit carries an
/// error of the same order as the hit point's own (a quadratic's constant term near zero), so
/// their point error bounds are widened by this factor: the spawned ray then starts clearly
/// outside the surface's error band at every scale.
inline constexpr double kAnalyticRetestMargin = 64.0;

struct SurfacePoint {
    Vec3 p{0.0};            // on the surface, refined (re-projected) where the shape allows
    Vec3 p_error{0.0};      // conservative absolute error bound of p, per component, that a
                            // spawned ray must clear (see kAnalyticRetestMargin, gamma_float)
    Vec3 n_geometric{0.0};  // outward, unit
    Vec3 n_shading{0.0};    // unit; equals n_geometric except for triangles with normals
    Vec2 uv{0.0};
};

/// The hits of a convex shape from up to four candidate roots: the smallest and the largest
/// (entry and exit of the one interval a line shares with a convex solid), each kept when inside
/// the interval; a root found twice (a side meeting a cap on the rim) counts once.
ShapeHits convex_hits(double* cand, int* part, int n, Interval t);
/// Whether (x, z) lies in the disc of radius r, widened by the errors of x and z and the
/// rounding of the test (cap and base discs; see convex_hits).
bool within_disc(double x, double z, double dx_err, double dz_err, double r);

Bounds3 bounds(const Sphere& s);
Bounds3 bounds(const Box& b);
Bounds3 bounds(const Cylinder& c);
Bounds3 bounds(const Cone& c);
Bounds3 bounds(const Triangle& t);

/// Tight bounds of the shape under an affine transform p' = m p (exact for every kind, so the
/// default camera frames what is really there).
Bounds3 bounds(const Sphere& s, const Mat4& m);
Bounds3 bounds(const Box& b, const Mat4& m);
Bounds3 bounds(const Cylinder& c, const Mat4& m);
Bounds3 bounds(const Cone& c, const Mat4& m);

/// Bounds of a disc of radius r centred at `centre` in the local plane normal to y, under m.
Bounds3 transformed_disc_bounds(const Vec3& centre, double r, const Mat4& m);

ShapeHits intersect(const Sphere& s, const Ray& ray, Interval t);
ShapeHits intersect(const Box& b, const Ray& ray, Interval t);
ShapeHits intersect(const Cylinder& c, const Ray& ray, Interval t);
ShapeHits intersect(const Cone& c, const Ray& ray, Interval t);
/// The renderer's triangle test (watertight, single precision: triangle4.h) on one triangle.
ShapeHits intersect(const Triangle& tri, const Ray& ray, Interval t);

/// `uv` false: texture coordinates are not computed (left at 0) for scenes without textures.
SurfacePoint surface_at(const Sphere& s, const Ray& ray, double t, int part, bool uv = true);
SurfacePoint surface_at(const Box& b, const Ray& ray, double t, int part, bool uv = true);
SurfacePoint surface_at(const Cylinder& c, const Ray& ray, double t, int part, bool uv = true);
SurfacePoint surface_at(const Cone& c, const Ray& ray, double t, int part, bool uv = true);
/// For triangles, `origin` is the point the float copy of the set's triangles is relative to
/// (GeometrySet::tri_origin): the point's error bound is the float rounding about it.
SurfacePoint surface_at(const Triangle& tri, const TriangleAttribs& attr, const Ray& ray, double t,
                        bool uv = true, const Vec3& origin = Vec3(0.0));

/// Spec §5's box face table: (u, v) of local point q on `face` (axis * 2 + 1 for the + side),
/// h the half side lengths. Each face reads upright and unmirrored from outside.
Vec2 box_face_uv(int face, const Vec3& q, const Vec3& h);

/// Spec §5's disc uv for cylinder caps and the cone base: top (q_x + r)/2r, (r - q_z)/2r;
/// bottom (q_x + r)/2r, (q_z + r)/2r.
inline Vec2 disc_uv(bool top, double qx, double qz, double r) {
    return top ? Vec2((qx + r) / (2 * r), (r - qz) / (2 * r))
               : Vec2((qx + r) / (2 * r), (qz + r) / (2 * r));
}

/// Spec §5: azimuth about +y measured from -z, in [0, 2*pi).
inline double azimuth(const Vec3& q) {
    double phi = std::atan2(-q.x, -q.z);
    if (phi < 0) phi += 2 * kPi;
    return phi;
}

}  // namespace rt
