// compile_scene(): the SceneDesc's files become GeometrySets (groups flattened into the file's
// frame, one copy per file however often it is instanced), instances are flattened into a list
// of (set, world transform), and the BVHs are built: one per set and one over the instances.
#include "rt/compile/compile.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <tuple>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

#include "compile/placement.h"
#include "rt/util/isa.h"
#include "rt/util/parallel_ranges.h"

namespace rt {

namespace {

using compile_detail::combine_csg_bounds;
using compile_detail::within_limits;

// The fewest primitives (or vertices, or blocks) a thread of the compile takes: below this the
// start of a thread costs more than it saves.
constexpr size_t kGrain = 16384;

class Compiler {
public:
    Compiler(const SceneDesc& desc, CompileReport& report, const std::optional<SceneTime>& time,
             Diagnostics* diag, unsigned threads, CompileProgress* progress = nullptr)
        : m_desc(desc),
          m_report(report),
          m_time(time),
          m_diag(diag),
          m_threads(!have_threads() ? 1u
                    : threads       ? threads
                                    : hardware_threads()),
          m_progress(progress) {}
    // The same, freeing desc's triangles and vertices once compiled where nothing reads them
    // again (compile_scene_releasing).
    Compiler(SceneDesc& desc, CompileReport& report, const std::optional<SceneTime>& time,
             Diagnostics* diag, unsigned threads, bool release)
        : Compiler(std::as_const(desc), report, time, diag, threads) {
        if (!release || !desc.tracks.empty() || report.record_locations) return;
        m_release = &desc;
        m_kept = files_inside_csg();
    }

    // fn(begin, end) over [0, n) in ranges on the compile's threads (parallel_ranges).
    template <class F>
    void in_ranges(size_t n, size_t grain, F&& fn) const {
        parallel_ranges(n, grain, std::forward<F>(fn), m_threads);
    }

    RenderScene run() {
        if (m_progress) {
            uint64_t shapes = 0;
            for (const FileDesc& f : m_desc.files) shapes += count_shapes(f.root);
            m_progress->total.store(3 * shapes, std::memory_order_relaxed);
        }
        if (m_desc.camera) m_scene.camera = compile_camera(*m_desc.camera);
        m_scene.background = m_desc.background;
        m_scene.ambient = m_desc.ambient;
        for (const LightDesc& l : m_desc.lights) m_scene.lights.push_back(compile_light(l));
        m_scene.texture_all_terms = m_desc.dialect == Dialect::V3;  // spec §13.9
        compile_materials();
        m_values = joint_values(m_desc.tracks, m_time, m_diag);
        m_scene.rig.tracks = m_desc.tracks;
        m_scene.time = m_time;
        if (!m_desc.files.empty()) place_all();
        m_report.build_seconds += compile_detail::place_instances(m_scene, m_values);
        fill_report();
        if (m_progress) m_progress->done.store(m_progress->total.load());
        return std::move(m_scene);
    }

private:
    void compile_materials() {
        // Global arrays with per-file offsets; the V0 default material goes last.
        size_t materials = 0;
        for (const FileDesc& f : m_desc.files) {
            m_texture_offset.push_back(static_cast<int>(m_scene.textures.size()));
            for (const TextureDesc& t : f.textures) m_scene.textures.push_back(t.image);
            m_material_offset.push_back(static_cast<int>(materials));
            materials += f.materials.size();
        }
        const std::vector<MaterialDesc> descs = material_descs(m_desc);
        const std::vector<MaterialOrigin> origins = material_origins(m_desc);
        for (size_t k = 0; k < descs.size(); ++k) {
            m_scene.materials.push_back(compile_material(descs[k], origins[k]));
            if (m_report.record_locations)
                m_report.material_names.push_back(origins[k].file < 0 ? "(default)"
                                                                      : descs[k].name);
        }
        m_default_material = static_cast<int>(materials);
    }

    // What is compiled into one set and placed: a file's root list, or a bound joint's subtree
    // in the joint's own frame (its set is the joint's shapes without the joints inside it).
    struct PlaceItem {
        size_t file;
        const GroupDesc* root;
        bool joint_root;
        int joint;   // the innermost joint node it lies under
        Mat4 after;  // its frame in that joint's frame (or the world's)
        SourceLoc at;
    };

    // Places the top file in the world: each root's set compiled once, one placement per
    // reference, the files it instances and the joints it holds pushed as roots of their own.
    // An explicit stack: joints nest as deep as groups.
    void place_all() {
        std::vector<PlaceItem> todo = {{0, &m_desc.files[0].root, false, -1, Mat4(1.0), {}}};
        while (!todo.empty()) {
            const PlaceItem item = todo.back();
            todo.pop_back();
            const int set = set_for(item);
            if (set >= 0) add_placement(set, item);
            push_roots(item, todo);
        }
    }

    void add_placement(int set, const PlaceItem& item) {
        Placement p;
        p.set = set;
        p.joint = item.joint;
        p.after = item.after;
        p.at = item.at;
        const GeometrySet& gs = m_scene.sets[static_cast<size_t>(set)];
        if (item.joint < 0) {
            p.instance.set = set;
            p.instance.world_from_set = Transform::from_matrix(item.after);
            p.instance.identity = p.instance.world_from_set.is_identity();
            p.instance.world_bounds = p.instance.identity
                                          ? gs.bvh.root_bounds
                                          : p.instance.world_from_set.apply(gs.bvh.root_bounds);
            if (!within_limits(p.instance.world_bounds))
                throw SceneError(item.at,
                                 "instance reaches beyond +-1e300 in the world (coordinates "
                                 "too large for the renderer)");
            if (!m_scene.camera)
                p.tight = compile_detail::tight_world_bounds(gs, p.instance.world_from_set.m);
        }
        m_scene.rig.placements.push_back(std::move(p));
    }

