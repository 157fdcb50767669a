// The placement of sets in the world at some joint values, shared by compile_scene() and
// animate() (spec §14): only the instances under joints and the top-level BVH depend on the time.
#include "compile/placement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <vector>

#include "rt/compile/compile.h"

namespace rt::compile_detail {

namespace {
Bounds3 shape_world_bounds(const GeometrySet& set, const Primitive& p, const Mat4& world_from_set) {
    const Mat4 m = p.transform < 0
                       ? world_from_set
                       : world_from_set * set.transforms[static_cast<size_t>(p.transform)].m;
    return visit_shape(set, p, [&](const auto& shape) { return bounds(shape, m); });
}

// The world box of a CSG tree, from its leaves' tight world boxes (post-order: a node's children
// are done before it).
Bounds3 csg_world_bounds(const GeometrySet& set, const CsgRoot& root, const Mat4& world_from_set) {
    const CsgArrays& c = set.csg;
    const uint32_t first = c.nodes[root.node].subtree_first;
    std::vector<Bounds3> b(root.node - first + 1);
    std::vector<Bounds3> kids;
    for (uint32_t i = first; i <= root.node; ++i) {
        const CsgNode& n = c.nodes[i];
        if (n.kind == CsgNodeKind::Leaf) {
            b[i - first] = shape_world_bounds(set, c.leaves[n.first].prim, world_from_set);
            continue;
        }
        kids.clear();
        for (uint32_t k = 0; k < n.count; ++k) kids.push_back(b[c.children[n.first + k] - first]);
        b[i - first] = combine_csg_bounds(n.kind, kids.data(), n.count);
    }
    return b.back();
}

// Tight world bounds of one primitive of a set placed by world_from_set (for the default camera).
Bounds3 world_bounds_of(const GeometrySet& set, const Primitive& p, const Mat4& world_from_set) {
    if (p.csg >= 0)
        return csg_world_bounds(set, set.csg.roots[static_cast<size_t>(p.csg)], world_from_set);
    return shape_world_bounds(set, p, world_from_set);
}

}  // namespace

// Geometry must stay within +-1e300 in every frame: beyond that, centroids, extents and areas
// overflow in the BVH build and the traversal. A shape or instance past it is an error at its
// directive (docs/format.md, "our choices").
static constexpr double kMaxCoordinate = 1e300;

bool within_limits(const Bounds3& b) {
    for (int a = 0; a < 3; ++a)
        if (!(std::abs(b.lo[a]) <= kMaxCoordinate && std::abs(b.hi[a]) <= kMaxCoordinate))
            return false;  // also NaN
    return true;
}

// The box of a CSG node from its children's boxes (spec §13.8, informative): union for lists
// and unions, intersection for intersections, A's box for a difference.
Bounds3 combine_csg_bounds(CsgNodeKind kind, const Bounds3* child, uint32_t count) {
    Bounds3 b;
    if (kind == CsgNodeKind::Empty || count == 0) return b;
    if (kind == CsgNodeKind::Difference) return child[0];
    if (kind != CsgNodeKind::Intersection) {
        for (uint32_t i = 0; i < count; ++i) b.extend(child[i]);
        return b;
    }
    b = child[0];
    double size = 0.0;  // the largest child's largest side
    for (uint32_t i = 0; i < count; ++i) {
        if (child[i].empty()) return {};  // an empty child: nothing is inside every child
        b.lo = glm::max(b.lo, child[i].lo);
        b.hi = glm::min(b.hi, child[i].hi);
        const Vec3 d = child[i].diagonal();
        size = std::max({size, d.x, d.y, d.z});
    }
    // A point "on" another child is up to its tolerance (1e-9 of its size and of its distance
    // from the origin) outside it, and outside its box: grown by more than that, also where the
    // boxes only touch (two boxes sharing the face x = 0 meet in a box of width 0 at 0).
    const Vec3 grow = 1e-7 * (glm::abs(b.lo) + glm::abs(b.hi) + Vec3(size));
    const Bounds3 grown{b.lo - grow, b.hi + grow};
    return grown.empty() ? Bounds3{} : grown;
}

Bounds3 tight_world_bounds(const GeometrySet& set, const Mat4& world_from_set) {
    Bounds3 b;
    for (const Primitive& p : set.prims) b.extend(world_bounds_of(set, p, world_from_set));
    return b;
}

namespace {

// The world matrix of every joint node (parents come first) and whether it is left out: under a
// singular joint.
void joint_worlds(const SceneRig& rig, const JointValues& values, std::vector<Mat4>& world,
                  std::vector<char>& hidden) {
    world.assign(rig.joints.size(), Mat4(1.0));
    hidden.assign(rig.joints.size(), 0);
    for (size_t i = 0; i < rig.joints.size(); ++i) {
        const JointNode& j = rig.joints[i];
        const size_t k = static_cast<size_t>(j.track);
        const bool parent_hidden = j.parent >= 0 && hidden[static_cast<size_t>(j.parent)];
        hidden[i] = parent_hidden || values.singular[k];
        if (hidden[i]) continue;
        const Mat4 parent = j.parent < 0 ? Mat4(1.0) : world[static_cast<size_t>(j.parent)];
        world[i] = parent * j.before * values.matrix[k];
    }
}

}  // namespace

double place_instances(RenderScene& scene, const JointValues& values) {
    std::vector<Mat4> world;
    std::vector<char> hidden;
    joint_worlds(scene.rig, values, world, hidden);
    // Built aside and committed at the end: a placement that throws leaves the scene as it was.
    std::vector<Instance> instances;
    Bounds3 world_bounds;
    std::vector<Bounds3> inst_bounds;
    for (const Placement& p : scene.rig.placements) {
        Instance inst = p.instance;
        Bounds3 tight = p.tight;
        const GeometrySet& set = scene.sets[static_cast<size_t>(p.set)];
        if (p.joint >= 0) {
            if (hidden[static_cast<size_t>(p.joint)]) continue;
            inst.set = p.set;
            inst.world_from_set =
                Transform::from_matrix(world[static_cast<size_t>(p.joint)] * p.after);
            inst.identity = inst.world_from_set.is_identity();
            inst.world_bounds = inst.identity ? set.bvh.root_bounds
                                              : inst.world_from_set.apply(set.bvh.root_bounds);
            if (!within_limits(inst.world_bounds))
                throw SceneError(p.at, "joint reaches beyond +-1e300 in the world at " +
                                           time_name(scene.time) +
                                           " (coordinates too large for the renderer)");
            if (!scene.camera) tight = tight_world_bounds(set, inst.world_from_set.m);
        }
        world_bounds.extend(scene.camera ? inst.world_bounds : tight);
        inst_bounds.push_back(inst.world_bounds);
        instances.push_back(inst);
    }
    const auto t0 = std::chrono::steady_clock::now();
    Bvh top = build_bvh(inst_bounds, {1, 16});
    // Instances in the top BVH's leaf order, as for the sets' primitives.
    scene.instances.clear();
    scene.instances.reserve(instances.size());
    for (uint32_t i : top.indices) scene.instances.push_back(instances[i]);
    std::iota(top.indices.begin(), top.indices.end(), 0u);
    scene.top = std::move(top);
    scene.world_bounds = world_bounds;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace rt::compile_detail

namespace rt {

void animate(RenderScene& scene, const SceneDesc& desc, const std::optional<SceneTime>& time,
             Diagnostics* diag) {
    if (scene.rig.recompile) {
        // Compiled again at the new time; what the caller set (camera, lights, materials)
        // stays: the same description compiles the same materials, in the same order.
        RenderScene next = compile_scene(desc, nullptr, time, diag);
        next.camera = scene.camera;
        next.lights = std::move(scene.lights);
        next.materials = std::move(scene.materials);
        next.background = scene.background;
        next.ambient = scene.ambient;
        scene = std::move(next);
        return;
    }
    const JointValues values = joint_values(scene.rig.tracks, time, diag);
    const std::optional<SceneTime> before = scene.time;
    scene.time = time;
    try {
        compile_detail::place_instances(scene, values);
    } catch (...) {
        scene.time = before;
        throw;
    }
}

}  // namespace rt
