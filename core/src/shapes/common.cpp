// The helpers of common.h and the kind names.
#include "common.h"

#include <array>
#include <utility>

namespace rt {

namespace {
template <size_t... I>
constexpr std::array<const char*, kShapeKinds> kind_names(std::index_sequence<I...>) {
    return {std::variant_alternative_t<I, Shape>::kName...};
}
constexpr auto kKindNames = kind_names(std::make_index_sequence<kShapeKinds>{});
}  // namespace

const char* shape_kind_name(ShapeKind k) {
    const auto i = static_cast<size_t>(k);
    return i < kKindNames.size() ? kKindNames[i] : "?";
}

Bounds3 transformed_disc_bounds(const Vec3& centre, double r, const Mat4& m) {
    // The disc is centre + r (cos a, 0, sin a); along axis i it spans r |(A_i0, A_i2)|.
    const Vec3 c = Vec3(m * glm::dvec4(centre, 1.0));
    Vec3 e;
    for (int i = 0; i < 3; ++i) e[i] = r * std::hypot(m[0][i], m[2][i]);
    return {c - e, c + e};
}

ShapeHits convex_hits(double* cand, int* part, int n, Interval t) {
    for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && cand[j] < cand[j - 1]; --j)
            std::swap(cand[j], cand[j - 1]), std::swap(part[j], part[j - 1]);
    // A line meets a convex solid in one interval: its hits are the smallest and the largest
    // candidate. Candidates accepted within their rounding band near a rim or an apex (a side root
    // a hair past the cap plane, a cap point a hair outside the disc) lie between the two and are
    // dropped, so the real exit is never displaced by a duplicate of the entry.
    ShapeHits h;
    if (n == 0) return h;
    if (t.contains(cand[0])) h.add(cand[0], part[0]);
    if (n > 1 && cand[n - 1] != cand[0] && t.contains(cand[n - 1])) h.add(cand[n - 1], part[n - 1]);
    return h;
}

bool within_disc(double x, double z, double dx_err, double dz_err, double r) {
    // x^2 + z^2 <= r^2 for the point as computed, widened by the error of its coordinates, so a
    // ray through a rim is accepted by the cap even when the side rejects it (and vice versa).
    const double err = 2.0 * (std::abs(x) * dx_err + std::abs(z) * dz_err) + dx_err * dx_err +
                       dz_err * dz_err + gamma(3) * (x * x + z * z + r * r);
    return x * x + z * z <= r * r + err;
}

uint32_t MeshBuilder::vertex(const Vec3& p, const Vec3& n, const Vec2& uv) {
    mesh.positions.push_back(p);
    mesh.normals.push_back(n);
    mesh.uvs.push_back(uv);
    return static_cast<uint32_t>(mesh.positions.size() - 1);
}

void MeshBuilder::triangle(uint32_t a, uint32_t b, uint32_t c) {
    const Vec3& pa = mesh.positions[a];
    const Vec3 cr = glm::cross(mesh.positions[b] - pa, mesh.positions[c] - pa);
    if (glm::length(cr) <=
            1e-14 * glm::length(mesh.positions[b] - pa) * glm::length(mesh.positions[c] - pa) ||
        glm::length(cr) == 0.0)
        return;
    const Vec3 outward = mesh.normals[a] + mesh.normals[b] + mesh.normals[c];
    mesh.indices.push_back(a);
    if (glm::dot(cr, outward) >= 0) {
        mesh.indices.push_back(b);
        mesh.indices.push_back(c);
    } else {
        mesh.indices.push_back(c);
        mesh.indices.push_back(b);
    }
}

void MeshBuilder::disc(const Vec3& centre, double r, bool top, int segments) {
    const Vec3 n(0.0, top ? 1.0 : -1.0, 0.0);
    auto uv = [&](double qx, double qz) { return disc_uv(top, qx, qz, r); };
    const uint32_t c = vertex(centre, n, uv(0, 0));
    std::vector<uint32_t> rim;
    for (int j = 0; j <= segments; ++j) {
        const double phi = 2 * kPi * j / segments;
        const double qx = -r * std::sin(phi), qz = -r * std::cos(phi);
        rim.push_back(vertex(centre + Vec3(qx, 0, qz), n, uv(qx, qz)));
    }
    for (int j = 0; j < segments; ++j)
        triangle(c, rim[static_cast<size_t>(j)], rim[static_cast<size_t>(j) + 1]);
}

}  // namespace rt