    // The files instanced and the joints held by item's root, not inside its joints (those
    // are roots of their own), in the order of a recursive pre-order walk.
    void push_roots(const PlaceItem& item, std::vector<PlaceItem>& todo) {
        std::vector<GroupVisit> walk = {{item.root, Mat4(1.0)}};
        std::vector<PlaceItem> found;
        while (!walk.empty()) {
            const GroupVisit v = walk.back();
            walk.pop_back();
            const GroupDesc& g = *v.group;
            const bool is_root = &g == item.root;
            if (g.track >= 0 && !is_root) {
                JointNode node;
                node.parent = item.joint;
                node.before = item.after * v.parent;
                node.track = g.track;
                m_scene.rig.joints.push_back(node);
                const int id = static_cast<int>(m_scene.rig.joints.size()) - 1;
                found.push_back({item.file, &g, true, id, Mat4(1.0), g.loc});
                continue;
            }
            const Mat4 m = is_root && item.joint_root ? v.parent : v.parent * g.matrix;
            for (const InstanceDesc& in : g.instances) {
                const size_t fj = instanced_file(item.file, in);
                found.push_back(
                    {fj, &m_desc.files[fj].root, false, item.joint, item.after * m, in.loc});
            }
            push_children(walk, g, m);
        }
        todo.insert(todo.end(), found.rbegin(), found.rend());
    }

    // A group and the matrix of its parent's frame: the walks of the group tree keep their own
    // stack (groups nest up to 10000 deep), in the order of a recursive pre-order walk.
    struct GroupVisit {
        const GroupDesc* group;
        Mat4 parent;
    };
    static void push_children(std::vector<GroupVisit>& todo, const GroupDesc& g, const Mat4& m) {
        for (auto it = g.groups.rbegin(); it != g.groups.rend(); ++it) todo.push_back({&*it, m});
    }

    // The matrix of group g inside a CSG node: a bound joint's value at the compiled time (the
    // node's set then depends on the time: animate() compiles again); null where it is singular.
    const Mat4* csg_group_matrix(const GroupDesc& g) {
        if (g.track < 0) return &g.matrix;
        m_scene.rig.recompile = true;
        const size_t k = static_cast<size_t>(g.track);
        return m_values.singular[k] ? nullptr : &m_values.matrix[k];
    }

    // One shape waiting for its place in the set with its group's transform: a triangle's
    // corners and material (copied: its description may be freed before it is placed, see
    // release_triangles()), another shape's description, or a compiled CSG tree.
    struct Pending {
        const ShapeDesc* shape = nullptr;  // null for a CSG tree and a freed triangle
        TriangleDesc tri;
        int material = 0;     // a triangle's
        int transform = -1;   // index into the set's transforms, -1: identity
        int csg = -1;         // index into the set's csg.roots
        bool mirror = false;  // the transform flips orientation
        bool triangle = false;
    };
    static Pending pending_shape(const ShapeDesc& s, int transform, bool mirror) {
        Pending p;
        p.shape = &s;
        p.transform = transform;
        p.mirror = mirror;
        if (const TriangleDesc* t = std::get_if<TriangleDesc>(&s.geometry)) {
            p.triangle = true;
            p.tri = *t;
            p.material = s.material;
        }
        return p;
    }
    // The directive a pending shape was read from (CompileReport::prim_locs).
    SourceLoc pending_loc(const Pending& p) const {
        return p.csg >= 0 ? *m_csg_locs[static_cast<size_t>(p.csg)]
               : p.shape  ? p.shape->loc
                          : SourceLoc{};
    }

    // Compiles file `fi` into a set in two passes: the shapes' bounds first, then the BVH over
    // them, then the primitives written straight in the BVH's leaf order, so a leaf reads its
    // primitives from consecutive memory and no array is copied twice.
    int set_for(const PlaceItem& item) {
        const size_t fi = item.file;
        if (auto it = m_set_of_root.find(item.root); it != m_set_of_root.end()) return it->second;
        GeometrySet set;
        set.name = m_desc.files[fi].path;
        m_vertex_file = fi;
        m_vertex_of.assign(m_desc.files[fi].vertices.size(), ~0u);
        m_csg_locs.clear();
        HugePageVector<Pending> pending;
        pending.reserve(count_shapes(*item.root));
        collect(set, item, pending);
        if (pending.empty()) {
            m_set_of_root[item.root] = -1;
            return -1;
        }
        // The build's input: each primitive's bounds in float (32 bytes), and their union.
        HugePageVector<PrimRef> refs(pending.size());
        const Bounds3 set_bounds = prim_refs(set, fi, pending, refs);
        step(fi, pending.size());
        const bool release = releasable(item);
        if (release) release_triangles(fi, pending);

        set.layout = layout_of(pending);
        const auto t0 = std::chrono::steady_clock::now();
        // The references move into the build, which frees them before the set grows.
        BvhBuildSettings build = set_bvh_settings(set.layout);
        build.threads = m_threads;
        set.bvh = build_bvh(std::move(refs), set_bounds, build);
        m_report.build_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        step(fi, pending.size());

        set.prims.reserve(pending.size());
        const auto triangles = std::count_if(pending.begin(), pending.end(),
                                             [](const Pending& p) { return p.triangle; });
        set.triangle_vertices.reserve(static_cast<size_t>(triangles));  // no copy as they grow
        std::vector<SourceLoc>* locs = nullptr;
        if (m_report.record_locations) {
            m_report.prim_locs.resize(m_scene.sets.size() + 1);
            locs = &m_report.prim_locs.back();
            locs->reserve(pending.size());
        }
        // In the BVH's order, the vertices' data copied afterwards on all cores (the set's
        // vertices are numbered in the order the triangles meet them).
        m_defer_vertices = true;
        for (uint32_t old : set.bvh.indices) {
            add_shape(set, fi, pending[old]);
            if (locs) locs->push_back(pending_loc(pending[old]));
        }
        m_defer_vertices = false;
        std::iota(set.bvh.indices.begin(), set.bvh.indices.end(), 0u);
        const size_t shapes = pending.size();
        HugePageVector<Pending>().swap(pending);  // freed before the packed copy is made
        std::vector<uint32_t>().swap(m_vertex_of);
        copy_deferred_vertices(set);
        if (release) HugePageVector<VertexDesc>().swap(m_release->files[fi].vertices);
        pack_triangles(set);
        step(fi, shapes);
        const int index = static_cast<int>(m_scene.sets.size());
        m_set_of_root[item.root] = index;
        m_scene.sets.push_back(std::move(set));
        return index;
    }

