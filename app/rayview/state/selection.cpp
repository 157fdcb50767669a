#include "state/selection.h"

#include <algorithm>
#include <vector>

#include "rt/accel/intersect.h"
#include "rt/compile/compile.h"
#include "rt/render/camera.h"
#include "rt/shapes/shapes.h"

namespace rt::view {

Selection selection_of(const LoadedScene& scene, int instance, uint32_t prim_index,
                       const Vec3& point) {
    const RenderScene& rs = scene.scene;
    if (instance < 0 || static_cast<size_t>(instance) >= rs.instances.size()) return {};
    const Instance& inst = rs.instances[static_cast<size_t>(instance)];
    const GeometrySet& set = rs.sets[static_cast<size_t>(inst.set)];
    if (prim_index >= set.prims.size()) return {};
    const Primitive& prim = set.prims[prim_index];
    Selection s;
    s.instance = instance;
    s.prim = prim_index;
    s.point = point;
    const Bounds3 b = set.prim_bounds(prim_index);
    s.bounds = inst.identity ? b : inst.world_from_set.apply(b);
    s.shape = prim.csg >= 0 ? "CSG node" : shape_kind_name(prim.kind);
    const size_t m = static_cast<size_t>(prim.material);
    s.material_index = prim.material;
    const std::string name = m < scene.material_names.size() ? scene.material_names[m] : "";
    s.material = (name.empty() ? "" : "!" + name + "! ") + "(material " + std::to_string(m) + ")";
    const auto& locs = scene.prim_locs;
    if (static_cast<size_t>(inst.set) < locs.size() && prim_index < locs[inst.set].size()) {
        const SourceLoc& loc = locs[inst.set][prim_index];
        s.where = loc.str();
        s.groups = group_path(loc.file ? scene.desc : SceneDesc{}, loc);
    }
    return s;
}

Selection pick_at(const LoadedScene& scene, const OrbitCamera& camera, int w, int h, double x,
                  double y) {
    w = std::max(1, w);
    h = std::max(1, h);
    const Camera cam = camera.camera(w, h);
    const Ray ray = cam.generate(0, 0, x * w, y * h);
    Hit hit;
    if (!intersect(scene.scene, ray, {0, kInf}, &hit)) return {};
    return selection_of(scene, hit.instance, hit.prim, ray.o + hit.t * ray.d);
}

}  // namespace rt::view
