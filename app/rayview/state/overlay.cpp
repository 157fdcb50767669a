#include "state/overlay.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#include <variant>

#include "rt/render/sampler.h"
#include "rt/shapes/shapes.h"

namespace rt::view {

Bounds3 view_bounds(const RenderScene& scene) {
    // The scene and what the overlay draws around it (light markers, arrows, cones), so the
    // near and far planes never clip either; the preview and its lines share them, so their
    // depths agree.
    Bounds3 b = scene.world_bounds;
    if (b.empty()) return b;
    const double size = glm::length(b.diagonal());
    const Vec3 centre = b.centre();
    for (const Light& l : scene.lights) {
        b.extend(l.kind == LightKind::Directional ? centre - 0.3 * size * l.direction : l.position);
        if (l.kind == LightKind::Sphere)
            b.extend(Bounds3{l.position - l.radius, l.position + l.radius});
    }
    const Vec3 margin(0.2 * size);  // marker arms, spot cones (0.15 of the size), rounding
    return {b.lo - margin, b.hi + margin};
}

namespace {

struct LineBuilder {
    std::vector<LineVertex> out;
    void segment(const Vec3& a, const Vec3& b, const Vec3& c) {
        LineVertex va{}, vb{};
        for (int k = 0; k < 3; ++k) {
            va.position[k] = static_cast<float>(a[k]);
            vb.position[k] = static_cast<float>(b[k]);
            va.color[k] = vb.color[k] = static_cast<float>(c[k]);
        }
        out.push_back(va);
        out.push_back(vb);
    }
    // Three great circles (in the xy, yz and zx planes) of 32 segments each.
    void wire_sphere(const Vec3& centre, double radius, const Vec3& c) {
        for (int axis = 0; axis < 3; ++axis) {
            Vec3 e1(0.0), e2(0.0);
            e1[axis] = radius;
            e2[(axis + 1) % 3] = radius;
            for (int k = 0; k < 32; ++k) {
                const double a0 = 2 * kPi * k / 32, a1 = 2 * kPi * (k + 1) / 32;
                segment(centre + std::cos(a0) * e1 + std::sin(a0) * e2,
                        centre + std::cos(a1) * e1 + std::sin(a1) * e2, c);
            }
        }
    }
    // The 12 edges of a box, its corners mapped by `xf` when given.
    void box(const Vec3& lo, const Vec3& hi, const Vec3& c, const Transform* xf) {
        auto corner = [&](int i) {
            const Vec3 p{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
            return xf ? xf->point(p) : p;
        };
        for (int i = 0; i < 8; ++i)
            for (int bit : {1, 2, 4})
                if (!(i & bit)) segment(corner(i), corner(i | bit), c);
    }
};

Vec3 marker_colour(const Vec3& c) {
    const double m = std::max(c.x, std::max(c.y, c.z));
    return m > 0 ? glm::clamp(c / m, 0.2, 1.0) : Vec3(1.0);
}

}  // namespace

std::vector<LineVertex> box_lines(const Bounds3& box, const Vec3& colour) {
    LineBuilder b;
    if (!box.empty()) b.box(box.lo, box.hi, colour, nullptr);
    return std::move(b.out);
}

namespace {

// Light `l`'s marker: a small cross at its position (three circles at its radius for a sphere
// light), and with `direction` a spot's cut-off cone or a directional light's arrows towards the
// scene's centre. `w`: the scene's bounds, `size` their diagonal.
void light_marker(LineBuilder& b, const Light& l, bool direction, const Bounds3& w, double size) {
    const Vec3 c = marker_colour(glm::max(l.diffuse, l.specular));
    const double s = (direction ? 0.03 : 0.015) * size;
    if (l.kind == LightKind::Directional) {
        if (!direction) return;  // no position to mark
        // Parallel rays (unlike a spot's cone): three arrows along the direction of travel
        // towards the scene's centre, side by side, with a bar across their tails.
        const Vec3 centre = w.empty() ? Vec3(0.0) : w.centre();
        Vec3 a1, a2;
        orthonormal_basis(l.direction, &a1, &a2);
        const double gap = 0.06 * size;
        for (int k = -1; k <= 1; ++k) {
            const Vec3 end = centre + (k * gap) * a1;
            b.segment(end - 0.3 * size * l.direction, end, c);
            for (const Vec3& side : {a1, -a1})
                b.segment(end, end - 2 * s * l.direction + s * side, c);
        }
        const Vec3 tail = centre - 0.3 * size * l.direction;
        b.segment(tail - gap * a1, tail + gap * a1, c);
        return;
    }
    for (int axis = 0; axis < 3; ++axis) {
        Vec3 d(0.0);
        d[axis] = s;
        b.segment(l.position - d, l.position + d, c);
    }
    if (l.kind == LightKind::Sphere && l.radius > 0) b.wire_sphere(l.position, l.radius, c);
    if (l.kind == LightKind::Spot && direction) {
        // The cut-off cone, 0.15 of the scene's size long.
        Vec3 a1, a2;
        orthonormal_basis(l.direction, &a1, &a2);
        const double len = 0.15 * size, angle = std::min(l.cutoff_rad, 1.4);
        Vec3 prev(0.0);
        for (int k = 0; k <= 16; ++k) {
            const double phi = 2 * kPi * k / 16;
            const Vec3 rim =
                l.position + len * (std::cos(angle) * l.direction +
                                    std::sin(angle) * (std::cos(phi) * a1 + std::sin(phi) * a2));
            if (k % 4 == 0) b.segment(l.position, rim, c);
            if (k > 0) b.segment(prev, rim, c);
            prev = rim;
        }
    }
}

// An instance's box, its set's BVH node boxes down to `bvh_depth` levels (dimmer deeper down)
// and its CSG nodes' boxes, in world space.
void instance_boxes(LineBuilder& b, const RenderScene& scene, const Instance& inst, int bvh_depth) {
    const Transform* xf = inst.identity ? nullptr : &inst.world_from_set;
    const Bvh& bvh = scene.sets[static_cast<size_t>(inst.set)].bvh;
    b.box(inst.world_bounds.lo, inst.world_bounds.hi, Vec3(1, 1, 0.3), nullptr);
    std::vector<std::pair<uint32_t, int>> stack;
    if (!bvh.empty()) stack.push_back({0u, 1});
    while (!stack.empty()) {
        const auto [node_index, depth] = stack.back();
        stack.pop_back();
        const Bvh4Node& node = bvh.nodes[node_index];
        const double fade = 1.0 / depth;
        for (uint32_t c = 0; c < node.num_children; ++c) {
            const Vec3 lo(node.lo[0][c], node.lo[1][c], node.lo[2][c]);
            const Vec3 hi(node.hi[0][c], node.hi[1][c], node.hi[2][c]);
            b.box(lo, hi, Vec3(0.3, 1.0, 0.5) * fade + Vec3(0.1), xf);
            if (!(node.child[c] & Bvh4Node::kLeaf) && depth < bvh_depth)
                stack.push_back({node.child[c], depth + 1});
        }
    }
    // The CSG nodes' own boxes (spec §13.8's informative bounds), in blue.
    for (const CsgNode& n : scene.sets[static_cast<size_t>(inst.set)].csg.nodes)
        if (n.kind != CsgNodeKind::Leaf && n.kind != CsgNodeKind::List && !n.bounds.empty())
            b.box(n.bounds.lo, n.bounds.hi, Vec3(0.3, 0.6, 1.0), xf);
}

}  // namespace

std::vector<LineVertex> overlay_lines(const RenderScene& scene, const LightMarkers& lights,
                                      int bvh_depth) {
    LineBuilder b;
    const Bounds3& w = scene.world_bounds;
    const double size = w.empty() ? 1.0 : glm::length(w.diagonal());
    if (lights.show)
        for (size_t li = 0; li < scene.lights.size(); ++li)
            light_marker(b, scene.lights[li],
                         lights.directions || static_cast<int>(li) == lights.selected, w, size);
    if (bvh_depth > 0)
        for (const Instance& inst : scene.instances) instance_boxes(b, scene, inst, bvh_depth);
    return std::move(b.out);
}

namespace {

// The world bounds of a group's own shapes under m.
Bounds3 shape_bounds(const FileDesc& f, const GroupDesc& g, const Mat4& m) {
    Bounds3 b;
    for (const ShapeDesc& shape : g.shapes) b.extend(bounds(shape, f, m));
    return b;
}

}  // namespace

namespace {

// A CSG operand that only wraps one list (no shapes, matrix or other children of its own) adds
// no box of its own: its list is the operand's box.
bool wrapper(const GroupDesc& g) {
    return g.shapes.empty() && g.instances.empty() && g.csgs.empty() && g.groups.size() == 1 &&
           g.matrix == Mat4(1.0) && g.joint.empty();
}

// The bounds of a CSG node from its operands' (spec §13.8, informative): union: their union;
// intersection: their intersection; difference: A's.
void combine(CsgOp op, size_t operand, const Bounds3& child, Bounds3* node) {
    if (op == CsgOp::Union || operand == 0) {
        node->extend(child);
    } else if (op == CsgOp::Intersection) {
        node->lo = glm::max(node->lo, child.lo);
        node->hi = glm::min(node->hi, child.hi);
        if (node->empty()) *node = Bounds3{};
    }
}

}  // namespace

std::vector<LineVertex> group_box_lines(const SceneDesc& desc, int depth) {
    if (depth <= 0 || desc.files.empty()) return {};
    // A walk with an explicit stack (groups nest 10^4 deep and includes 200 files deep), each
    // group's bounds the union of its shapes' and its children's, a CSG node's those of its
    // operands combined by its operation, a box drawn when it closes.
    struct Frame {
        int file;
        const GroupDesc* group;  // a list, transform or CSG operand; null for a CSG node
        const CsgDesc* csg;      // the CSG node, when group is null
        Mat4 m;
        int level;
        bool drawn;
        Bounds3 b;
        size_t child = 0, instance = 0, node = 0;
    };
    LineBuilder lines;
    size_t budget = 200000;  // group visits: a scene of millions of instances draws a sample
    std::vector<Frame> stack;
    auto push = [&](int file, const GroupDesc& g, const Mat4& parent, int level) {
        const Mat4 m = parent * g.matrix;
        const bool operand = !stack.empty() && stack.back().csg;
        const bool drawn = !(operand && wrapper(g));
        stack.push_back({file, &g, nullptr, m, drawn ? level : level - 1, drawn,
                         shape_bounds(desc.files[static_cast<size_t>(file)], g, m)});
        --budget;
    };
    push(0, desc.files[0].root, Mat4(1.0), 0);
    while (!stack.empty()) {
        Frame& top = stack.back();
        const FileDesc& f = desc.files[static_cast<size_t>(top.file)];
        if (top.csg) {
            if (budget > 0 && top.child < top.csg->operands.size()) {
                const GroupDesc& operand = top.csg->operands[top.child++];
                push(top.file, operand, top.m, top.level + 1);  // invalidates `top`
                continue;
            }
        } else if (budget > 0 && top.child < top.group->groups.size()) {
            const GroupDesc& child = top.group->groups[top.child++];
            push(top.file, child, top.m, top.level + 1);  // invalidates `top`
            continue;
        } else if (budget > 0 && top.instance < top.group->instances.size()) {
            const InstanceDesc& inst = top.group->instances[top.instance++];
            const int sub = f.ray_files[static_cast<size_t>(inst.ray_file)];
            push(sub, desc.files[static_cast<size_t>(sub)].root, top.m, top.level + 1);
            continue;
        } else if (budget > 0 && top.node < top.group->csgs.size()) {
            const CsgDesc& node = top.group->csgs[top.node++];
            const Frame next{top.file, nullptr, &node, top.m, top.level + 1, true, Bounds3{}};
            stack.push_back(next);  // invalidates `top`
            --budget;
            continue;
        }
        const Frame done = top;
        stack.pop_back();
        if (done.drawn && done.level >= 1 && done.level <= depth && !done.b.empty()) {
            const Vec3 colour = done.csg ? Vec3(0.3, 0.6, 1.0) : Vec3(1.0, 0.55, 0.2);
            lines.box(done.b.lo, done.b.hi, colour / static_cast<double>(done.level) + Vec3(0.15),
                      nullptr);
        }
        if (stack.empty()) break;
        Frame& parent = stack.back();
        if (parent.csg)
            combine(parent.csg->op, parent.child - 1, done.b, &parent.b);
        else
            parent.b.extend(done.b);
    }
    return std::move(lines.out);
}

std::vector<LineVertex> inspect_lines(const PixelTree& tree, double tick, double miss_length,
                                      int hovered) {
    LineBuilder b;
    auto colour = [](const float* c) { return Vec3(c[0], c[1], c[2]); };
    for (size_t i = 0; i < tree.rays.size(); ++i) {
        const InspectRay& r = tree.rays[i];
        const bool hot = static_cast<int>(i) == hovered;
        const float* c = hot                                     ? InspectColours::hovered
                         : r.kind == InspectRay::Kind::Camera    ? InspectColours::camera
                         : r.kind == InspectRay::Kind::Reflected ? InspectColours::reflected
                                                                 : InspectColours::refracted;
        const double len = glm::length(r.ray.d);
        if (!(len > 0.0)) continue;
        b.segment(r.ray.o, r.hit ? r.point : r.ray.o + (miss_length / len) * r.ray.d, colour(c));
        if (!r.hit) continue;
        b.segment(r.point, r.point + tick * r.n,
                  colour(hot ? InspectColours::hovered : InspectColours::normal));
        for (const InspectLight& light : r.lights)
            for (const InspectShadowRay& s : light.shadow_rays) {
                const bool blocked = s.transmittance == Vec3(0.0);
                const Vec3 sc = colour(hot       ? InspectColours::hovered
                                       : blocked ? InspectColours::shadow_blocked
                                                 : InspectColours::shadow_lit);
                // Toward a point t runs in (0, 1); toward a direction as far as a miss goes.
                const double sl = glm::length(s.ray.d);
                if (!(sl > 0.0)) continue;
                double t_end = std::isfinite(s.t_max) ? s.t_max : miss_length / sl;
                if (blocked && !s.occluders.empty()) t_end = s.occluders.back().t;
                const Vec3 e = s.ray.o + t_end * s.ray.d;
                b.segment(s.ray.o, e, sc);
                if (!blocked) continue;
                for (int axis = 0; axis < 3; ++axis) {
                    Vec3 d(0.0);
                    d[axis] = 0.5 * tick;
                    b.segment(e - d, e + d, sc);
                }
            }
    }
    return std::move(b.out);
}

}  // namespace rt::view