    // CompileProgress: `n` units more are done; a cancelled compile stops here, with an error at
    // file fi.
    void step(size_t fi, size_t n) const {
        if (!m_progress) return;
        m_progress->done.fetch_add(n, std::memory_order_relaxed);
        if (m_progress->cancel && m_progress->cancel->load(std::memory_order_relaxed))
            throw SceneError({intern_file_name(m_desc.files[fi].path), 0, 0}, "loading cancelled");
    }

    // Whether item's file is read by no set compiled after item's: a file's root (not a joint's
    // subtree, none without tracks), not instanced inside a CSG tree (whose set reads its shapes).
    bool releasable(const PlaceItem& item) const {
        return m_release && !item.joint_root && !m_kept[item.file] &&
               item.root == &m_desc.files[item.file].root;
    }

    // The files instanced inside a CSG tree, and the files they instance: one walk over every
    // file's groups that knows whether it is under a CSG node's operand.
    std::vector<char> files_inside_csg() const {
        std::vector<char> inside(m_desc.files.size(), 0);
        struct Visit {
            const GroupDesc* group;
            size_t file;
            bool in_csg;
        };
        std::vector<Visit> todo;
        for (size_t fi = 0; fi < m_desc.files.size(); ++fi)
            todo.push_back({&m_desc.files[fi].root, fi, false});
        while (!todo.empty()) {
            const Visit v = todo.back();
            todo.pop_back();
            for (const GroupDesc& c : v.group->groups) todo.push_back({&c, v.file, v.in_csg});
            for (const CsgDesc& c : v.group->csgs)
                for (const GroupDesc& o : c.operands) todo.push_back({&o, v.file, true});
            if (!v.in_csg) continue;
            for (const InstanceDesc& in : v.group->instances) {
                const size_t fj = instanced_file(v.file, in);
                if (!std::exchange(inside[fj], 1))
                    todo.push_back({&m_desc.files[fj].root, fj, true});
            }
        }
        return inside;
    }

    // The file an instance in file fi places.
    size_t instanced_file(size_t fi, const InstanceDesc& in) const {
        return static_cast<size_t>(m_desc.files[fi].ray_files[static_cast<size_t>(in.ray_file)]);
    }

    // Frees the shapes of file fi's groups that hold only triangles: their pending entries keep
    // what the set needs of them (corners, material).
    void release_triangles(size_t fi, HugePageVector<Pending>& pending) {
        for (Pending& p : pending)
            if (p.triangle) p.shape = nullptr;
        std::vector<GroupDesc*> todo = {&m_release->files[fi].root};
        while (!todo.empty()) {
            GroupDesc* g = todo.back();
            todo.pop_back();
            const bool triangles =
                std::all_of(g->shapes.begin(), g->shapes.end(), [](const ShapeDesc& s) {
                    return std::holds_alternative<TriangleDesc>(s.geometry);
                });
            if (triangles) HugePageVector<ShapeDesc>().swap(g->shapes);
            for (GroupDesc& c : g->groups) todo.push_back(&c);
        }
    }

    // Each pending shape's reference for the build (refs[i] for pending[i]) and their union, on
    // all cores; the first shape in order that reaches too far is the error.
    Bounds3 prim_refs(const GeometrySet& set, size_t fi, const HugePageVector<Pending>& pending,
                      HugePageVector<PrimRef>& refs) const {
        Bounds3 all;
        std::mutex mutex;
        in_ranges(pending.size(), kGrain, [&](size_t begin, size_t end) {
            Bounds3 part;
            for (size_t i = begin; i < end; ++i) {
                const Pending& p = pending[i];
                const Bounds3 b =
                    p.csg >= 0  // its leaves were checked when it was compiled
                        ? set.csg.nodes[set.csg.roots[static_cast<size_t>(p.csg)].node].bounds
                        : shape_bounds(set, fi, p);
                if (p.csg < 0 && !within_limits(b))
                    throw SceneError(p.shape->loc,
                                     "shape reaches beyond +-1e300 in its file's frame "
                                     "(coordinates too large for the renderer)");
                refs[i] = make_prim_ref(b, static_cast<uint32_t>(i));
                part.extend(b);
            }
            const std::lock_guard lock(mutex);
            all.extend(part);
        });
        return all;
    }

