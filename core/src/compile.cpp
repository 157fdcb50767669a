// compile_scene(): the SceneDesc's files become GeometrySets (groups flattened into the file's
// frame, one copy per file however often it is instanced), instances are flattened into a list
// of (set, world transform), and the BVHs are built: one per set and one over the instances.
#include <chrono>
#include <map>
#include <numeric>

#include "rt/render_scene.h"

namespace rt {

namespace {

// Widens a box by the rounding error of the transform that produced it (stays conservative).
Bounds3 widen(Bounds3 b) {
    const Vec3 err = gamma(3) * (glm::abs(b.lo) + glm::abs(b.hi));
    b.lo -= err;
    b.hi += err;
    return b;
}

// Tight world bounds of one primitive of a set placed by world_from_set (for the default camera).
Bounds3 world_bounds_of(const GeometrySet& set, const Primitive& p, const Mat4& world_from_set) {
    if (p.kind == ShapeKind::Triangle) {
        const Triangle& t = set.triangles[p.index];
        Bounds3 b;
        for (const Vec3& v : {t.p0, t.p1, t.p2})
            b.extend(Vec3(world_from_set * glm::dvec4(v, 1.0)));
        return b;
    }
    const Mat4 m = p.transform < 0
                       ? world_from_set
                       : world_from_set * set.transforms[static_cast<size_t>(p.transform)].m;
    switch (p.kind) {
        case ShapeKind::Sphere:
            return bounds(set.spheres[p.index], m);
        case ShapeKind::Box:
            return bounds(set.boxes[p.index], m);
        case ShapeKind::Cylinder:
            return bounds(set.cylinders[p.index], m);
        case ShapeKind::Cone:
            return bounds(set.cones[p.index], m);
        case ShapeKind::Triangle:
            break;
    }
    return {};
}

class Compiler {
public:
    explicit Compiler(const SceneDesc& desc) : m_desc(desc) {}

    RenderScene run() {
        m_scene.dialect = m_desc.dialect;
        m_scene.camera = m_desc.camera;
        m_scene.background = m_desc.background;
        m_scene.ambient = m_desc.ambient;
        for (const LightDesc& l : m_desc.lights) m_scene.lights.push_back(compile_light(l));
        compile_materials();
        m_set_of_file.assign(m_desc.files.size(), -2);  // -2: not compiled yet
        if (!m_desc.files.empty()) place(0, Mat4(1.0));
        build_acceleration();
        fill_stats();
        return std::move(m_scene);
    }

private:
    static Light compile_light(const LightDesc& d) {
        Light l;
        l.kind = d.kind;
        l.color = d.color;
        l.position = d.position;
        if (d.kind != LightKind::Point) l.direction = glm::normalize(d.direction);
        l.constant_atten = d.constant_atten;
        l.linear_atten = d.linear_atten;
        l.quadratic_atten = d.quadratic_atten;
        l.cutoff_rad = d.cutoff_rad;
        l.spot_exponent = d.spot_exponent;
        return l;
    }

    void compile_materials() {
        // Global arrays with per-file offsets; the V0 default material goes last.
        for (const FileDesc& f : m_desc.files) {
            m_texture_offset.push_back(static_cast<int>(m_scene.textures.size()));
            for (const TextureDesc& t : f.textures) m_scene.textures.push_back(t.image);
            m_material_offset.push_back(static_cast<int>(m_scene.materials.size()));
            for (const MaterialDesc& md : f.materials) {
                Material m = to_material(md);
                if (md.texture >= 0) m.texture = m_texture_offset.back() + md.texture;
                m_scene.materials.push_back(m);
            }
        }
        m_default_material = static_cast<int>(m_scene.materials.size());
        m_scene.materials.push_back(to_material(v0_default_material()));
    }

    static Material to_material(const MaterialDesc& d) {
        Material m;
        m.emissive = d.emissive;
        m.ambient = d.ambient;
        m.diffuse = d.diffuse;
        m.specular = d.specular;
        m.specular_exponent = d.specular_exponent;
        m.transparent = d.transparent;
        m.refractive_index = d.refractive_index;
        return m;
    }

    // Places file `fi` in the world: compiles its set once, adds an instance for its own
    // shapes, and recurses into the files it instances.
    void place(size_t fi, const Mat4& world_from_file) {
        const int set = set_for(fi);
        if (set >= 0) {
            Instance inst;
            inst.set = set;
            inst.world_from_set = Transform::from_matrix(world_from_file);
            inst.identity = inst.world_from_set.is_identity();
            m_scene.instances.push_back(inst);
        }
        place_instances(m_desc.files[fi], m_desc.files[fi].root, world_from_file);
    }

    void place_instances(const FileDesc& f, const GroupDesc& g, const Mat4& world_from_group) {
        const Mat4 m = world_from_group * g.matrix;
        for (const InstanceDesc& in : g.instances)
            place(static_cast<size_t>(f.ray_files[static_cast<size_t>(in.ray_file)]), m);
        for (const GroupDesc& child : g.groups) place_instances(f, child, m);
    }

