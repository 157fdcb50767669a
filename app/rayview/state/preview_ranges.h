// The preview's draw ranges of a set's mesh, before any GL: its triangles grouped by material,
// each group with its bounds, its largest flat parts (where planar reflections may go) and the
// solid it is (where refraction meets a second interface), read from the kinds and numbers the
// core gave each primitive (PreviewShape). No GL here.
#pragma once

#include <optional>
#include <vector>

#include "rt/shapes/tessellate.h"

namespace rt::view {

/// A flat part of a range: its triangles in one plane n.p + d = 0 (set frame, n unit), their
/// area and the area-weighted centroid (on the plane), and their box.
struct FlatFace {
    Vec3 n{0.0};
    double d = 0, area = 0;
    Vec3 centroid{0.0};
    Bounds3 bounds;
};

/// The triangles of one material of a set's mesh, drawn by one call.
struct PreviewRange {
    int material = 0;
    unsigned first = 0, count = 0;  // in MaterialRanges::indices
    Bounds3 bounds;                 // of its vertices, in the set's frame
    std::vector<FlatFace> faces;    // its largest flat parts (planar reflections), if any
    /// The solid the range is, in the set's frame: its primitive's, when the material's
    /// triangles are one primitive's alone and that is a solid there (PreviewShape::solid).
    std::optional<PreviewShape> solid;
};

struct MaterialRanges {
    std::vector<unsigned> indices;  // the mesh's triangles, grouped by material (stable)
    std::vector<PreviewRange> ranges;
};

/// The mesh's ranges in the order of their materials' numbers. `shapes`: what the mesh's
/// triangles are (tessellate_set's); without them no range is a solid.
MaterialRanges material_ranges(const PreviewMesh& mesh, const std::vector<PreviewShape>& shapes);

/// The largest flat parts (at most 8, the largest first) of triangles `tris` of `mesh`: the
/// planes whose triangles make a sixth or so of their connected part (a box's face, a
/// cylinder's cap, a wall), not the facets of a tessellated curved surface; none for more than
/// 20000 triangles (a mesh, not a wall).
std::vector<FlatFace> flat_faces(const PreviewMesh& mesh, const std::vector<size_t>& tris);

}  // namespace rt::view