    // The walk of a set that holds only shapes of kind k; a kind without a walk of its own
    // takes the analytic walk.
    static constexpr SetLayout one_kind_layout(ShapeKind k) {
        switch (k) {
            case ShapeKind::Sphere:
                return SetLayout::Spheres;
            case ShapeKind::Box:
                return SetLayout::Boxes;
            case ShapeKind::Cylinder:
                return SetLayout::Cylinders;
            case ShapeKind::Cone:
                return SetLayout::Cones;
            case ShapeKind::Triangle:
                return SetLayout::Triangles;
            default:
                return SetLayout::Analytic;
        }
    }

    // The one kind a set holds gets a walk of its own; triangles-only sets get packed leaves.
    static SetLayout layout_of(const HugePageVector<Pending>& pending) {
        std::array<size_t, kShapeKinds> count{};  // geometry.index() is the kind (ShapeDesc)
        for (const Pending& p : pending) {
            if (p.csg >= 0) return SetLayout::Mixed;  // CSG primitives: the Mixed walk only
            ++count[p.triangle ? static_cast<size_t>(ShapeKind::Triangle)
                               : p.shape->geometry.index()];
        }
        for (size_t k = 0; k < count.size(); ++k)
            if (count[k] == pending.size()) return one_kind_layout(static_cast<ShapeKind>(k));
        return count[static_cast<size_t>(ShapeKind::Triangle)] == 0 ? SetLayout::Analytic
                                                                    : SetLayout::Mixed;
    }

    // Single-precision copies of the triangles, four per block (unused lanes zero), relative to
    // the centre of their bounds: float then resolves a mesh to its own size, not to its
    // distance from the origin (a mesh at 1e4 would otherwise snap to a grid of 1e-3).
    void pack_triangles(GeometrySet& set) const {
        set.tri_origin = triangle_bounds_centre(set);
        auto put = [&](size_t i, Tri4& block, int lane) {
            const Triangle t = set.triangle(i);
            put_triangle(block, lane, t.p0, t.p1, t.p2, set.tri_origin);
        };
        if (set.layout != SetLayout::Triangles) {
            set.tri4.assign((set.triangle_count() + 3) / 4, Tri4{});
            in_ranges(set.tri4.size(), kGrain / 4, [&](size_t begin, size_t end) {
                for (size_t i = begin * 4; i < std::min(end * 4, set.triangle_count()); ++i)
                    put(i, set.tri4[i / 4], static_cast<int>(i % 4));
            });
            return;
        }
        // Each leaf in blocks of its own, in the order of the nodes the closest-hit walk reads
        // (the 8-wide ones when there are); the leaves of both trees then name their first block.
        auto leaves = [](auto& nodes, auto&& f) {
            for (auto& node : nodes)
                for (uint32_t c = 0; c < node.num_children; ++c)
                    if (node.child[c] & Bvh4Node::kLeaf) f(node.child[c]);
        };
        // The leaves in that order, each with its first block, then packed on all cores.
        struct Leaf {
            uint32_t* child;
            uint32_t block;
        };
        std::vector<Leaf> order;
        uint32_t blocks = 0;
        const bool wide = !set.bvh.nodes8.empty();
        auto number = [&](uint32_t& child) {
            order.push_back({&child, blocks});
            blocks += (Bvh4Node::leaf_count(child) + 3) / 4;
        };
        if (wide)
            leaves(set.bvh.nodes8, number);
        else
            leaves(set.bvh.nodes, number);
        set.tri4.assign(blocks, Tri4{});
        set.tri4_prim.assign(blocks, {~0u, ~0u, ~0u, ~0u});
        // A leaf's first block, by its first primitive.
        std::vector<uint32_t> block_of(wide ? set.triangle_count() : 0);
        in_ranges(order.size(), kGrain / 4, [&](size_t begin, size_t end) {
            for (size_t l = begin; l < end; ++l) {
                uint32_t& child = *order[l].child;
                const uint32_t first = Bvh4Node::leaf_first(child);
                const uint32_t count = Bvh4Node::leaf_count(child);
                const uint32_t next = order[l].block;
                for (uint32_t k = 0; k < count; ++k) {
                    put(first + k, set.tri4[next + k / 4], static_cast<int>(k % 4));
                    set.tri4_prim[next + k / 4][k % 4] = first + k;
                }
                if (wide) block_of[first] = next;
                child = Bvh4Node::leaf(next, count);
            }
        });
        if (wide)
            leaves(set.bvh.nodes, [&](uint32_t& child) {
                child = Bvh4Node::leaf(block_of[Bvh4Node::leaf_first(child)],
                                       Bvh4Node::leaf_count(child));
            });
        HugePageVector<uint32_t>().swap(set.bvh.indices);  // the leaves name blocks now
    }

    // The centre of the bounds of the set's triangles (not of a dropped CSG tree's), or 0.
    Vec3 triangle_bounds_centre(const GeometrySet& set) const {
        Bounds3 b;
        std::mutex mutex;
        in_ranges(set.triangle_count(), kGrain, [&](size_t begin, size_t end) {
            Bounds3 part;
            for (size_t i = begin; i < end; ++i)
                for (const uint32_t v : set.triangle_vertices[i])
                    part.extend(set.vertex_positions[v]);
            const std::lock_guard lock(mutex);
            b.extend(part);
        });
        return b.empty() ? Vec3(0.0) : b.centre();
    }