    int set_for(size_t fi) {
        if (m_set_of_file[fi] != -2) return m_set_of_file[fi];
        GeometrySet set;
        set.name = m_desc.files[fi].path;
        const size_t n = count_shapes(m_desc.files[fi].root);
        set.prims.reserve(n);
        set.prim_bounds.reserve(n);
        add_group(set, fi, m_desc.files[fi].root, Mat4(1.0));
        if (set.prims.empty()) {
            m_set_of_file[fi] = -1;
            return -1;
        }
        const auto t0 = std::chrono::steady_clock::now();
        set.bvh = build_bvh(set.prim_bounds);
        reorder(set);
        m_scene.stats.build_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        m_set_of_file[fi] = static_cast<int>(m_scene.sets.size());
        m_scene.sets.push_back(std::move(set));
        return m_set_of_file[fi];
    }

    // Puts the primitives (and each kind's array) in the BVH's leaf order, so a leaf reads its
    // primitives from consecutive memory; the BVH's order becomes the identity.
    static void reorder(GeometrySet& set) {
        GeometrySet out;
        out.name = std::move(set.name);
        out.transforms = std::move(set.transforms);
        const size_t n = set.prims.size();
        out.prims.reserve(n);
        out.prim_bounds.reserve(n);
        out.triangles.reserve(set.triangles.size());
        out.triangle_attribs.reserve(set.triangle_attribs.size());
        for (uint32_t old : set.bvh.indices) {
            Primitive p = set.prims[old];
            switch (p.kind) {
                case ShapeKind::Sphere:
                    p.index = move_one(set.spheres, out.spheres, p.index);
                    break;
                case ShapeKind::Box:
                    p.index = move_one(set.boxes, out.boxes, p.index);
                    break;
                case ShapeKind::Cylinder:
                    p.index = move_one(set.cylinders, out.cylinders, p.index);
                    break;
                case ShapeKind::Cone:
                    p.index = move_one(set.cones, out.cones, p.index);
                    break;
                case ShapeKind::Triangle:
                    out.triangle_attribs.push_back(set.triangle_attribs[p.index]);
                    p.index = move_one(set.triangles, out.triangles, p.index);
                    break;
            }
            out.prims.push_back(p);
            out.prim_bounds.push_back(set.prim_bounds[old]);
        }
        out.bvh = std::move(set.bvh);
        std::iota(out.bvh.indices.begin(), out.bvh.indices.end(), 0u);
        out.triangles_only = out.triangles.size() == out.prims.size();
        set = std::move(out);
    }

    template <class T>
    static uint32_t move_one(const std::vector<T>& from, std::vector<T>& to, uint32_t i) {
        to.push_back(from[i]);
        return static_cast<uint32_t>(to.size() - 1);
    }

    static size_t count_shapes(const GroupDesc& g) {
        size_t n = g.shapes.size();
        for (const GroupDesc& c : g.groups) n += count_shapes(c);
        return n;
    }

    void add_group(GeometrySet& set, size_t fi, const GroupDesc& g, const Mat4& parent) {
        const Mat4 m = parent * g.matrix;
        if (!g.shapes.empty()) {
            const bool identity = (m == Mat4(1.0));
            const Transform xf = Transform::from_matrix(m);
            const bool mirror = glm::determinant(Mat3(m)) < 0;
            int xf_index = -1;
            for (const ShapeDesc& s : g.shapes) {
                const bool analytic = !std::holds_alternative<TriangleDesc>(s.geometry);
                if (analytic && !identity && xf_index < 0) {
                    xf_index = static_cast<int>(set.transforms.size());
                    set.transforms.push_back(xf);
                }
                add_shape(set, fi, s, xf, identity ? -1 : xf_index, identity, mirror);
            }
        }
        for (const GroupDesc& child : g.groups) add_group(set, fi, child, m);
    }

