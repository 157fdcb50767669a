// The render representation, the contract between the stages: flat arrays with resolved indices
// and cached matrices. compile_scene() (rt/compile/compile.h) writes it from a SceneDesc; the
// accel and render stages read it (and never include compile/). Each .ray file that is instanced
// is compiled once into a GeometrySet (its groups flattened into the file's frame) with its own
// BVH; instances place a set in the world. The renderer never sees text.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rt/accel/bvh.h"
#include "rt/accel/triangle4.h"
#include "rt/image/image.h"
#include "rt/scene/scene_parts.h"
#include "rt/scene/scene_time.h"
#include "rt/shapes/shapes.h"
#include "rt/util/error.h"

namespace rt {

/// One primitive of a set: its kind, its index in the kind's array, its material and, for the
/// analytic shapes, the transform from the shape's frame to the set's frame (-1: identity).
///
/// A CSG node (spec §13.8) is one primitive too: csg >= 0 is its index into the set's
/// CsgArrays::roots, and its surfaces are those of its leaves that the node accepts. Never
/// visit_shape() such a primitive: its kind, index, material and transform are those of one of
/// its leaves, the first analytic one if any (so a walk that forgets the test still reads a real
/// shape, not past an array), which is not what it is. Only Mixed-layout sets hold CSG
/// primitives.
struct Primitive {
    ShapeKind kind = ShapeKind::Sphere;
    uint32_t index = 0;
    int material = 0;
    int transform = -1;
    int csg = -1;
};

/// The nodes of a compiled CSG tree. Transforms, lists and instances inside a CSG node are
/// flattened: each leaf carries its set_from_leaf transform, and a list or an instance's root
/// list becomes a List node (the union of surfaces that filters nothing).
enum class CsgNodeKind : uint8_t { Leaf, Union, Intersection, Difference, List, Empty };

struct CsgNode {
    CsgNodeKind kind = CsgNodeKind::Empty;
    uint32_t first = 0;  // Leaf: index into CsgArrays::leaves; else first of CsgArrays::children
    uint32_t count = 0;  // children (a Difference has two: A then B)
    int parent = -1;     // -1: the root of its tree
    uint32_t subtree_first = 0;  // post-order: the node's subtree is nodes [subtree_first, self]
    Bounds3 bounds;              // in the set's frame (spec §13.8's informative rule)
};

/// A shape under a CSG node: an ordinary primitive of the set's shape arrays (csg == -1) with
/// its material and set_from_leaf transform, not in the set's BVH.
struct CsgLeaf {
    Primitive prim;
    uint32_t node = 0;    // its Leaf node
    bool flip = false;    // inside the second operand of an odd number of differences
    double epsilon = 0.;  // the inside test's tolerance in the leaf's frame (spec §13.8)
};

struct CsgRoot {
    uint32_t node = 0;  // the root node (last of its tree's nodes)
    uint32_t first_leaf = 0, leaf_count = 0;
};

/// The CSG trees of a set: each tree's nodes in post-order (children before their parent).
struct CsgArrays {
    std::vector<CsgNode> nodes;
    std::vector<uint32_t> children;
    std::vector<CsgLeaf> leaves;
    std::vector<CsgRoot> roots;
    /// Operation nodes (union, intersection, difference), as the plan counts them.
    size_t operations() const {
        size_t n = 0;
        for (const CsgNode& nd : nodes)
            n += nd.kind == CsgNodeKind::Union || nd.kind == CsgNodeKind::Intersection ||
                 nd.kind == CsgNodeKind::Difference;
        return n;
    }
};

/// How a set's leaves are walked (intersect.cpp): one shape kind tested without a dispatch, the
/// analytic kinds through a switch, packed triangles four at a time, or any mix of the five.
enum class SetLayout : uint8_t { Mixed, Analytic, Spheres, Boxes, Cylinders, Cones, Triangles };
inline constexpr int kSetLayouts = 7;

/// The compiled geometry of one .ray file, in that file's frame.
struct GeometrySet {
    std::string name;  // the file it came from
    HugePageVector<Primitive> prims;
    ShapeArrays shapes;  // the analytic shapes, one array per kind (shapes.h)
    /// The triangles in float, four per block: what rays test, relative to tri_origin. Mixed
    /// sets pack triangle i in lane i % 4 of block i / 4. Triangles sets pack each BVH leaf in
    /// blocks of its own (its leaves name their first block) and tri4_prim names each lane's
    /// triangle: a leaf of up to four triangles is one test.
    HugePageVector<Tri4> tri4;
    HugePageVector<std::array<uint32_t, 4>> tri4_prim;  // Triangles sets only
    Vec3 tri_origin{0.0};                               // of the set's frame
    /// Per triangle: its three vertices, as indices into the vertex arrays (flattened into the
    /// set's frame). A vertex of a mesh in the set's own frame is kept once for all the
    /// triangles that share it (transformed meshes keep one per triangle corner).
    HugePageVector<std::array<uint32_t, 3>> triangle_vertices;
    HugePageVector<Vec3> vertex_positions;
    // The file's normals (not renormalised: spec §5 normalises the interpolated sum), mapped by
    // a transform's (A^-1)^T when the set's frame is not the file's; zero for none.
    HugePageVector<Vec3> vertex_normals;
    HugePageVector<Vec2> vertex_uvs;
    size_t triangle_count() const { return triangle_vertices.size(); }
    /// Triangle i's corners (in double; tri4 holds them in float for the walk).
    Triangle triangle(size_t i) const {
        const std::array<uint32_t, 3>& v = triangle_vertices[i];
        return {vertex_positions[v[0]], vertex_positions[v[1]], vertex_positions[v[2]]};
    }
    /// Primitive i's bounds in the set's frame, as the compile gave them to the BVH build
    /// (computed again: a set keeps no bounds per primitive).
    Bounds3 prim_bounds(size_t i) const;
    /// Triangle i's normals and uvs (has_normals: all three vertices have one).
    TriangleAttribs triangle_attribs(size_t i) const {
        TriangleAttribs a;
        a.has_normals = true;
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t v = triangle_vertices[i][k];
            a.n[k] = vertex_normals[v];
            a.uv[k] = vertex_uvs[v];
            a.has_normals = a.has_normals && a.n[k] != Vec3(0.0);
        }
        return a;
    }
    std::vector<Transform> transforms;    // set_from_shape for analytic shapes under groups
    Bvh bvh;                              // primitives are stored in its leaf order
    CsgArrays csg;                        // the trees of the CSG primitives (csg >= 0)
    SetLayout layout = SetLayout::Mixed;  // the kinds of prims; Triangles: prims[i] is triangle i
};