    static size_t count_shapes(const GroupDesc& root) {
        size_t n = 0;
        std::vector<const GroupDesc*> todo = {&root};
        while (!todo.empty()) {
            const GroupDesc* g = todo.back();
            todo.pop_back();
            n += g->shapes.size();
            for (const GroupDesc& c : g->groups) todo.push_back(&c);
        }
        return n;
    }

    // Flattens the group tree of item's root: one cached transform per group with shapes (none
    // when identity). The joints inside it are sets of their own (push_roots).
    void collect(GeometrySet& set, const PlaceItem& item, HugePageVector<Pending>& pending) {
        const size_t fi = item.file;
        std::vector<GroupVisit> todo = {{item.root, Mat4(1.0)}};
        while (!todo.empty()) {
            const GroupVisit v = todo.back();
            todo.pop_back();
            const GroupDesc& g = *v.group;
            const bool is_root = &g == item.root;
            if (g.track >= 0 && !is_root) continue;
            const Mat4 m = is_root && item.joint_root ? v.parent : v.parent * g.matrix;
            if (!g.shapes.empty()) {
                int xf = -1;
                if (m != Mat4(1.0)) {
                    xf = static_cast<int>(set.transforms.size());
                    set.transforms.push_back(Transform::from_matrix(m));
                }
                const bool mirror = glm::determinant(Mat3(m)) < 0;
                for (const ShapeDesc& s : g.shapes) pending.push_back(pending_shape(s, xf, mirror));
            }
            for (const CsgDesc& c : g.csgs) {
                const int root = compile_csg(set, fi, c, m);
                if (root >= 0) {
                    Pending p;
                    p.csg = root;
                    pending.push_back(p);
                    m_csg_locs.resize(static_cast<size_t>(root) + 1);
                    m_csg_locs[static_cast<size_t>(root)] = &c.loc;
                }
            }
            push_children(todo, g, m);
        }
    }

    // One step of the post-order walk of a CSG description: a CSG node or a list (an operand,
    // a group inside one, an instance's root list), with the frame of its parent and its file.
    struct CsgVisit {
        const CsgDesc* csg;  // or null: a list
        const GroupDesc* group;
        Mat4 parent;
        size_t file;
        bool flip;           // under the second operand of an odd number of differences
        bool open = false;   // its children are being compiled
        size_t results = 0;  // the size of the results stack when it was opened
        uint32_t first = 0;  // the size of the nodes array when it was opened
    };

    // Appends node `kind` over the children ids in results[from..], popping them.
    static uint32_t close_csg_node(CsgArrays& c, CsgNodeKind kind, std::vector<uint32_t>& results,
                                   size_t from, uint32_t subtree_first) {
        CsgNode n;
        n.kind = kind;
        n.first = static_cast<uint32_t>(c.children.size());
        n.count = static_cast<uint32_t>(results.size() - from);
        n.subtree_first = subtree_first;
        const uint32_t id = static_cast<uint32_t>(c.nodes.size());
        std::vector<Bounds3> kids;
        for (size_t i = from; i < results.size(); ++i) {
            c.children.push_back(results[i]);
            c.nodes[results[i]].parent = static_cast<int>(id);
            kids.push_back(c.nodes[results[i]].bounds);
        }
        n.bounds = combine_csg_bounds(kind, kids.data(), n.count);
        if (n.count == 0) n.kind = CsgNodeKind::Empty;
        c.nodes.push_back(n);
        results.resize(from);
        results.push_back(id);
        return id;
    }

    // The leaves of the shapes of list g (in frame m of file fi), pushed as finished nodes.
    void add_csg_leaves(GeometrySet& set, size_t fi, const GroupDesc& g, const Mat4& m, bool flip,
                        std::vector<uint32_t>& results) {
        if (g.shapes.empty()) return;
        int xf = -1;
        if (m != Mat4(1.0)) {
            xf = static_cast<int>(set.transforms.size());
            set.transforms.push_back(Transform::from_matrix(m));
        }
        const bool mirror = glm::determinant(Mat3(m)) < 0;
        for (const ShapeDesc& s : g.shapes) {
            const Pending pend = pending_shape(s, xf, mirror);
            CsgNode n;
            n.kind = CsgNodeKind::Leaf;
            n.bounds = shape_bounds(set, fi, pend);
            if (!within_limits(n.bounds))
                throw SceneError(s.loc,
                                 "shape reaches beyond +-1e300 in its file's frame "
                                 "(coordinates too large for the renderer)");
            n.first = static_cast<uint32_t>(set.csg.leaves.size());
            n.subtree_first = static_cast<uint32_t>(set.csg.nodes.size());
            CsgLeaf leaf;
            leaf.prim = make_primitive(set, fi, pend);
            leaf.node = n.subtree_first;
            leaf.flip = flip;
            leaf.epsilon =
                visit_shape(set, leaf.prim, [](const auto& shape) { return csg_epsilon(shape); });
            results.push_back(n.subtree_first);
            set.csg.nodes.push_back(n);
            set.csg.leaves.push_back(leaf);
        }
    }

