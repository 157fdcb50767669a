// Helpers on the description: the bounds of a described shape (the viewer's group boxes).
#include "rt/scene/scene_desc.h"

#include <variant>

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
    switch (op) {
        case CsgOp::Union:
            return "union";
        case CsgOp::Intersection:
            return "intersection";
        case CsgOp::Difference:
            break;
    }
    return "difference";
}

}  // namespace rt
