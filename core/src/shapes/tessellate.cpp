// A primitive's preview: its triangles in the set's frame and what it is there; each shape's
// own tessellation is in its file.
#include "rt/shapes/tessellate.h"

#include <cmath>

namespace rt {

void PreviewMesh::append(const PreviewMesh& other, const Transform* xf) {
    const uint32_t base = static_cast<uint32_t>(positions.size());
    for (size_t i = 0; i < other.positions.size(); ++i) {
        positions.push_back(xf ? xf->point(other.positions[i]) : other.positions[i]);
        // As the trace's mesh normals (spec §5): mapped, and normalised only after the
        // interpolation (the fragment shader's normalize).
        normals.push_back(xf ? xf->interpolable_normal(other.normals[i]) : other.normals[i]);
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
    // CSG tags: kept one per triangle once any triangle has one.
    if (csg.empty() && other.csg.empty()) return;
    csg.resize(triangle_count() - other.triangle_count(), -1);
    if (other.csg.size() == other.triangle_count())
        csg.insert(csg.end(), other.csg.begin(), other.csg.end());
    else
        csg.resize(triangle_count(), -1);
}

namespace {

// s when `a` is s times a rotation or a reflection (a similarity: a sphere stays one), to 1e-3
// of s^2 (a rotation a file writes with four digits is one); else 0.
double similarity_scale(const Mat3& a) {
    const Mat3 g = glm::transpose(a) * a;
    const double s2 = (g[0][0] + g[1][1] + g[2][2]) / 3;
    if (!(s2 > 0)) return 0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (std::abs(g[c][r] - (c == r ? s2 : 0.0)) > 1e-3 * s2) return 0;
    return std::sqrt(s2);
}

// Whether `a` maps axis k onto an axis: its image's other components within 1e-6 of it.
bool keeps_axis(const Mat3& a, int k) {
    const Vec3 v = a[k];
    int along = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(v[i]) > std::abs(v[along])) along = i;
    for (int i = 0; i < 3; ++i)
        if (i != along && std::abs(v[i]) > 1e-6 * std::abs(v[along])) return false;
    return v[along] != 0;
}

// The kind and, when the transform keeps it one, the solid in the set's frame.
template <class S>
PreviewShape placed(const S&, const Transform*) {
    PreviewShape out;
    out.kind = S::kKind;
    return out;
}

PreviewShape placed(const Sphere& s, const Transform* xf) {
    PreviewShape out;
    out.kind = ShapeKind::Sphere;
    const double scale = xf ? similarity_scale(Mat3(xf->m)) : 1.0;
    out.solid = scale > 0 && s.radius > 0;
    out.centre = xf ? xf->point(s.centre) : s.centre;
    out.radius = scale * s.radius;
    return out;
}

PreviewShape placed(const Box& b, const Transform* xf) {
    PreviewShape out;
    out.kind = ShapeKind::Box;
    const Mat3 a = xf ? Mat3(xf->m) : Mat3(1.0);
    out.solid = b.half.x > 0 && b.half.y > 0 && b.half.z > 0 && keeps_axis(a, 0) &&
                keeps_axis(a, 1) && keeps_axis(a, 2);
    const Bounds3 local{b.centre - b.half, b.centre + b.half};
    out.box = xf ? xf->apply(local) : local;
    return out;
}

PreviewShape placed(const Torus& t, const Transform* xf) {
    PreviewShape out;
    out.kind = ShapeKind::Torus;
    const Mat3 a = xf ? Mat3(xf->m) : Mat3(1.0);
    const double scale = similarity_scale(a);
    out.solid = scale > 0 && keeps_axis(a, 1) && t.ring > 0 && t.tube > 0;
    out.centre = xf ? xf->point(t.centre) : t.centre;
    out.radii = scale * Vec2(t.ring, t.tube);
    return out;
}

}  // namespace

template <class S>
PreviewShape append_preview(const S& shape, const Transform* xf, int material, int detail,
                            PreviewMesh& out) {
    PreviewShape s = placed(shape, xf);
    s.first = out.triangle_count();
    PreviewMesh m = tessellate(shape, detail);
    m.materials.assign(m.triangle_count(), material);
    out.append(m, xf);
    s.count = out.triangle_count() - s.first;
    return s;
}

template PreviewShape append_preview(const Sphere&, const Transform*, int, int, PreviewMesh&);
template PreviewShape append_preview(const Box&, const Transform*, int, int, PreviewMesh&);
template PreviewShape append_preview(const Cylinder&, const Transform*, int, int, PreviewMesh&);
template PreviewShape append_preview(const Cone&, const Transform*, int, int, PreviewMesh&);
template PreviewShape append_preview(const Torus&, const Transform*, int, int, PreviewMesh&);

PreviewShape append_preview(const Triangle& t, const TriangleAttribs& attribs, int material,
                            PreviewMesh& out) {
    PreviewShape s;
    s.kind = ShapeKind::Triangle;
    s.first = out.triangle_count();
    tessellate(t, attribs, out);
    out.materials.push_back(material);
    s.count = 1;
    return s;
}

}  // namespace rt
