#include "selection.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "rt/accel/intersect.h"
#include "rt/compile/compile.h"
#include "rt/render/camera.h"
#include "rt/shapes/shapes.h"

namespace rt::view {

namespace {

bool same_loc(const SourceLoc& a, const SourceLoc& b) {
    return a.line == b.line && a.col == b.col && a.file && b.file && *a.file == *b.file;
}

// The groups (and CSG nodes) from `g` down to the directive at `loc`, outermost first, as
// "group at line 12 > joint 'arm' at line 15"; false when it is not below `g`.
bool find_group_path(const GroupDesc& g, const SourceLoc& loc, std::vector<std::string>* path) {
    for (const ShapeDesc& s : g.shapes)
        if (same_loc(s.loc, loc)) return true;
    auto step = [&](const GroupDesc& child, const std::string& what) {
        path->push_back(what + " at line " + std::to_string(child.loc.line));
        if (find_group_path(child, loc, path)) return true;
        path->pop_back();
        return false;
    };
    for (const GroupDesc& child : g.groups)
        if (step(child, child.joint.empty() ? "group" : "joint '" + child.joint + "'")) return true;
    for (const CsgDesc& c : g.csgs) {
        if (same_loc(c.loc, loc)) return true;
        for (const GroupDesc& operand : c.operands)
            if (step(operand, std::string(csg_op_name(c.op)) + " operand")) return true;
    }
    return false;
}

std::string group_path(const SceneDesc& desc, const SourceLoc& loc) {
    for (const FileDesc& f : desc.files) {
        std::vector<std::string> path;
        if (!find_group_path(f.root, loc, &path)) continue;
        std::string text = std::filesystem::path(f.path).filename().string();
        for (const std::string& p : path) text += " > " + p;
        return text;
    }
    return "";
}

}  // namespace

Selection pick_at(const LoadedScene& scene, const OrbitCamera& camera, int w, int h, double x,
                  double y) {
    const RenderScene& rs = scene.scene;
    w = std::max(1, w);
    h = std::max(1, h);
    const Camera cam = make_camera(compile_camera(camera.desc()), w, h);
    const Ray ray = cam.generate(0, 0, x * w, y * h);
    Hit hit;
    if (!intersect(rs, ray, {0, kInf}, &hit)) return {};
    const Instance& inst = rs.instances[static_cast<size_t>(hit.instance)];
    const GeometrySet& set = rs.sets[static_cast<size_t>(inst.set)];
    const Primitive& prim = set.prims[hit.prim];
    Selection s;
    s.instance = hit.instance;
    s.prim = hit.prim;
    s.point = ray.o + hit.t * ray.d;
    const Bounds3 b = set.prim_bounds(hit.prim);
    s.bounds = inst.identity ? b : inst.world_from_set.apply(b);
    s.shape = prim.csg >= 0 ? "CSG node" : shape_kind_name(prim.kind);
    const size_t m = static_cast<size_t>(prim.material);
    s.material_index = prim.material;
    const std::string name = m < scene.material_names.size() ? scene.material_names[m] : "";
    s.material = (name.empty() ? "" : "!" + name + "! ") + "(material " + std::to_string(m) + ")";
    const auto& locs = scene.prim_locs;
    if (static_cast<size_t>(inst.set) < locs.size() && hit.prim < locs[inst.set].size()) {
        const SourceLoc& loc = locs[inst.set][hit.prim];
        s.where = loc.str();
        s.groups = group_path(loc.file ? scene.desc : SceneDesc{}, loc);
    }
    return s;
}

}  // namespace rt::view
