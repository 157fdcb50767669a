// NOT AN ORDINARY HEADER: a source file that three units compile, one per instruction set.
// Include it only from walks_sse2.cpp, walks_avx2.cpp and walks_avx512.cpp, once each: it defines
// functions (not inline) in the namespace of the unit's ISA, and its tail under
// `#ifdef RT_ISA_SSE2` defines intersect_brute_force() and intersect_primitive() once, in the
// SSE2 unit. Nothing else includes it; queries.h declares what it defines.
//
// The ray queries on a RenderScene, one compiled walk per geometry variant (queries.h), as one
// kernel family compiled per instruction set (isa_target.h). intersect.cpp picks the table of the
// active one.
#pragma once

#include <algorithm>
#include <array>
#include <type_traits>
#include <utility>
#include <vector>

#include "accel/isa_target.h"
#include "accel/queries.h"
#include "accel/triangle_kernel.h"
#include "accel/walk4.h"
#include "accel/walk8.h"
#include "rt/accel/intersect.h"

RT_ISA_BEGIN

namespace {

// Triangle `index` of a Triangles set (packed by leaf) in lane 0 of a block of its own, with the
// same float vertices (lanes do not interact: the same answer): for the brute-force path and the
// benchmark's per-primitive test.
[[gnu::noinline]] int leaf_packed_triangle(const GeometrySet& set, uint32_t index,
                                           const TriRay& tri, Interval t, float tt[4]) {
    Tri4 alone{};
    const Triangle tr = set.triangle(index);
    put_triangle(alone, 0, tr.p0, tr.p1, tr.p2, set.tri_origin);
    return tri4_hits(alone, tri, 1, float_lower(t.lo), float_upper(t.hi), tt) ? 0 : -1;
}

// The one triangle test (spec §5; see triangle4.h): lane `index % 4` of block `index / 4` in a
// Mixed set.
ShapeHits triangle_hits(const GeometrySet& set, uint32_t index, const TriRay& tri, Interval t) {
    ShapeHits h;
    float tt[4];
    int lane = static_cast<int>(index & 3u);
    if (set.layout == SetLayout::Triangles) {
        lane = leaf_packed_triangle(set, index, tri, t, tt);
    } else if (!tri4_hits(set.tri4[index >> 2], tri, 1 << lane, float_lower(t.lo),
                          float_upper(t.hi), tt)) {
        lane = -1;
    }
    if (lane >= 0) {
        const double th = static_cast<double>(tt[lane]);
        if (t.contains(th)) h.add(th, 0);
    }
    return h;
}

// The kinds a set of layout L holds: a single one for the one-kind layouts, so the dispatch on
// them (visit_shape) folds away.
constexpr uint32_t layout_kinds(SetLayout l) {
    switch (l) {
        case SetLayout::Spheres:
            return kind_bit(ShapeKind::Sphere);
        case SetLayout::Boxes:
            return kind_bit(ShapeKind::Box);
        case SetLayout::Cylinders:
            return kind_bit(ShapeKind::Cylinder);
        case SetLayout::Cones:
            return kind_bit(ShapeKind::Cone);
        case SetLayout::Triangles:
            return kind_bit(ShapeKind::Triangle);
        case SetLayout::Analytic:
            return kAnalyticKinds;
        case SetLayout::Mixed:
            break;
    }
    return kAllKinds;
}

// Every hit of one primitive of a set, for a ray in the set's frame. Without kXf no primitive
// has a transform; `tri` is the ray set up for the triangle kernel, read only where the layout
// has triangles (Mixed; Triangles sets take the packed walk).
template <SetLayout L, bool kXf>
ShapeHits prim_hits(const GeometrySet& set, const Primitive& p, const Ray& ray, const TriRay* tri,
                    Interval t) {
    if constexpr (L == SetLayout::Mixed)
        if (p.kind == ShapeKind::Triangle) return triangle_hits(set, p.index, *tri, t);
    const Ray* r = &ray;
    Ray local;
    if constexpr (kXf) {
        if (p.transform >= 0) {
            local = set.transforms[static_cast<size_t>(p.transform)].inv_ray(ray);
            r = &local;
        }
    }
    return visit_shape<layout_kinds(L) & kAnalyticKinds>(
        set, p, [&](const auto& shape) { return intersect(shape, *r, t); });
}

// CSG (spec §13.8). Inside flags of a point for a node: strictly inside, inside or on.
constexpr uint8_t kStrict = 1, kOnOrIn = 2;

uint8_t leaf_inside(const GeometrySet& set, const CsgLeaf& leaf, const Vec3& p_set) {
    const Primitive& pr = leaf.prim;
    const Vec3 q = pr.transform < 0
                       ? p_set
                       : set.transforms[static_cast<size_t>(pr.transform)].inv_point(p_set);
    const double sgn = visit_shape(set, pr, [&](const auto& shape) { return csg_sign(shape, q); });
    return static_cast<uint8_t>((sgn < -leaf.epsilon ? kStrict : 0) |
                                (sgn <= leaf.epsilon ? kOnOrIn : 0));
}

// A node's flags from its children's (spec §13.8's table of composite shapes).
uint8_t combine_inside(CsgNodeKind kind, const uint8_t* v, uint32_t count) {
    uint8_t r = 0;
    switch (kind) {
        case CsgNodeKind::Union:
        case CsgNodeKind::List:
            for (uint32_t i = 0; i < count; ++i) r |= v[i];
            return r;
        case CsgNodeKind::Intersection:
            r = count > 0 ? kStrict | kOnOrIn : 0;
            for (uint32_t i = 0; i < count; ++i) r &= v[i];
            return r;
        case CsgNodeKind::Difference: {
            const uint8_t a = v[0], b = count > 1 ? v[1] : 0;
            return static_cast<uint8_t>(((a & kStrict) && !(b & kOnOrIn) ? kStrict : 0) |
                                        ((a & kOnOrIn) && !(b & kStrict) ? kOnOrIn : 0));
        }
        case CsgNodeKind::Leaf:
        case CsgNodeKind::Empty:
            break;
    }
    return 0;
}

// The flags of node `node` at p: its subtree in post-order with a stack of flags (no recursion,
// trees nest as deep as the file does).
uint8_t node_inside(const GeometrySet& set, uint32_t node, const Vec3& p_set) {
    const CsgArrays& c = set.csg;
    const CsgNode& top = c.nodes[node];
    if (top.kind == CsgNodeKind::Leaf) return leaf_inside(set, c.leaves[top.first], p_set);
    const size_t n = node - top.subtree_first + 1;
    // Up to 64 nodes on the stack; larger trees reuse one buffer per thread (no allocation per
    // hit once it has grown).
    uint8_t small[64] = {};
    static thread_local std::vector<uint8_t> big;
    if (n > sizeof small && big.size() < n) big.resize(n);
    uint8_t* stack = n > sizeof small ? big.data() : small;
    size_t sp = 0;
    for (uint32_t i = top.subtree_first; i <= node; ++i) {
        const CsgNode& nd = c.nodes[i];
        if (nd.kind == CsgNodeKind::Leaf) {
            stack[sp++] = leaf_inside(set, c.leaves[nd.first], p_set);
            continue;
        }
        sp -= nd.count;
        stack[sp] = combine_inside(nd.kind, stack + sp, nd.count);
        ++sp;
    }
    return stack[0];
}

// Whether every CSG node from the leaf up to its root keeps the leaf's surface point p (spec
// §13.8, valid surfaces); lists between do not filter.
bool csg_accepts(const GeometrySet& set, const CsgLeaf& leaf, const Vec3& p_set) {
    const CsgArrays& c = set.csg;
    uint32_t node = leaf.node;
    for (int up = c.nodes[node].parent; up >= 0;
         node = static_cast<uint32_t>(up), up = c.nodes[static_cast<size_t>(up)].parent) {
        const CsgNode& n = c.nodes[static_cast<size_t>(up)];
        const uint32_t* kids = &c.children[n.first];
        if (n.kind == CsgNodeKind::Union) {
            for (uint32_t k = 0; k < n.count; ++k)
                if (kids[k] != node && (node_inside(set, kids[k], p_set) & kStrict)) return false;
        } else if (n.kind == CsgNodeKind::Intersection) {
            for (uint32_t k = 0; k < n.count; ++k)
                if (kids[k] != node && !(node_inside(set, kids[k], p_set) & kOnOrIn)) return false;
        } else if (n.kind == CsgNodeKind::Difference) {
            if (kids[0] == node) {
                if (n.count > 1 && (node_inside(set, kids[1], p_set) & kStrict)) return false;
            } else if (!(node_inside(set, kids[0], p_set) & kStrict)) {
                return false;
            }
        }
    }
    return true;
}

// Calls f(ShapeHits of one hit, on one leaf, t) for every valid hit of CSG primitive p in t, in
// no order; f may shrink t.hi for the leaves still to test, and returns true to stop (and so
// does this).
template <bool kXf, class F>
bool csg_each(const GeometrySet& set, const Primitive& p, const Ray& r, const TriRay* tri,
              Interval t, F&& f) {
    const CsgRoot& root = set.csg.roots[static_cast<size_t>(p.csg)];
    for (uint32_t l = root.first_leaf; l < root.first_leaf + root.leaf_count; ++l) {
        const CsgLeaf& leaf = set.csg.leaves[l];
        const ShapeHits h = prim_hits<SetLayout::Mixed, kXf>(set, leaf.prim, r, tri, t);
        for (int k = 0; k < h.count && h.t[k] < t.hi; ++k) {
            if (!csg_accepts(set, leaf, r.at(h.t[k]))) continue;
            ShapeHits one;
            one.add(h.t[k], h.part[k]);
            one.leaf = static_cast<int>(l);
            if (f(one, t)) return true;
        }
    }
    return false;
}

// The nearest valid hit of CSG primitive p in t (none: count 0): each leaf is tested in what is
// left of the interval, and its hits come nearest first.
template <bool kXf>
ShapeHits csg_nearest(const GeometrySet& set, const Primitive& p, const Ray& r, const TriRay* tri,
                      Interval t) {
    ShapeHits best;
    csg_each<kXf>(set, p, r, tri, t, [&](const ShapeHits& one, Interval& left) {
        best = one;
        left.hi = one.t[0];
        return false;
    });
    return best;
}

template <bool kXf>
Ray to_set(const Instance& inst, const Ray& ray) {
    if constexpr (kXf) return inst.identity ? ray : inst.world_from_set.inv_ray(ray);
    return ray;
}

// Calls hits(prim, ShapeHits, t_max) for the primitives of a set along a ray in its frame;
// hits returns true to stop the walk. Triangle-only sets test each leaf's triangles four at a
// time (packed in leaf order), under the 8-wide nodes where there are and the caller's answer
// does not depend on the order the leaves come in (kAnyOrder); the other layouts test one
// primitive at a time.
template <bool kOrdered, bool kAnyOrder, SetLayout L, bool kXf, bool kCsg, class F>
bool walk_set(const GeometrySet& set, const Ray& r, double& t_max, double t_min, F&& hits) {
    bool stopped = false;
    if constexpr (L == SetLayout::Triangles) {
        // For the closest hit, set up at the first leaf: a third of the primary rays on a mesh
        // reach none. Shadow rays start on a surface and nearly all reach one.
        TriRay tri = kOrdered ? TriRay() : TriRay({r.o - set.tri_origin, r.d});
        bool tri_ready = !kOrdered;
        // Of hits at the same distance the lowest primitive index wins, whatever the order the
        // leaves come in: the 4-wide and the 8-wide trees find the same one.
        uint32_t best_prim = ~0u;
        auto leaf = [&](uint32_t first, uint32_t count, double& best) {
            if (!tri_ready) {
                tri = TriRay({r.o - set.tri_origin, r.d});
                tri_ready = true;
            }
            return leaf_block_hits(
                set.tri4.data(), first, count, tri, float_lower(t_min), best,
                [&](uint32_t b, int l, double th) {
                    const uint32_t prim = set.tri4_prim[b][static_cast<size_t>(l)];
                    if (!(th > t_min &&
                          (th < best || (kOrdered && th == best && prim < best_prim))))
                        return false;
                    ShapeHits h;
                    h.add(th, 0);
                    best_prim = prim;
                    return stopped = hits(prim, h, best);
                });
        };
#if !defined(RT_ISA_SSE2)
        if constexpr (kAnyOrder) {
            traverse_leaves_wide<kOrdered>(set.bvh, r, t_max, leaf);
            return stopped;
        }
#endif
        traverse_leaves<kOrdered>(set.bvh, r, t_max, leaf);
    } else {
        // A triangles-only set's leaves name packed blocks, not primitive ranges: the generic
        // walk takes the packed one there too.
        if constexpr (L == SetLayout::Mixed)
            if (set.layout == SetLayout::Triangles)
                return walk_set<kOrdered, kAnyOrder, SetLayout::Triangles, false, false>(
                    set, r, t_max, t_min, hits);
        TriRay tri;
        if constexpr (L == SetLayout::Mixed) tri = TriRay({r.o - set.tri_origin, r.d});
        traverse<kOrdered>(set.bvh, r, t_max, [&](uint32_t pi, double& best) {
            const Primitive& p = set.prims[pi];
            if constexpr (kCsg) {
                if (p.csg >= 0) {
                    if constexpr (kOrdered)
                        return stopped =
                                   hits(pi, csg_nearest<kXf>(set, p, r, &tri, {t_min, best}), best);
                    else
                        return stopped = csg_each<kXf>(set, p, r, &tri, {t_min, best},
                                                       [&](const ShapeHits& h, Interval&) {
                                                           return hits(pi, h, best);
                                                       });
                }
            }
            return stopped = hits(pi, prim_hits<L, kXf>(set, p, r, &tri, {t_min, best}), best);
        });
    }
    return stopped;
}

// The walk of geometry variant V over one set: its layout when every set shares it, else the
// set's own (one switch per set visited, not per primitive).
template <uint32_t V, bool kOrdered, bool kAnyOrder, class F>
bool walk(const GeometrySet& set, const Ray& r, double& t_max, double t_min, F&& hits) {
    constexpr bool kXf = (V & kGeomTransforms) != 0;
    constexpr bool kCsg = (V & kGeomCsg) != 0;
    constexpr uint32_t kLayout = (V & kGeomPerSet) >> kGeomLayoutShift;
    if constexpr (kLayout < kSetLayouts) {
        constexpr SetLayout kL = static_cast<SetLayout>(kLayout);
        return walk_set < kOrdered, kAnyOrder, kL, kXf,
               kCsg && kL == SetLayout::Mixed > (set, r, t_max, t_min, hits);
    } else {
        switch (set.layout) {
            case SetLayout::Mixed:
                return walk_set<kOrdered, kAnyOrder, SetLayout::Mixed, kXf, kCsg>(set, r, t_max,
                                                                                  t_min, hits);
            case SetLayout::Analytic:
                return walk_set<kOrdered, kAnyOrder, SetLayout::Analytic, kXf, false>(set, r, t_max,
                                                                                      t_min, hits);
            case SetLayout::Spheres:
                return walk_set<kOrdered, kAnyOrder, SetLayout::Spheres, kXf, false>(set, r, t_max,
                                                                                     t_min, hits);
            case SetLayout::Boxes:
                return walk_set<kOrdered, kAnyOrder, SetLayout::Boxes, kXf, false>(set, r, t_max,
                                                                                   t_min, hits);
            case SetLayout::Cylinders:
                return walk_set<kOrdered, kAnyOrder, SetLayout::Cylinders, kXf, false>(
                    set, r, t_max, t_min, hits);
            case SetLayout::Cones:
                return walk_set<kOrdered, kAnyOrder, SetLayout::Cones, kXf, false>(set, r, t_max,
                                                                                   t_min, hits);
            case SetLayout::Triangles:
                return walk_set<kOrdered, kAnyOrder, SetLayout::Triangles, kXf, false>(
                    set, r, t_max, t_min, hits);
        }
        return false;
    }
}

// Calls f(instance index, ray in the set's frame, t_max) for the instances whose box the ray
// enters; without kGeomInstancing the one instance is walked directly (no top-level BVH).
template <uint32_t V, bool kOrdered, class F>
void for_each_instance(const RenderScene& scene, const Ray& ray, double& t_max, F&& f) {
    constexpr bool kXf = (V & kGeomTransforms) != 0;
    if constexpr ((V & kGeomInstancing) == 0) {
        f(0u, to_set<kXf>(scene.instances[0], ray), t_max);
    } else {
        traverse<kOrdered>(scene.top, ray, t_max, [&](uint32_t ii, double& best) {
            return f(ii, to_set<kXf>(scene.instances[ii], ray), best);
        });
    }
}

template <uint32_t V>
bool closest_hit(const RenderScene& scene, const Ray& ray, Interval t, Hit* hit) {
    double t_max = t.hi;
    bool found = false;
    for_each_instance<V, true>(scene, ray, t_max, [&](uint32_t ii, const Ray& r, double& best) {
        const GeometrySet& set = scene.sets[static_cast<size_t>(scene.instances[ii].set)];
        walk<V, true, true>(set, r, best, t.lo, [&](uint32_t pi, const ShapeHits& h, double& b) {
            if (h.count > 0) {
                b = h.t[0];
                *hit = {h.t[0], static_cast<int>(ii), pi, h.part[0], h.leaf};
                found = true;
            }
            return false;
        });
        return false;
    });
    return found;
}

template <uint32_t V>
bool any_hit(const RenderScene& scene, const Ray& ray, double t_max) {
    double limit = t_max;
    bool hit = false;
    for_each_instance<V, false>(scene, ray, limit, [&](uint32_t ii, const Ray& r, double&) {
        const GeometrySet& set = scene.sets[static_cast<size_t>(scene.instances[ii].set)];
        double inner = t_max;
        return hit = walk<V, false, true>(
                   set, r, inner, 0.0,
                   [&](uint32_t, const ShapeHits& h, double&) { return h.count > 0; });
    });
    return hit;
}

template <uint32_t V>
Vec3 transmitted(const RenderScene& scene, const Ray& ray, double t_max) {
    Vec3 s(1.0);
    double limit = t_max;  // never shrinks: every crossing counts, order does not matter
    for_each_instance<V, false>(scene, ray, limit, [&](uint32_t ii, const Ray& r, double&) {
        const GeometrySet& set = scene.sets[static_cast<size_t>(scene.instances[ii].set)];
        double inner = t_max;
        // The product of the crossings depends on their order: the 4-wide tree's, under every set.
        return walk<V, false, false>(
            set, r, inner, 0.0, [&](uint32_t pi, const ShapeHits& h, double&) {
                int material = set.prims[pi].material;
                if constexpr ((V & kGeomCsg) != 0)
                    if (h.leaf >= 0)
                        material = set.csg.leaves[static_cast<size_t>(h.leaf)].prim.material;
                const Vec3& tr = scene.materials[static_cast<size_t>(material)].transparent;
                for (int k = 0; k < h.count; ++k) s *= tr;
                return h.count > 0 && s == Vec3(0.0);
            });
    });
    return s;
}

// What shading needs at a hit; without kXf (V) no transform is applied.
template <uint32_t V>
SurfaceInteraction surface_interaction(const RenderScene& scene, const Ray& ray, const Hit& hit,
                                       bool uv) {
    constexpr bool kXf = (V & kGeomTransforms) != 0;
    const Instance& inst = scene.instances[static_cast<size_t>(hit.instance)];
    const GeometrySet& set = scene.sets[static_cast<size_t>(inst.set)];
    const Primitive* prim = &set.prims[hit.prim];
    const CsgLeaf* leaf = nullptr;  // a CSG primitive's hit is on one of its leaves
    if constexpr ((V & kGeomCsg) != 0) {
        if (hit.leaf >= 0) {
            leaf = &set.csg.leaves[static_cast<size_t>(hit.leaf)];
            prim = &leaf->prim;
        }
    }
    const Primitive& p = *prim;
    const Ray r_set = to_set<kXf>(inst, ray);

    SurfacePoint sp;
    const Transform* shape_xf =
        !kXf || p.transform < 0 ? nullptr : &set.transforms[static_cast<size_t>(p.transform)];
    const Ray r = shape_xf ? shape_xf->inv_ray(r_set) : r_set;
    // The layout every set shares fixes the kind; per set (kGeomPerSet) it is read.
    constexpr uint32_t kLayout = (V & kGeomPerSet) >> kGeomLayoutShift;
    constexpr SetLayout kFixed =
        kLayout < kSetLayouts ? static_cast<SetLayout>(kLayout) : SetLayout::Mixed;
    sp = visit_shape<layout_kinds(kFixed)>(set, p, [&](const auto& shape) {
        if constexpr (std::is_same_v<std::decay_t<decltype(shape)>, Triangle>)
            return surface_at(shape, set.triangle_attribs(p.index), r, hit.t, uv, set.tri_origin);
        else
            return surface_at(shape, r, hit.t, hit.part, uv);
    });
    // Shape frame -> set frame -> world: points by M, normals by (A^-1)^T (spec §4.1). The error
    // bound grows by |A| applied to the local bound plus the rounding of the transform itself
    // (pbrt-v4's Transform error bounds, Pharr, Jakob, Humphreys, 4th ed. §6.8.6), plus the image
    // under |A| of the rounding that mapping a spawned ray's origin back through M^-1 adds in the
    // local frame: under extreme non-uniform scale (1e-4 on one axis, a translation of 100) that
    // term dominates, and without it a spawned ray re-hit its own cone.
    auto apply = [](const Transform& xf, SurfacePoint& s) {
        const Mat3 a(xf.m), inv(xf.inv);
        Mat3 abs_a, abs_inv;
        for (int c = 0; c < 3; ++c) abs_a[c] = glm::abs(a[c]), abs_inv[c] = glm::abs(inv[c]);
        const Vec3 p_new = xf.point(s.p);
        const Vec3 back_err =
            gamma(3) * (abs_inv * glm::abs(p_new) + glm::abs(Vec3(xf.inv[3])) + s.p_error);
        s.p_error = abs_a * (s.p_error + back_err) +
                    gamma(3) * (abs_a * glm::abs(s.p) + glm::abs(Vec3(xf.m[3])));
        s.p = p_new;
        s.n_geometric = glm::normalize(xf.normal_dir(s.n_geometric));
        s.n_shading = glm::normalize(xf.normal_dir(s.n_shading));
    };
    if constexpr (kXf) {
        if (shape_xf) apply(*shape_xf, sp);
        if (!inst.identity) apply(inst.world_from_set, sp);
    }

    // B's surface faces out of A - B: negated once per difference with the leaf in B (§13.8).
    if (leaf && leaf->flip) {
        sp.n_geometric = -sp.n_geometric;
        sp.n_shading = -sp.n_shading;
    }

    return {sp, p.material};
}

// The CSG bit matters with the Mixed and per-set layouts only (the others hold no CSG).
constexpr uint32_t canonical_variant(uint32_t v) {
    const uint32_t layout = (v & kGeomPerSet) >> kGeomLayoutShift;
    const bool mixed = layout == static_cast<uint32_t>(SetLayout::Mixed) || layout == kSetLayouts;
    return mixed ? v : v & ~static_cast<uint32_t>(kGeomCsg);
}

template <uint32_t... V>
constexpr std::array<GeometryQueries, sizeof...(V)> query_table(
    std::integer_sequence<uint32_t, V...>) {
    return {GeometryQueries{&closest_hit<canonical_variant(V)>, &any_hit<canonical_variant(V)>,
                            &transmitted<canonical_variant(V)>,
                            &surface_interaction<canonical_variant(V)>}...};
}

// Every geometry variant, indexed by its GeomFeature bits.
constexpr auto kQueries = query_table(std::make_integer_sequence<uint32_t, kGeomVariants>{});

// No shapes: nothing is hit, nothing occludes, everything is transmitted.
constexpr GeometryQueries kEmptyQueries{
    [](const RenderScene&, const Ray&, Interval, Hit*) { return false; },
    [](const RenderScene&, const Ray&, double) { return false; },
    [](const RenderScene&, const Ray&, double) { return Vec3(1.0); },
    &surface_interaction<kGeomGeneric>};  // never called: nothing is hit

}  // namespace