    void add_shape(GeometrySet& set, size_t fi, const ShapeDesc& s, const Transform& xf,
                   int xf_index, bool identity, bool mirror) {
        Primitive p;
        p.material = s.material < 0 ? m_default_material : m_material_offset[fi] + s.material;
        p.transform = xf_index;
        const Mat4& m = xf.m;
        Bounds3 local;
        if (const auto* sp = std::get_if<SphereDesc>(&s.geometry)) {
            p.kind = ShapeKind::Sphere;
            p.index = static_cast<uint32_t>(set.spheres.size());
            set.spheres.push_back({sp->centre, sp->radius});
            local = xf_index < 0 ? bounds(set.spheres.back()) : bounds(set.spheres.back(), m);
        } else if (const auto* bx = std::get_if<BoxDesc>(&s.geometry)) {
            p.kind = ShapeKind::Box;
            p.index = static_cast<uint32_t>(set.boxes.size());
            set.boxes.push_back({bx->centre, 0.5 * bx->size});
            local = xf_index < 0 ? bounds(set.boxes.back()) : bounds(set.boxes.back(), m);
        } else if (const auto* cy = std::get_if<CylinderDesc>(&s.geometry)) {
            p.kind = ShapeKind::Cylinder;
            p.index = static_cast<uint32_t>(set.cylinders.size());
            set.cylinders.push_back({cy->centre, cy->radius, cy->height});
            local = xf_index < 0 ? bounds(set.cylinders.back()) : bounds(set.cylinders.back(), m);
        } else if (const auto* co = std::get_if<ConeDesc>(&s.geometry)) {
            p.kind = ShapeKind::Cone;
            p.index = static_cast<uint32_t>(set.cones.size());
            set.cones.push_back({co->centre, co->radius, co->height});
            local = xf_index < 0 ? bounds(set.cones.back()) : bounds(set.cones.back(), m);
        } else {
            const auto& td = std::get<TriangleDesc>(s.geometry);
            const FileDesc& f = m_desc.files[fi];
            p.kind = ShapeKind::Triangle;
            p.index = static_cast<uint32_t>(set.triangles.size());
            p.transform = -1;  // triangles are flattened into the set's frame
            const VertexDesc* v[3];
            for (int i = 0; i < 3; ++i) v[i] = &f.vertices[static_cast<size_t>(td.v[i])];
            // A mirroring transform flips the cross product; swap two vertices so the geometric
            // normal stays (A^-1)^T times the local one (spec §4.1), as refraction needs.
            if (mirror) std::swap(v[1], v[2]);
            Triangle tri = identity ? Triangle{v[0]->position, v[1]->position, v[2]->position}
                                    : Triangle{xf.point(v[0]->position), xf.point(v[1]->position),
                                               xf.point(v[2]->position)};
            TriangleAttribs attr;
            attr.has_normals = true;
            for (int i = 0; i < 3; ++i) {
                attr.uv[i] = v[i]->uv;
                const Vec3 n = v[i]->normal;
                if (n == Vec3(0.0)) {
                    attr.has_normals = false;
                } else {
                    attr.n[i] = identity ? n : glm::normalize(xf.normal_dir(n));
                }
            }
            set.triangles.push_back(tri);
            set.triangle_attribs.push_back(attr);
            set.prims.push_back(p);
            set.prim_bounds.push_back(bounds(tri));
            return;
        }
        set.prims.push_back(p);
        set.prim_bounds.push_back(xf_index < 0 ? local : widen(local));
    }

    void build_acceleration() {
        std::vector<Bounds3> inst_bounds;
        for (Instance& inst : m_scene.instances) {
            const Bounds3 b = m_scene.sets[static_cast<size_t>(inst.set)].bvh.bounds();
            inst.world_bounds = inst.identity ? b : inst.world_from_set.apply(b);
            inst_bounds.push_back(inst.world_bounds);
            if (m_scene.camera) {
                m_scene.world_bounds.extend(inst.world_bounds);
                continue;
            }
            // No camera: the default camera needs the tight world bounding box (spec §6.3).
            const GeometrySet& set = m_scene.sets[static_cast<size_t>(inst.set)];
            for (const Primitive& p : set.prims)
                m_scene.world_bounds.extend(world_bounds_of(set, p, inst.world_from_set.m));
        }
        const auto t0 = std::chrono::steady_clock::now();
        m_scene.top = build_bvh(inst_bounds, {1, 16});
        // Instances in the top BVH's leaf order, as for the sets' primitives.
        std::vector<Instance> ordered;
        ordered.reserve(m_scene.instances.size());
        for (uint32_t i : m_scene.top.indices) ordered.push_back(m_scene.instances[i]);
        m_scene.instances = std::move(ordered);
        std::iota(m_scene.top.indices.begin(), m_scene.top.indices.end(), 0u);
        m_scene.stats.build_seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }

    void fill_stats() {
        SceneStats& s = m_scene.stats;
        s.files = m_desc.files.size();
        s.instances = m_scene.instances.size();
        s.lights = m_scene.lights.size();
        s.materials = m_scene.materials.size() - 1;  // without the built-in default
        s.textures = m_scene.textures.size();
        for (const GeometrySet& set : m_scene.sets) s.unique_prims += set.prims.size();
        std::vector<size_t> uses(m_scene.sets.size(), 0);
        for (const Instance& inst : m_scene.instances) ++uses[static_cast<size_t>(inst.set)];
        for (size_t i = 0; i < m_scene.sets.size(); ++i)
            for (const Primitive& p : m_scene.sets[i].prims)
                s.prims_by_kind[static_cast<int>(p.kind)] += uses[i];
        s.skipped_shapes = m_desc.skipped_shapes;
    }

    const SceneDesc& m_desc;
    RenderScene m_scene;
    std::vector<int> m_set_of_file;
    std::vector<int> m_texture_offset, m_material_offset;
    int m_default_material = 0;
};

}  // namespace

RenderScene compile_scene(const SceneDesc& desc) { return Compiler(desc).run(); }

}  // namespace rt