    // Opens a visit: its leaves now, its children pushed to be compiled before it closes.
    void open_csg_visit(GeometrySet& set, CsgVisit v, std::vector<CsgVisit>& todo,
                        std::vector<uint32_t>& results) {
        v.open = true;
        v.results = results.size();
        v.first = static_cast<uint32_t>(set.csg.nodes.size());
        todo.push_back(v);
        if (v.csg) {
            const CsgDesc& c = *v.csg;
            if (c.op == CsgOp::Difference && c.operands.size() != 2)
                throw SceneError(c.loc, "a CSG difference needs exactly two operands");
            for (size_t i = c.operands.size(); i-- > 0;)
                todo.push_back({nullptr, &c.operands[i], v.parent, v.file,
                                v.flip != (c.op == CsgOp::Difference && i == 1)});
            return;
        }
        const GroupDesc& g = *v.group;
        const Mat4* gm = csg_group_matrix(g);
        if (!gm) return;  // a joint singular at this time: an empty operand
        const Mat4 m = v.parent * *gm;
        add_csg_leaves(set, v.file, g, m, v.flip, results);
        // Pushed in reverse so that they close in the list's order: groups, instances, CSGs.
        for (auto it = g.csgs.rbegin(); it != g.csgs.rend(); ++it)
            todo.push_back({&*it, nullptr, m, v.file, v.flip});
        for (auto it = g.instances.rbegin(); it != g.instances.rend(); ++it) {
            const size_t fj = instanced_file(v.file, *it);
            todo.push_back({nullptr, &m_desc.files[fj].root, m, fj, v.flip});
        }
        for (auto it = g.groups.rbegin(); it != g.groups.rend(); ++it)
            todo.push_back({nullptr, &*it, m, v.file, v.flip});
    }

    // Compiles CSG node `c` of file fi in frame m into set.csg (post-order, without recursion:
    // CSG nodes nest as deep as groups). Returns its index in set.csg.roots, or -1 when it has
    // no surface at all (no leaf, or an empty box), in which case nothing is kept.
    int compile_csg(GeometrySet& set, size_t fi, const CsgDesc& c, const Mat4& m) {
        CsgArrays& a = set.csg;
        const size_t nodes0 = a.nodes.size(), children0 = a.children.size(),
                     leaves0 = a.leaves.size();
        // The leaves' shapes go to the set's arrays as they are met; a dropped tree takes them
        // back (a Triangles set relies on prims[i] being triangle i).
        const size_t triangles0 = set.triangle_count(), transforms0 = set.transforms.size();
        std::array<size_t, kShapeKinds> kinds0{};
        std::apply([&](const auto&... v) { kinds0 = {v.size()...}; }, set.shapes.arrays);
        std::vector<CsgVisit> todo = {{&c, nullptr, m, fi, false}};
        std::vector<uint32_t> results;
        while (!todo.empty()) {
            const CsgVisit v = todo.back();
            todo.pop_back();
            if (!v.open) {
                open_csg_visit(set, v, todo, results);
                continue;
            }
            if (!v.csg && results.size() - v.results == 1) continue;  // a list of one: the child
            CsgNodeKind kind = CsgNodeKind::List;
            if (v.csg)
                kind = v.csg->op == CsgOp::Union          ? CsgNodeKind::Union
                       : v.csg->op == CsgOp::Intersection ? CsgNodeKind::Intersection
                                                          : CsgNodeKind::Difference;
            close_csg_node(a, kind, results, v.results, v.first);
        }
        CsgRoot root{static_cast<uint32_t>(a.nodes.size() - 1), static_cast<uint32_t>(leaves0),
                     static_cast<uint32_t>(a.leaves.size() - leaves0)};
        if (root.leaf_count == 0 || a.nodes[root.node].bounds.empty()) {
            a.nodes.resize(nodes0);
            a.children.resize(children0);
            a.leaves.resize(leaves0);
            set.triangle_vertices.resize(triangles0);  // their vertices stay (no one uses them)
            set.transforms.resize(transforms0);
            size_t k = 0;
            std::apply([&](auto&... v) { (v.resize(kinds0[k++]), ...); }, set.shapes.arrays);
            return -1;
        }
        a.roots.push_back(root);
        return static_cast<int>(a.roots.size() - 1);
    }

    // The triangle's vertices in the set's frame; a mirroring transform swaps the last two so
    // the geometric normal stays (A^-1)^T times the local one (spec §4.1), as refraction needs.
    static std::array<const VertexDesc*, 3> triangle_vertices(const FileDesc& f,
                                                              const TriangleDesc& t, bool mirror) {
        std::array<const VertexDesc*, 3> v{};
        for (int i = 0; i < 3; ++i)
            v[static_cast<size_t>(i)] = &f.vertices[static_cast<size_t>(t.v[i])];
        if (mirror) std::swap(v[1], v[2]);
        return v;
    }

    Bounds3 shape_bounds(const GeometrySet& set, size_t fi, const Pending& p) const {
        const Transform* xf =
            p.transform < 0 ? nullptr : &set.transforms[static_cast<size_t>(p.transform)];
        Bounds3 b;
        if (p.triangle) {
            for (const VertexDesc* v : triangle_vertices(m_desc.files[fi], p.tri, p.mirror))
                b.extend(xf ? xf->point(v->position) : v->position);
            return b;
        }
        return std::visit(
            [&](const auto& geo) {
                if constexpr (!std::is_same_v<std::decay_t<decltype(geo)>, TriangleDesc>) {
                    // Exact bounds under the group's transform, widened by its rounding.
                    const auto& shape = to_shape(geo);
                    b = xf ? bounds(shape, xf->m).widened() : bounds(shape);
                }
                return b;
            },
            p.shape->geometry);
    }

