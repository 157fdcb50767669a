#include "rt/shapes/tessellate.h"

#include <algorithm>

namespace rt {

void PreviewMesh::append(const PreviewMesh& other, const Transform* xf) {
    const uint32_t base = static_cast<uint32_t>(positions.size());
    for (size_t i = 0; i < other.positions.size(); ++i) {
        positions.push_back(xf ? xf->point(other.positions[i]) : other.positions[i]);
        normals.push_back(xf ? glm::normalize(xf->normal_dir(other.normals[i])) : other.normals[i]);
        uvs.push_back(other.uvs[i]);
    }
    // A mirroring transform reverses the winding; swap two corners to keep it counter-clockwise
    // seen from outside.
    const bool mirror = xf && glm::determinant(Mat3(xf->m)) < 0;
    for (size_t t = 0; t + 2 < other.indices.size(); t += 3) {
        indices.push_back(base + other.indices[t]);
        indices.push_back(base + other.indices[t + (mirror ? 2 : 1)]);
        indices.push_back(base + other.indices[t + (mirror ? 1 : 2)]);
    }
    materials.insert(materials.end(), other.materials.begin(), other.materials.end());
}

namespace {

struct Builder {
    PreviewMesh mesh;

    uint32_t vertex(const Vec3& p, const Vec3& n, const Vec2& uv) {
        mesh.positions.push_back(p);
        mesh.normals.push_back(n);
        mesh.uvs.push_back(uv);
        return static_cast<uint32_t>(mesh.positions.size() - 1);
    }

    // Adds the triangle wound counter-clockwise seen from outside (along its vertex normals);
    // drops triangles without area (the collapsed corners of poles and apexes).
    void triangle(uint32_t a, uint32_t b, uint32_t c) {
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

    // A grid of (rows + 1) x (cols + 1) vertices from f(row, col) -> {p, n, uv}, two triangles a
    // cell.
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

    // A disc of radius r at height y (normal +y or -y) as a fan, uv from spec §5's cap rules.
    void disc(const Vec3& centre, double r, bool top, int segments) {
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
};

// The point at azimuth phi (spec §5: measured from -z about +y) at horizontal radius rho.
Vec3 around(double phi, double rho) { return {-rho * std::sin(phi), 0.0, -rho * std::cos(phi)}; }

}  // namespace

PreviewMesh tessellate(const Sphere& s, int detail) {
    const int segments = std::max(3, detail), rings = std::max(2, detail / 2);
    Builder b;
    // v = acos(-q_y / r) / pi: v = 0 at the bottom pole.
    b.grid(rings, segments, [&](int i, int j, Vec3* p, Vec3* n, Vec2* uv) {
        const double v = static_cast<double>(i) / rings, u = static_cast<double>(j) / segments;
        const double theta = kPi * v;
        Vec3 q = around(2 * kPi * u, s.radius * std::sin(theta));
        q.y = -s.radius * std::cos(theta);
        *p = s.centre + q;
        *n = q / s.radius;
        *uv = {u, v};
    });
    return std::move(b.mesh);
}

PreviewMesh tessellate(const Box& box) {
    Builder b;
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

PreviewMesh tessellate(const Cylinder& c, int detail) {
    const int segments = std::max(3, detail);
    const double h2 = 0.5 * c.height;
    Builder b;
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

PreviewMesh tessellate(const Cone& c, int detail) {
    const int segments = std::max(3, detail);
    const double h2 = 0.5 * c.height, r = c.radius, h = c.height;
    Builder b;
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

PreviewMesh tessellate_set(const GeometrySet& set, int detail) {
    PreviewMesh out;
    for (const Primitive& p : set.prims) {
        PreviewMesh m;
        switch (p.kind) {
            case ShapeKind::Sphere:
                m = tessellate(set.spheres[p.index], detail);
                break;
            case ShapeKind::Box:
                m = tessellate(set.boxes[p.index]);
                break;
            case ShapeKind::Cylinder:
                m = tessellate(set.cylinders[p.index], detail);
                break;
            case ShapeKind::Cone:
                m = tessellate(set.cones[p.index], detail);
                break;
            case ShapeKind::Triangle: {
                const Triangle& t = set.triangles[p.index];
                const TriangleAttribs& a = set.triangle_attribs[p.index];
                const Vec3 ng = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
                const Vec3 ps[3] = {t.p0, t.p1, t.p2};
                const uint32_t first = static_cast<uint32_t>(out.positions.size());
                for (int k = 0; k < 3; ++k) {
                    out.positions.push_back(ps[k]);
                    out.normals.push_back(a.has_normals ? a.n[k] : ng);
                    out.uvs.push_back(a.uv[k]);
                }
                // The file's winding: (v2 - v1) x (v3 - v1) is the geometric normal (spec §5).
                out.indices.insert(out.indices.end(), {first, first + 1, first + 2});
                out.materials.push_back(p.material);
                continue;
            }
        }
        m.materials.assign(m.triangle_count(), p.material);
        out.append(m,
                   p.transform < 0 ? nullptr : &set.transforms[static_cast<size_t>(p.transform)]);
    }
    return out;
}

}  // namespace rt
