// The preview's CSG data (spec §13.8): each CSG leaf tessellated whole with its leaf index on
// every vertex, and the set's CSG trees packed as RGBA32F texels for preview.frag (RT_CSG),
// which discards the fragments of leaf surfaces that the trees reject. No GL here.
#pragma once

#include <vector>

#include "rt/render_scene.h"
#include "rt/shapes/shapes.h"

namespace rt::view {

/// The set's CSG trees in preview.frag's layout (see its RT_CSG comment): `texels` holds four
/// floats a texel; nodes, children and leaves are the texel offsets of the three tables.
struct CsgTexels {
    std::vector<float> texels;
    int nodes = 0, children = 0, leaves = 0;
    std::vector<float> leaf_of_vertex;  // per vertex of the set's mesh: its leaf, -1 for none
};

/// Fills `texels` for the set's mesh from tessellate_set() (the trees, and the leaf of each
/// vertex from the mesh's per-triangle leaf tags, which it then drops). No CSG: both stay.
void add_csg_leaves(const GeometrySet& set, PreviewMesh* mesh, CsgTexels* texels);

}  // namespace rt::view
