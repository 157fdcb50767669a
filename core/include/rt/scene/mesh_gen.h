// Procedural test meshes: a closed, bumpy "blob" of about N triangles, as plain arrays or as .ray
// text. Used by `raygen` (large scenes for users) and `raybench` (the same meshes for Embree).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rt/util/math.h"

namespace rt {

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // per vertex, unit
    std::vector<std::array<int, 3>> triangles;
};

/// A closed latitude-longitude sphere displaced by smooth bumps, with about `target_triangles`
/// triangles (the exact count is 4 k (k - 1) for the grid size k chosen). Deterministic.
TriangleMesh make_blob_mesh(size_t target_triangles);

/// The mesh as a complete V1 .ray scene: camera, lights, one material, vertices, triangles.
std::string ray_text_for_mesh(const TriangleMesh& mesh);

}  // namespace rt