/// The sets of a scene. They never change once compiled, so copies of a scene share them: a
/// copy for another time (the viewer's preview while the trace runs) or another thread (a
/// background render) costs its instances, not its geometry. push_back() (the compile) copies
/// the list first when it is shared, so a scene never changes another's sets.
class SetList {
public:
    size_t size() const { return m_sets->size(); }
    bool empty() const { return m_sets->empty(); }
    const GeometrySet& operator[](size_t i) const { return (*m_sets)[i]; }
    std::vector<GeometrySet>::const_iterator begin() const { return m_sets->begin(); }
    std::vector<GeometrySet>::const_iterator end() const { return m_sets->end(); }
    void push_back(GeometrySet set) {
        if (m_sets.use_count() > 1) m_sets = std::make_shared<std::vector<GeometrySet>>(*m_sets);
        m_sets->push_back(std::move(set));
    }

private:
    std::shared_ptr<std::vector<GeometrySet>> m_sets = std::make_shared<std::vector<GeometrySet>>();
};

/// A set placed in the world. Nested instancing is flattened into composed transforms.
struct Instance {
    int set = 0;
    Transform world_from_set;
    bool identity = true;
    Bounds3 world_bounds;
};

/// How the compile placed the sets (spec §14): a placement's world_from_set is the product of
/// the joint matrices of its chain of joints with static matrices between them, so animate()
/// (rt/compile/compile.h) moves joints by computing a few products and rebuilding only the
/// top-level BVH; no set is compiled again. A scene without bound joints has no joint nodes.
struct JointNode {
    int parent = -1;   // the enclosing joint node, -1: the world
    Mat4 before{1.0};  // world(node) = world(parent) * before * J(track)
    int track = 0;     // index into SceneRig::tracks
};

struct Placement {
    int set = 0;
    int joint = -1;     // the innermost joint node it lies under, -1: none (a static instance)
    Mat4 after{1.0};    // world_from_set = world(joint) * after
    SourceLoc at;       // the #ray_file_instance or joint that placed it (messages)
    Instance instance;  // a static placement's instance, ready (joint == -1)
    Bounds3 tight;      // a static placement's tight world bounds (only for a scene without camera)
};

struct SceneRig {
    std::vector<KeyTrack> tracks;
    std::vector<JointNode> joints;  // parents before children
    std::vector<Placement> placements;
    /// A joint under a CSG node: its operand is flattened into the node's set at the compiled
    /// time, so animate() compiles the scene again.
    bool recompile = false;
    bool animated() const { return !joints.empty() || recompile; }
};

struct RenderScene {
    std::optional<CameraPose> camera;  // absent: default camera (spec §6.3, at the render's size)
    Vec3 background{0.0};
    Vec3 ambient{0.0};
    /// V3 (spec §13.9): the texel multiplies K_E, K_A, K_D and K_S; V0/V1: K_A and K_D only.
    bool texture_all_terms = false;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<std::shared_ptr<const TextureImage>> textures;
    SetList sets;
    std::vector<Instance> instances;
    Bvh top;               // over instances' world bounds
    Bounds3 world_bounds;  // tight when the scene has no camera (the default camera frames it)
    SceneRig rig;          // what animate() needs to move the joints
    /// The time the joints hold: none (key 0 as read) or the last animate()'s.
    std::optional<SceneTime> time;
};

}  // namespace rt