    void add_shape(GeometrySet& set, size_t fi, const Pending& pend) {
        if (pend.csg >= 0) {
            // A leaf's fields (see Primitive), an analytic one where there is one (a walk that
            // forgets the test then does not take it for a triangle), and the tree.
            const CsgRoot& root = set.csg.roots[static_cast<size_t>(pend.csg)];
            uint32_t shown = root.first_leaf;
            for (uint32_t l = root.first_leaf + root.leaf_count; l-- > root.first_leaf;)
                if (set.csg.leaves[l].prim.kind != ShapeKind::Triangle) shown = l;
            Primitive p = set.csg.leaves[shown].prim;
            p.csg = pend.csg;
            set.prims.push_back(p);
            return;
        }
        set.prims.push_back(make_primitive(set, fi, pend));
    }

    // The primitive of a shape, its shape appended to the set's arrays.
    Primitive make_primitive(GeometrySet& set, size_t fi, const Pending& pend) {
        const int material = pend.triangle ? pend.material : pend.shape->material;
        Primitive p;
        p.material = material < 0 ? m_default_material : m_material_offset[fi] + material;
        p.transform = pend.transform;
        if (pend.triangle) {
            p.kind = ShapeKind::Triangle;
            p.index = static_cast<uint32_t>(set.triangle_count());
            p.transform = -1;  // flattened into the set's frame
            add_triangle(set, fi, pend);
            return p;
        }
        std::visit(
            [&](const auto& geo) {
                if constexpr (!std::is_same_v<std::decay_t<decltype(geo)>, TriangleDesc>) {
                    using T = std::decay_t<decltype(to_shape(geo))>;
                    std::vector<T>& shapes = set.shapes.of<T>();
                    p.kind = T::kKind;
                    p.index = static_cast<uint32_t>(shapes.size());
                    shapes.push_back(to_shape(geo));
                }
            },
            pend.shape->geometry);
        return p;
    }

    // Triangles are flattened into the set's frame: no per-primitive transform.
    void add_triangle(GeometrySet& set, size_t fi, const Pending& pend) {
        const Transform* xf =
            pend.transform < 0 ? nullptr : &set.transforms[static_cast<size_t>(pend.transform)];
        const TriangleDesc& td = pend.tri;
        const auto v = triangle_vertices(m_desc.files[fi], td, pend.mirror);
        std::array<uint32_t, 3> ids{};
        for (size_t i = 0; i < 3; ++i) {
            const size_t k = i == 0 || !pend.mirror ? i : 3 - i;  // as triangle_vertices orders
            // Only the set's own file shares its vertices: a CSG operand's instance numbers
            // another file's vertices from 0 too.
            const size_t shared = fi == m_vertex_file ? static_cast<size_t>(td.v[k]) : SIZE_MAX;
            ids[i] = set_vertex(set, *v[i], shared, xf);
        }
        set.triangle_vertices.push_back(ids);
    }

    // The index of a triangle corner in the set's vertex arrays (its position and normal in the
    // set's frame, its uv): a vertex of the set's file (file_vertex, or SIZE_MAX for another
    // file's) in the set's own frame once for all its triangles (m_vertex_of), a transformed one
    // for each corner. While m_defer_vertices is set, only the number is given out and the data
    // waits in m_deferred for copy_deferred_vertices().
    uint32_t set_vertex(GeometrySet& set, const VertexDesc& v, size_t file_vertex,
                        const Transform* xf) {
        constexpr uint32_t kNone = ~0u;
        if (!xf && file_vertex < m_vertex_of.size() && m_vertex_of[file_vertex] != kNone)
            return m_vertex_of[file_vertex];
        const uint32_t id = static_cast<uint32_t>(set.vertex_positions.size() + m_deferred.size());
        if (m_defer_vertices)
            m_deferred.push_back({&v, xf});
        else
            put_vertex(set, id, v, xf);
        if (!xf && file_vertex < m_vertex_of.size()) m_vertex_of[file_vertex] = id;
        return id;
    }

    static void put_vertex(GeometrySet& set, uint32_t id, const VertexDesc& v,
                           const Transform* xf) {
        if (id == set.vertex_positions.size()) {
            set.vertex_positions.emplace_back();
            set.vertex_normals.emplace_back();
            set.vertex_uvs.emplace_back();
        }
        set.vertex_positions[id] = xf ? xf->point(v.position) : v.position;
        // Not renormalised: spec §5 normalises the interpolated sum
        // (Transform::interpolable_normal).
        set.vertex_normals[id] = !xf ? v.normal : xf->interpolable_normal(v.normal);
        set.vertex_uvs[id] = v.uv;
    }

    // The deferred vertices' data, on all cores: the arrays grow once to their final size.
    void copy_deferred_vertices(GeometrySet& set) {
        const size_t first = set.vertex_positions.size(), n = m_deferred.size();
        set.vertex_positions.resize(first + n);
        set.vertex_normals.resize(first + n);
        set.vertex_uvs.resize(first + n);
        in_ranges(n, kGrain, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i)
                put_vertex(set, static_cast<uint32_t>(first + i), *m_deferred[i].vertex,
                           m_deferred[i].transform);
        });
        HugePageVector<DeferredVertex>().swap(m_deferred);
    }

