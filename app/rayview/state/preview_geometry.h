// The preview's geometry before any GL: each placed set tessellated, with its CSG leaves'
// texels, and a coarse version of each big one that the preview draws while the view moves.
// Made off the interface thread while a scene loads (SceneLoader), so the frame that swaps the
// scene in only uploads it. No GL here.
#pragma once

#include <atomic>
#include <vector>

#include "rt/render_scene.h"
#include "rt/shapes/tessellate.h"
#include "state/csg_preview.h"

namespace rt::view {

/// One entry per set of the scene; a set no instance places is left empty.
struct PreviewGeometry {
    struct Set {
        bool placed = false;
        PreviewMesh mesh;
        std::vector<PreviewShape> shapes;  // tessellate_set's
        CsgTexels csg;
        /// decimate(mesh, kCoarseTriangles) when the mesh has more than kCoarseAbove
        /// triangles and no CSG leaves; else empty.
        PreviewMesh coarse;
    };
    std::vector<Set> sets;
    int detail = 0;
};
/// Every primitive of a set in the set's frame, tagged with its material (a CSG node's leaves
/// whole, each tagged with its leaf: PreviewMesh::csg), for instances to draw with their
/// world_from_set transform. `shapes` (when given) gets what each primitive is, in the mesh's
/// order: one entry each, but one for a run of triangles of one material.
PreviewMesh tessellate_set(const GeometrySet& set, int detail,
                           std::vector<PreviewShape>* shapes = nullptr);

/// Throws std::runtime_error("loading cancelled") at its next check once *cancel is set.
PreviewGeometry prepare_preview(const RenderScene& scene, int detail = 48,
                                const std::atomic<bool>* cancel = nullptr);

/// Meshes above this many triangles get a coarse version of about kCoarseTriangles.
constexpr size_t kCoarseAbove = 250000;
constexpr size_t kCoarseTriangles = 80000;

/// A coarser `mesh` of at most about `target` triangles, by vertex clustering: the vertices in
/// one cell of a uniform grid over the mesh's bounds (and of one material) become one, at
/// their mean position with their normals' normalised sum and the first one's uv; triangles
/// that collapse and repeats are dropped, and one folded over (facing against its normals
/// where its source did not) is wound back. The grid is refined until the count is near the
/// target. Each triangle keeps its material; CSG leaves are not kept (the caller does not ask
/// for meshes that have them). A mesh already at or below `target` comes back as it is.
PreviewMesh decimate(const PreviewMesh& mesh, size_t target,
                     const std::atomic<bool>* cancel = nullptr);

}  // namespace rt::view
