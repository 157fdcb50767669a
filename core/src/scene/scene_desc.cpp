// Helpers on the description: the bounds of a described shape (the viewer's group boxes) and
// the groups above a directive.
#include "rt/scene/scene_desc.h"

#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "rt/util/enum_names.h"

namespace rt {

Bounds3 bounds(const ShapeDesc& shape, const FileDesc& file, const Mat4& m) {
    return std::visit(
        [&](const auto& geo) {
            Bounds3 b;
            if constexpr (std::is_same_v<std::decay_t<decltype(geo)>, TriangleDesc>) {
                for (int v : geo.v)
                    if (v >= 0 && static_cast<size_t>(v) < file.vertices.size())
                        b.extend(Vec3(
                            m * glm::dvec4(file.vertices[static_cast<size_t>(v)].position, 1.0)));
            } else {
                b = bounds(to_shape(geo), m);
            }
            return b;
        },
        shape.geometry);
}

}  // namespace rt

namespace rt {

const char* csg_op_name(CsgOp op) {
    static constexpr const char* kNames[] = {"union", "intersection", "difference"};
    return enum_name(op, kNames, "difference");
}

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

}  // namespace

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

}  // namespace rt
