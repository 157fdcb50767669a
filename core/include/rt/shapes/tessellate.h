// Triangle meshes of the analytic shapes and of whole geometry sets, for the viewer's rasterized
// preview. Positions, outward normals and texture coordinates follow spec §5, so the preview and
// the trace agree; no GL here, the viewer uploads these arrays.
#pragma once

#include <cstdint>
#include <vector>

#include "rt/compile/render_scene.h"

namespace rt {

struct PreviewMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // unit, outward (the shader applies the two-sided rule)
    std::vector<Vec2> uvs;
    std::vector<uint32_t> indices;  // three per triangle
    std::vector<int> materials;     // one per triangle: index into RenderScene::materials

    size_t triangle_count() const { return indices.size() / 3; }
    /// Appends `other` with every vertex mapped by `xf` (points by M, normals by (A^-1)^T).
    void append(const PreviewMesh& other, const Transform* xf = nullptr);
};

/// `detail` is the number of segments around the y axis (at least 3); rings follow from it.
PreviewMesh tessellate(const Sphere& s, int detail);
PreviewMesh tessellate(const Box& b);
PreviewMesh tessellate(const Cylinder& c, int detail);
PreviewMesh tessellate(const Cone& c, int detail);

/// Every primitive of a set in the set's frame, tagged with its material. Instances draw it
/// with their world_from_set transform.
PreviewMesh tessellate_set(const GeometrySet& set, int detail);

}  // namespace rt
