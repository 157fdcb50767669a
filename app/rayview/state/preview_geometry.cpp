#include "preview_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "rt/shapes/tessellate.h"

namespace rt::view {

namespace {

// One clustering of `mesh` on a grid of `cells` cells along its longest side.
PreviewMesh cluster(const PreviewMesh& mesh, const Bounds3& box, double cells) {
    const Vec3 size = box.diagonal();
    const double cell = std::max({size.x, size.y, size.z}) / cells;
    const auto index = [&](double v, double lo) {
        return static_cast<uint64_t>(std::clamp((v - lo) / cell, 0.0, 2097151.0));
    };
    struct Cluster {
        Vec3 position{0.0}, normal{0.0};
        Vec2 uv{0.0};
        double count = 0;
    };
    std::unordered_map<uint64_t, uint32_t> id_of;  // (cell, material) -> cluster
    std::vector<Cluster> clusters;
    const bool uvs = mesh.uvs.size() == mesh.positions.size();
    const auto corner = [&](size_t t, int k) {
        const uint32_t v = mesh.indices[t * 3 + static_cast<size_t>(k)];
        const Vec3& p = mesh.positions[v];
        const uint64_t key =
            (index(p.x, box.lo.x) | index(p.y, box.lo.y) << 21 | index(p.z, box.lo.z) << 42) ^
            static_cast<uint64_t>(mesh.materials[t]) * 0x9E3779B97F4A7C15ull;
        auto [it, fresh] = id_of.try_emplace(key, static_cast<uint32_t>(clusters.size()));
        if (fresh) {
            clusters.emplace_back();
            clusters.back().uv = uvs ? mesh.uvs[v] : Vec2(0.0);
        }
        Cluster& c = clusters[it->second];
        c.position += p;
        c.normal += mesh.normals[v];
        c.count += 1;
        return it->second;
    };
    PreviewMesh out;
    std::vector<size_t> source;         // the mesh's triangle each kept one comes from
    std::unordered_set<uint64_t> seen;  // the sorted corners of each triangle kept
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        std::array<uint32_t, 3> c{corner(t, 0), corner(t, 1), corner(t, 2)};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        std::array<uint32_t, 3> sorted = c;
        std::sort(sorted.begin(), sorted.end());
        const uint64_t key =
            (static_cast<uint64_t>(sorted[0]) * 0x100000001B3ull ^ sorted[1]) * 0x100000001B3ull ^
            sorted[2];
        if (!seen.insert(key).second) continue;
        out.indices.insert(out.indices.end(), c.begin(), c.end());
        out.materials.push_back(mesh.materials[t]);
        source.push_back(t);
    }
    out.positions.reserve(clusters.size());
    for (const Cluster& c : clusters) {
        out.positions.push_back(c.position / c.count);
        const double n = glm::length(c.normal);
        out.normals.push_back(n > 0 ? c.normal / n : Vec3(0, 1, 0));
        if (uvs) out.uvs.push_back(c.uv);
    }
    // A triangle the clustering folded over faces against its normals (the two-sided rule
    // would draw it dark): wound back to its source triangle's sense against its normals.
    const auto along = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& normals) {
        return glm::dot(glm::cross(b - a, c - a), normals) >= 0;
    };
    for (size_t k = 0; k < source.size(); ++k) {
        const uint32_t* v = &mesh.indices[3 * source[k]];
        uint32_t* w = &out.indices[3 * k];
        const bool was = along(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]],
                               mesh.normals[v[0]] + mesh.normals[v[1]] + mesh.normals[v[2]]);
        const bool is = along(out.positions[w[0]], out.positions[w[1]], out.positions[w[2]],
                              out.normals[w[0]] + out.normals[w[1]] + out.normals[w[2]]);
        if (was != is) std::swap(w[1], w[2]);
    }
    return out;
}

void check_cancel(const std::atomic<bool>* cancel) {
    if (cancel && cancel->load(std::memory_order_relaxed))
        throw std::runtime_error("loading cancelled");
}

}  // namespace

PreviewMesh decimate(const PreviewMesh& mesh, size_t target, const std::atomic<bool>* cancel) {
    if (mesh.triangle_count() <= target) return mesh;
    Bounds3 box;
    for (const Vec3& p : mesh.positions) box.extend(p);
    // A closed surface keeps about twice as many triangles as the cells it passes through,
    // which grow as the square of the cells along a side: start from that guess, then correct
    // it by the square root of the ratio found.
    double cells = std::max(4.0, std::sqrt(static_cast<double>(target)));
    PreviewMesh out;
    for (int tries = 0; tries < 5; ++tries) {
        check_cancel(cancel);
        out = cluster(mesh, box, cells);
        const double ratio = static_cast<double>(target) /
                             static_cast<double>(std::max<size_t>(out.triangle_count(), 1));
        if (ratio >= 0.7 && ratio <= 1.0) break;
        cells *= std::clamp(std::sqrt(ratio) * 0.97, 0.25, 4.0);
    }
    if (out.triangle_count() > target) out = cluster(mesh, box, cells * 0.8);
    return out;
}

PreviewGeometry prepare_preview(const RenderScene& scene, int detail,
                                const std::atomic<bool>* cancel) {
    // Sets no instance places are not tessellated.
    PreviewGeometry g;
    g.detail = detail;
    g.sets.resize(scene.sets.size());
    for (const Instance& inst : scene.instances)
        g.sets[static_cast<size_t>(inst.set)].placed = true;
    for (size_t si = 0; si < scene.sets.size(); ++si) {
        PreviewGeometry::Set& s = g.sets[si];
        if (!s.placed) continue;
        check_cancel(cancel);
        s.mesh = tessellate_set(scene.sets[si], detail);
        add_csg_leaves(scene.sets[si], &s.mesh, &s.csg);
        if (s.mesh.triangle_count() > kCoarseAbove && s.csg.leaf_of_vertex.empty())
            s.coarse = decimate(s.mesh, kCoarseTriangles, cancel);
    }
    return g;
}

}  // namespace rt::view
