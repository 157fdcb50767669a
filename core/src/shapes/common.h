// Helpers the shape files share (private to core/src/shapes): the convex-hit selection and the
// disc test of the rimmed shapes, transformed disc bounds, spec §5's disc uv, and the mesh
// builder of the preview tessellations.
#pragma once

#include <vector>

#include "rt/shapes/shapes.h"

namespace rt {

/// The hits of a convex shape from up to four candidate roots: the smallest and the largest
/// (entry and exit of the one interval a line shares with a convex solid), each kept when inside
/// the interval; a root found twice (a side meeting a cap on the rim) counts once.
ShapeHits convex_hits(double* cand, int* part, int n, Interval t);
/// Whether (x, z) lies in the disc of radius r, widened by the errors of x and z and the
/// rounding of the test (cap and base discs; see convex_hits).
bool within_disc(double x, double z, double dx_err, double dz_err, double r);

/// Bounds of a disc of radius r centred at `centre` in the local plane normal to y, under m.
Bounds3 transformed_disc_bounds(const Vec3& centre, double r, const Mat4& m);

/// Spec §5's disc uv for cylinder caps and the cone base: top (q_x + r)/2r, (r - q_z)/2r;
/// bottom (q_x + r)/2r, (q_z + r)/2r.
inline Vec2 disc_uv(bool top, double qx, double qz, double r) {
    return top ? Vec2((qx + r) / (2 * r), (r - qz) / (2 * r))
               : Vec2((qx + r) / (2 * r), (qz + r) / (2 * r));
}

/// A point q (relative to the shape's centre) put on the cap or base disc of radius r at height
/// y, facing +y (top) or -y, with spec §5's disc uv when asked.
inline void on_disc(bool top, double y, double r, bool uv, Vec3& q, SurfacePoint& sp) {
    q.y = y;
    sp.n_geometric = Vec3(0.0, top ? 1.0 : -1.0, 0.0);
    if (uv) sp.uv = disc_uv(top, q.x, q.z, r);
}

/// sp placed at centre + q (q on the surface, relative to the centre), with the error bound of
/// a re-projected point (g: the gamma of the shape's arithmetic) and the shading normal its
/// geometric one.
inline SurfacePoint placed(SurfacePoint sp, const Vec3& centre, const Vec3& q, double g) {
    sp.p = centre + q;
    sp.p_error = kAnalyticRetestMargin * g * (glm::abs(centre) + glm::abs(q));
    sp.n_shading = sp.n_geometric;
    return sp;
}

/// The point at azimuth phi (spec §5: measured from -z about +y) at horizontal radius rho.
inline Vec3 around(double phi, double rho) {
    return {-rho * std::sin(phi), 0.0, -rho * std::cos(phi)};
}

/// Builds a PreviewMesh from vertices, triangles, grids and discs (the tessellations).
struct MeshBuilder {
    PreviewMesh mesh;

    uint32_t vertex(const Vec3& p, const Vec3& n, const Vec2& uv);

    /// Adds the triangle wound counter-clockwise seen from outside (along its vertex normals);
    /// drops triangles without area (the collapsed corners of poles and apexes).
    void triangle(uint32_t a, uint32_t b, uint32_t c);

    /// A grid of (rows + 1) x (cols + 1) vertices from f(row, col) -> {p, n, uv}, two triangles
    /// a cell.
    template <class F>
    void grid(int rows, int cols, F&& f) {
        const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
        for (int i = 0; i <= rows; ++i)
            for (int j = 0; j <= cols; ++j) {
                Vec3 p, n;
                Vec2 uv;
                f(i, j, &p, &n, &uv);
                vertex(p, n, uv);
            }
        auto at = [&](int i, int j) { return base + static_cast<uint32_t>(i * (cols + 1) + j); };
        for (int i = 0; i < rows; ++i)
            for (int j = 0; j < cols; ++j) {
                triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
                triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }

    /// A disc of radius r at `centre` (normal +y or -y) as a fan, uv from spec §5's cap rules.
    void disc(const Vec3& centre, double r, bool top, int segments);
};

}  // namespace rt
