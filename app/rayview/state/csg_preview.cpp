#include "state/csg_preview.h"

#include <cmath>

namespace rt::view {

namespace {

// The shape's kind and parameters for csg_sign in preview.frag: (centre, a) and (b, c).
struct LeafShape {
    float kind = 4;  // triangle: never inside
    Vec3 centre{0.0};
    float a = 0, b = 0, c = 0;
};

// Its numbers in the order its directive lists them (shapes.h): the centre, then its sizes.
LeafShape leaf_shape(const GeometrySet& set, const Primitive& p) {
    LeafShape s;
    visit_shape(set, p, [&](auto shape) {
        using T = decltype(shape);
        s.kind = static_cast<float>(T::kKind);
        if constexpr (requires(T t, LeafShape & l) { t.params(l); }) {
            struct Take {
                LeafShape& s;
                int sizes = 0;
                void point(const Vec3& v) { s.centre = v; }
                void size(double x, const char*) {
                    (sizes == 0 ? s.a : sizes == 1 ? s.b : s.c) = static_cast<float>(x);
                    ++sizes;
                }
            } take{s};
            shape.params(take);
        }
    });
    return s;
}

float node_kind(CsgNodeKind k) {
    switch (k) {
        case CsgNodeKind::Leaf:
            return 0;
        case CsgNodeKind::Union:
            return 1;
        case CsgNodeKind::Intersection:
            return 2;
        case CsgNodeKind::Difference:
            return 3;
        case CsgNodeKind::List:
            return 4;
        case CsgNodeKind::Empty:
            break;
    }
    return 5;
}

}  // namespace

// The trees in preview.frag's layout.
static CsgTexels csg_texels(const GeometrySet& set) {
    const CsgArrays& csg = set.csg;
    CsgTexels out;
    auto texel = [&](double x, double y, double z, double w) {
        for (double v : {x, y, z, w}) out.texels.push_back(static_cast<float>(v));
    };
    out.nodes = 0;
    for (const CsgNode& n : csg.nodes) {
        texel(node_kind(n.kind), n.first, n.count, n.parent);
        texel(n.subtree_first, 0, 0, 0);
    }
    out.children = static_cast<int>(out.texels.size() / 4);
    for (uint32_t c : csg.children) texel(c, 0, 0, 0);
    out.leaves = static_cast<int>(out.texels.size() / 4);
    for (const CsgLeaf& l : csg.leaves) {
        const LeafShape s = leaf_shape(set, l.prim);
        // float positions: the tolerance grows from 1e-9 to 1e-5 of the leaf's scale (c + size)
        texel(s.kind, 1e4 * l.epsilon, l.node, 0);
        const Mat4 inv = l.prim.transform < 0
                             ? Mat4(1.0)
                             : set.transforms[static_cast<size_t>(l.prim.transform)].inv;
        for (int r = 0; r < 3; ++r) texel(inv[0][r], inv[1][r], inv[2][r], inv[3][r]);
        texel(s.centre.x, s.centre.y, s.centre.z, s.a);
        texel(s.b, s.c, 0, 0);
    }
    return out;
}

void add_csg_leaves(const GeometrySet& set, PreviewMesh* mesh, CsgTexels* texels) {
    if (set.csg.leaves.empty()) return;
    *texels = csg_texels(set);
    // tessellate_set tags each leaf's triangles with the leaf; its vertices are its own.
    texels->leaf_of_vertex.assign(mesh->positions.size(), -1.0f);
    if (mesh->csg.size() == mesh->triangle_count())
        for (size_t t = 0; t < mesh->triangle_count(); ++t)
            for (int k = 0; k < 3; ++k)
                texels->leaf_of_vertex[mesh->indices[3 * t + static_cast<size_t>(k)]] =
                    static_cast<float>(mesh->csg[t]);
    mesh->csg.clear();
}

}  // namespace rt::view
