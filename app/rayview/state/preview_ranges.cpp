#include "state/preview_ranges.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <unordered_map>

namespace rt::view {

namespace {

// Triangles whose planes agree to these tolerances are one face: normals within about 0.06
// degrees, offsets within 1e-5 of the range's size.
constexpr double kNormalStep = 1e-3;
constexpr double kOffsetStep = 1e-5;
// Ranges with more triangles are meshes, not walls: their flat parts are not looked for.
constexpr size_t kMaxFaceTriangles = 20000;
constexpr size_t kFacesPerRange = 8;
// Faces smaller than this share of their connected part's area are the facets of a tessellated
// curved surface (a sphere's, a cylinder's), which keeps its cube map; a box's face is a sixth
// or more.
constexpr double kMinFaceShare = 0.05;

// The connected part of each of triangles `tris` (triangles that share vertices: one
// tessellated shape, or a box's face), named by one of its vertices, so that a facet is weighed
// against its own surface, not against a floor of the same material.
std::vector<uint32_t> connected_parts(const PreviewMesh& mesh, const std::vector<size_t>& tris) {
    std::unordered_map<uint32_t, uint32_t> parent;
    const auto find = [&](uint32_t v) {
        auto it = parent.try_emplace(v, v).first;
        while (it->second != v) {
            v = it->second;
            it = parent.find(v);
        }
        return v;
    };
    for (size_t t : tris) {
        const uint32_t r0 = find(mesh.indices[t * 3]);
        for (int k = 1; k < 3; ++k) {
            const uint32_t rk = find(mesh.indices[t * 3 + k]);
            if (rk != r0) parent[rk] = r0;
        }
    }
    std::vector<uint32_t> part;
    part.reserve(tris.size());
    for (size_t t : tris) part.push_back(find(mesh.indices[t * 3]));
    return part;
}

using PlaneKey = std::tuple<long, long, long, long>;

// A triangle's plane, one sign per plane (the first non-zero component of n positive), its key
// to the tolerances above, and its area (0: degenerate, no plane).
struct TrianglePlane {
    PlaneKey key;
    Vec3 n{0.0};
    double d = 0, area = 0;
};

TrianglePlane plane_of(const Vec3& a, const Vec3& b, const Vec3& c, double size) {
    const Vec3 cr = glm::cross(b - a, c - a);
    const double twice_area = glm::length(cr);
    if (!(twice_area > 0.0)) return {};
    Vec3 n = cr / twice_area;
    const double lead = std::abs(n.x) > 1e-9 ? n.x : std::abs(n.y) > 1e-9 ? n.y : n.z;
    if (lead < 0) n = -n;
    const double d = -glm::dot(n, a);
    const PlaneKey key{std::lround(n.x / kNormalStep), std::lround(n.y / kNormalStep),
                       std::lround(n.z / kNormalStep), std::lround(d / (kOffsetStep * size))};
    return {key, n, d, 0.5 * twice_area};
}

// The primitive each material's triangles are, when they are one primitive's alone.
std::map<int, const PreviewShape*> sole_shapes(const PreviewMesh& mesh,
                                               const std::vector<PreviewShape>& shapes) {
    std::map<int, const PreviewShape*> sole;
    for (const PreviewShape& s : shapes) {
        if (s.count == 0) continue;
        const auto [it, fresh] = sole.try_emplace(mesh.materials[s.first], &s);
        if (!fresh) it->second = nullptr;
    }
    return sole;
}

}  // namespace

std::vector<FlatFace> flat_faces(const PreviewMesh& mesh, const std::vector<size_t>& tris) {
    if (tris.empty() || tris.size() > kMaxFaceTriangles) return {};
    Bounds3 box;
    for (size_t t : tris)
        for (int k = 0; k < 3; ++k) box.extend(mesh.positions[mesh.indices[t * 3 + k]]);
    const double size = std::max(glm::length(box.diagonal()), 1e-300);
    const std::vector<uint32_t> part = connected_parts(mesh, tris);
    const auto corner = [&](size_t t, int k) -> const Vec3& {
        return mesh.positions[mesh.indices[t * 3 + static_cast<size_t>(k)]];
    };
    std::vector<TrianglePlane> planes;
    planes.reserve(tris.size());
    std::unordered_map<uint32_t, double> part_area;
    std::map<std::pair<uint32_t, PlaneKey>, double> part_plane_area;
    for (size_t i = 0; i < tris.size(); ++i) {
        const size_t t = tris[i];
        planes.push_back(plane_of(corner(t, 0), corner(t, 1), corner(t, 2), size));
        if (!(planes.back().area > 0)) continue;
        part_area[part[i]] += planes.back().area;
        part_plane_area[{part[i], planes.back().key}] += planes.back().area;
    }
    std::map<PlaneKey, FlatFace> faces;
    for (size_t i = 0; i < tris.size(); ++i) {
        const TrianglePlane& p = planes[i];
        if (!(p.area > 0)) continue;
        // A facet of a curved surface (a sphere's, a cylinder's side) keeps its cube map; a
        // box's face or a cylinder's cap is a sixth or more of its part.
        if (part_plane_area[{part[i], p.key}] < kMinFaceShare * part_area[part[i]]) continue;
        const Vec3 &a = corner(tris[i], 0), &b = corner(tris[i], 1), &c = corner(tris[i], 2);
        FlatFace& f = faces[p.key];
        if (f.area == 0) f.n = p.n, f.d = p.d;
        f.centroid += p.area * (a + b + c) / 3.0;
        f.area += p.area;
        f.bounds.extend(a);
        f.bounds.extend(b);
        f.bounds.extend(c);
    }
    std::vector<FlatFace> out;
    for (auto& [key, f] : faces) {
        f.centroid /= f.area;
        out.push_back(f);
    }
    std::sort(out.begin(), out.end(),
              [](const FlatFace& x, const FlatFace& y) { return x.area > y.area; });
    if (out.size() > kFacesPerRange) out.resize(kFacesPerRange);
    return out;
}

MaterialRanges material_ranges(const PreviewMesh& mesh, const std::vector<PreviewShape>& shapes) {
    std::vector<size_t> order(mesh.triangle_count());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return mesh.materials[a] < mesh.materials[b]; });
    const std::map<int, const PreviewShape*> sole = sole_shapes(mesh, shapes);
    MaterialRanges out;
    out.indices.reserve(mesh.indices.size());
    std::vector<size_t> range_tris;
    const auto close = [&] {
        PreviewRange& r = out.ranges.back();
        r.faces = flat_faces(mesh, range_tris);
        const auto it = sole.find(r.material);
        if (it != sole.end() && it->second && it->second->solid) r.solid = *it->second;
    };
    for (size_t t : order) {
        const int m = mesh.materials[t];
        if (out.ranges.empty() || out.ranges.back().material != m) {
            if (!out.ranges.empty()) close();
            range_tris.clear();
            out.ranges.push_back(
                {m, static_cast<unsigned>(out.indices.size()), 0, Bounds3{}, {}, {}});
        }
        range_tris.push_back(t);
        for (int k = 0; k < 3; ++k) {
            const unsigned v = mesh.indices[t * 3 + static_cast<size_t>(k)];
            out.indices.push_back(v);
            out.ranges.back().bounds.extend(mesh.positions[v]);
        }
        out.ranges.back().count += 3;
    }
    if (!out.ranges.empty()) close();
    return out;
}

}  // namespace rt::view
