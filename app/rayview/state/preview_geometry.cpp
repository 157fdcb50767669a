#include "state/preview_geometry.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <tuple>
#include <type_traits>

namespace rt::view {

namespace {

// An open-addressing table from 64-bit keys to 32-bit values (~0u marks a free slot), at most
// half full: the clustering looks up every corner of a million-triangle mesh several times,
// which std::unordered_map's node per key makes several times slower.
class FlatMap {
public:
    explicit FlatMap(size_t expected) { rehash(std::max<size_t>(16, std::bit_ceil(2 * expected))); }
    // The value of `key`, set to `value` first when the key is new; whether it was new.
    std::pair<uint32_t, bool> try_emplace(uint64_t key, uint32_t value) {
        if (2 * (m_size + 1) > m_values.size()) rehash(2 * m_values.size());
        const size_t mask = m_values.size() - 1;
        for (size_t i = mix(key) & mask;; i = (i + 1) & mask) {
            if (m_values[i] == kFree) {
                m_keys[i] = key;
                m_values[i] = value;
                ++m_size;
                return {value, true};
            }
            if (m_keys[i] == key) return {m_values[i], false};
        }
    }

private:
    static constexpr uint32_t kFree = ~0u;
    static uint64_t mix(uint64_t k) {  // splitmix64's finaliser
        k = (k ^ (k >> 30)) * 0xBF58476D1CE4E5B9ull;
        k = (k ^ (k >> 27)) * 0x94D049BB133111EBull;
        return k ^ (k >> 31);
    }
    void rehash(size_t capacity) {
        std::vector<uint64_t> keys(capacity);
        std::vector<uint32_t> values(capacity, kFree);
        for (size_t j = 0; j < m_values.size(); ++j) {
            if (m_values[j] == kFree) continue;
            size_t i = mix(m_keys[j]) & (capacity - 1);
            while (values[i] != kFree) i = (i + 1) & (capacity - 1);
            keys[i] = m_keys[j];
            values[i] = m_values[j];
        }
        m_keys = std::move(keys);
        m_values = std::move(values);
    }
    std::vector<uint64_t> m_keys;
    std::vector<uint32_t> m_values;
    size_t m_size = 0;
};

// A triangle the clustering folded over faces against its normals (the two-sided rule would
// draw it dark): wound back to its source triangle's sense against its normals. `source`: the
// triangle of `mesh` each of `out`'s comes from.
void wind_back(const PreviewMesh& mesh, const std::vector<size_t>& source, PreviewMesh& out) {
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
}

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
    // (cell, material) -> cluster. A mesh whose triangles share vertices, of one material,
    // finds each vertex's cluster once (they are numbered in the order the corners meet them
    // either way).
    const bool one_material = std::adjacent_find(mesh.materials.begin(), mesh.materials.end(),
                                                 std::not_equal_to<>()) == mesh.materials.end();
    const bool shared = one_material && mesh.positions.size() < mesh.indices.size();
    std::vector<uint32_t> cluster_of(shared ? mesh.positions.size() : 0, ~0u);
    FlatMap id_of(1 << 14);  // the clusters are few: about the cells the surface crosses
    std::vector<Cluster> clusters;
    const bool uvs = mesh.uvs.size() == mesh.positions.size();
    const auto corner = [&](size_t t, int k) {
        const uint32_t v = mesh.indices[t * 3 + static_cast<size_t>(k)];
        const Vec3& p = mesh.positions[v];
        uint32_t id = shared ? cluster_of[v] : ~0u;
        if (id == ~0u) {
            const uint64_t key =
                (index(p.x, box.lo.x) | index(p.y, box.lo.y) << 21 | index(p.z, box.lo.z) << 42) ^
                static_cast<uint64_t>(mesh.materials[t]) * 0x9E3779B97F4A7C15ull;
            bool fresh = false;
            std::tie(id, fresh) = id_of.try_emplace(key, static_cast<uint32_t>(clusters.size()));
            if (fresh) {
                clusters.emplace_back();
                clusters.back().uv = uvs ? mesh.uvs[v] : Vec2(0.0);
            }
            if (shared) cluster_of[v] = id;
        }
        Cluster& c = clusters[id];
        c.position += p;
        c.normal += mesh.normals[v];
        c.count += 1;
        return id;
    };
    PreviewMesh out;
    std::vector<size_t> source;  // the mesh's triangle each kept one comes from
    FlatMap seen(1 << 16);       // the sorted corners of each triangle kept
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        std::array<uint32_t, 3> c{corner(t, 0), corner(t, 1), corner(t, 2)};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        std::array<uint32_t, 3> sorted = c;
        std::sort(sorted.begin(), sorted.end());
        const uint64_t key =
            (static_cast<uint64_t>(sorted[0]) * 0x100000001B3ull ^ sorted[1]) * 0x100000001B3ull ^
            sorted[2];
        if (!seen.try_emplace(key, 0).second) continue;
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
    wind_back(mesh, source, out);
    return out;
}

// Appends one shape primitive (or CSG leaf) of the set, tagged with CSG leaf `csg` (-1: none),
// and what it is to `shapes` (a triangle that follows one of its material: into its run).
void append_primitive(const GeometrySet& set, const Primitive& p, int detail, int csg,
                      PreviewMesh& out, std::vector<PreviewShape>* shapes) {
    const size_t before = out.triangle_count();
    const PreviewShape shape = visit_shape(set, p, [&](const auto& s) {
        if constexpr (std::is_same_v<std::decay_t<decltype(s)>, Triangle>)
            return append_preview(s, set.triangle_attribs(p.index), p.material, out);
        else
            return append_preview(
                s, p.transform < 0 ? nullptr : &set.transforms[static_cast<size_t>(p.transform)],
                p.material, detail, out);
    });
    if (shapes) {
        PreviewShape* run = shapes->empty() ? nullptr : &shapes->back();
        if (shape.kind == ShapeKind::Triangle && run && run->kind == ShapeKind::Triangle &&
            run->first + run->count == shape.first && out.materials[run->first] == p.material)
            run->count += shape.count;
        else
            shapes->push_back(shape);
    }
    if (csg < 0 && out.csg.empty()) return;
    out.csg.resize(before, -1);
    out.csg.resize(out.triangle_count(), csg);
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

PreviewMesh tessellate_set(const GeometrySet& set, int detail, std::vector<PreviewShape>* shapes) {
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
            append_primitive(set, p, detail, -1, out, shapes);
            continue;
        }
        // The leaves whole, each tagged with its index (PreviewMesh::csg).
        const CsgRoot& r = set.csg.roots[static_cast<size_t>(p.csg)];
        for (uint32_t l = r.first_leaf; l < r.first_leaf + r.leaf_count; ++l)
            append_primitive(set, set.csg.leaves[l].prim, detail, static_cast<int>(l), out, shapes);
    }
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
        s.mesh = tessellate_set(scene.sets[si], detail, &s.shapes);
        add_csg_leaves(scene.sets[si], &s.mesh, &s.csg);
        if (s.mesh.triangle_count() > kCoarseAbove && s.csg.leaf_of_vertex.empty())
            s.coarse = decimate(s.mesh, kCoarseTriangles, cancel);
    }
    return g;
}

}  // namespace rt::view
