// The set-level preview mesh; each shape's own tessellation is in its file.
#include "rt/shapes/tessellate.h"

#include <algorithm>

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

// Appends one shape primitive (or CSG leaf) of the set, tagged with CSG leaf `csg` (-1: none).
void append_primitive(const GeometrySet& set, const Primitive& p, int detail, int csg,
                      PreviewMesh& out) {
    const size_t before = out.triangle_count();
    visit_shape(set, p, [&](const auto& shape) {
        if constexpr (std::is_same_v<std::decay_t<decltype(shape)>, Triangle>) {
            // In the set's frame already: appended as it is.
            tessellate(shape, set.triangle_attribs(p.index), out);
            out.materials.push_back(p.material);
        } else {
            PreviewMesh m = tessellate(shape, detail);
            m.materials.assign(m.triangle_count(), p.material);
            out.append(
                m, p.transform < 0 ? nullptr : &set.transforms[static_cast<size_t>(p.transform)]);
        }
    });
    if (csg < 0 && out.csg.empty()) return;
    out.csg.resize(before, -1);
    out.csg.resize(out.triangle_count(), csg);
}

}  // namespace

PreviewMesh tessellate_set(const GeometrySet& set, int detail) {
    PreviewMesh out;
    // A mesh's arrays made room for at once: three vertices per triangle, not copied as they
    // grow (the other kinds add theirs as they come).
    const size_t triangles = set.triangle_count();
    out.positions.reserve(3 * triangles);
    out.normals.reserve(3 * triangles);
    out.uvs.reserve(3 * triangles);
    out.indices.reserve(3 * triangles);
    out.materials.reserve(triangles);
    for (const Primitive& p : set.prims) {
        if (p.csg < 0) {
            append_primitive(set, p, detail, -1, out);
            continue;
        }
        // The leaves whole, each tagged with its index (PreviewMesh::csg).
        const CsgRoot& r = set.csg.roots[static_cast<size_t>(p.csg)];
        for (uint32_t l = r.first_leaf; l < r.first_leaf + r.leaf_count; ++l)
            append_primitive(set, set.csg.leaves[l].prim, detail, static_cast<int>(l), out);
    }
    return out;
}

}  // namespace rt