    void fill_report() {
        CompileReport& s = m_report;
        s.files = m_desc.files.size();
        s.instances = m_scene.instances.size();
        s.lights = m_scene.lights.size();
        s.materials = m_scene.materials.size() - 1;  // without the built-in default
        s.textures = m_scene.textures.size();
        for (const GeometrySet& set : m_scene.sets) s.unique_prims += set.prims.size();
        std::vector<size_t> uses(m_scene.sets.size(), 0);
        for (const Instance& inst : m_scene.instances) ++uses[static_cast<size_t>(inst.set)];
        for (size_t i = 0; i < m_scene.sets.size(); ++i) {
            const GeometrySet& set = m_scene.sets[i];
            for (const Primitive& p : set.prims) {
                if (p.csg < 0) {
                    s.prims_by_kind[static_cast<int>(p.kind)] += uses[i];
                    continue;
                }
                const CsgRoot& r = set.csg.roots[static_cast<size_t>(p.csg)];
                for (uint32_t l = r.first_leaf; l < r.first_leaf + r.leaf_count; ++l)
                    s.prims_by_kind[static_cast<int>(set.csg.leaves[l].prim.kind)] += uses[i];
            }
        }
        s.skipped_shapes = m_desc.skipped_shapes;
    }

    const SceneDesc& m_desc;
    CompileReport& m_report;
    RenderScene m_scene;
    const std::optional<SceneTime>& m_time;
    Diagnostics* m_diag;
    unsigned m_threads;  // for the loops over primitives and the BVH builds
    CompileProgress* m_progress;
    JointValues m_values;
    std::unordered_map<const GroupDesc*, int> m_set_of_root;  // -1: the root has no shapes
    SceneDesc* m_release = nullptr;            // compile_scene_releasing()'s description
    std::vector<char> m_kept;                  // [file]: its triangles and vertices are kept
    std::vector<const SourceLoc*> m_csg_locs;  // the set being compiled: its CSG trees' directives
    size_t m_vertex_file = 0;                  // the file of the set being compiled
    std::vector<uint32_t> m_vertex_of;         // its vertex -> the set's vertex
    struct DeferredVertex {
        const VertexDesc* vertex;
        const Transform* transform;  // into the set's transforms, which no longer grow
    };
    bool m_defer_vertices = false;
    HugePageVector<DeferredVertex> m_deferred;  // the set's vertices from number size() on
    std::vector<int> m_texture_offset, m_material_offset;
    int m_default_material = 0;
};

}  // namespace

Bounds3 GeometrySet::prim_bounds(size_t i) const {
    const Primitive& p = prims[i];
    if (p.csg >= 0) return csg.nodes[csg.roots[static_cast<size_t>(p.csg)].node].bounds;
    const Transform* xf = p.transform < 0 ? nullptr : &transforms[static_cast<size_t>(p.transform)];
    return visit_shape(*this, p, [&](const auto& shape) {
        if constexpr (std::is_same_v<std::decay_t<decltype(shape)>, Triangle>) {
            Bounds3 b;  // in the set's frame already
            for (const Vec3& v : {shape.p0, shape.p1, shape.p2}) b.extend(v);
            return b;
        } else {
            return xf ? bounds(shape, xf->m).widened() : bounds(shape);
        }
    });
}

std::vector<MaterialOrigin> material_origins(const SceneDesc& desc) {
    std::vector<MaterialOrigin> out;
    int first_texture = 0;
    for (size_t f = 0; f < desc.files.size(); ++f) {
        const FileDesc& file = desc.files[f];
        const int textures = static_cast<int>(file.textures.size());
        for (size_t m = 0; m < file.materials.size(); ++m)
            out.push_back({static_cast<int>(f), static_cast<int>(m), first_texture, textures});
        first_texture += textures;
    }
    out.push_back({});  // the V0 default
    return out;
}

std::vector<MaterialDesc> material_descs(const SceneDesc& desc) {
    std::vector<MaterialDesc> out;
    for (const FileDesc& file : desc.files)
        out.insert(out.end(), file.materials.begin(), file.materials.end());
    out.push_back(v0_default_material());
    return out;
}

Material compile_material(const MaterialDesc& d, const MaterialOrigin& o) {
    Material m = d;
    m.texture = d.texture >= 0 && d.texture < o.textures ? o.first_texture + d.texture : -1;
    return m;
}

Light compile_light(const LightDesc& d) {
    Light l = d;
    const bool directed = d.kind == LightKind::Directional || d.kind == LightKind::Spot;
    l.direction = directed ? glm::normalize(d.direction) : Light{}.direction;
    return l;
}

CameraPose compile_camera(const CameraDesc& d) { return d; }

BvhBuildSettings set_bvh_settings(SetLayout layout) {
    switch (layout) {
        case SetLayout::Mixed:
            return {};
        case SetLayout::Triangles:
            return {4, 16, 4, active_isa() >= Isa::Avx2};
        default:
            // Analytic shapes cost several box tests each (a cone's robust test is ~200
            // instructions, a 4-wide node test ~40): one per leaf, culled by its own box.
            return {1, 16, 1};
    }
}

namespace {

// The report a compile fills: the caller's, emptied but for what it asks for, or `local`.
CompileReport& fresh_report(CompileReport* report, CompileReport& local) {
    CompileReport& r = report ? *report : local;
    const bool locations = r.record_locations;
    r = {};
    r.record_locations = locations;
    return r;
}

}  // namespace

RenderScene compile_scene(const SceneDesc& desc, CompileReport* report,
                          const std::optional<SceneTime>& time, Diagnostics* diag, unsigned threads,
                          CompileProgress* progress) {
    CompileReport local;
    return Compiler(desc, fresh_report(report, local), time, diag, threads, progress).run();
}

RenderScene compile_scene_releasing(SceneDesc& desc, CompileReport* report,
                                    const std::optional<SceneTime>& time, Diagnostics* diag,
                                    unsigned threads) {
    CompileReport local;
    return Compiler(desc, fresh_report(report, local), time, diag, threads, true).run();
}

}  // namespace rt