const GeometryQueries& geometry_queries(uint32_t variant) {
    if (variant == kGeomEmpty) return kEmptyQueries;
    return kQueries[variant < kGeomVariants ? variant : kGeomGeneric];
}

RT_ISA_END

#ifdef RT_ISA_SSE2
// The brute-force path and the per-primitive test, once (with the baseline kernels: the same
// arithmetic as every other).
namespace rt {

using namespace sse2;

bool intersect_brute_force(const RenderScene& scene, const Ray& ray, Interval t, Hit* hit) {
    double best = t.hi;
    bool found = false;
    for (size_t ii = 0; ii < scene.instances.size(); ++ii) {
        const Instance& inst = scene.instances[ii];
        const GeometrySet& set = scene.sets[static_cast<size_t>(inst.set)];
        const Ray r = to_set<true>(inst, ray);
        const TriRay tri({r.o - set.tri_origin, r.d});
        for (uint32_t pi = 0; pi < set.prims.size(); ++pi) {
            const Primitive& p = set.prims[pi];
            const ShapeHits h =
                p.csg >= 0 ? csg_nearest<true>(set, p, r, &tri, {t.lo, best})
                           : prim_hits<SetLayout::Mixed, true>(set, p, r, &tri, {t.lo, best});
            if (h.count > 0) {
                best = h.t[0];
                *hit = {h.t[0], static_cast<int>(ii), pi, h.part[0], h.leaf};
                found = true;
            }
        }
    }
    return found;
}

ShapeHits intersect_primitive(const GeometrySet& set, uint32_t prim, const Ray& ray_set,
                              Interval t) {
    const TriRay tri({ray_set.o - set.tri_origin, ray_set.d});
    const Primitive& p = set.prims[prim];
    if (p.csg >= 0) return csg_nearest<true>(set, p, ray_set, &tri, t);
    return prim_hits<SetLayout::Mixed, true>(set, p, ray_set, &tri, t);
}

}  // namespace rt
#endif
