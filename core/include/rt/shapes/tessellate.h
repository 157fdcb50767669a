// The viewer's preview of one primitive: its triangles appended to a PreviewMesh (PreviewMesh
// and each shape's tessellate() are in shapes.h, each shape's code in its own file), with what
// the primitive is in its set's frame, so the viewer reads the kind rather than guessing it
// back from the vertices. Shapes only: the loop over a geometry set is the viewer's
// (app/rayview/state/preview_geometry.cpp).
#pragma once

#include <cstddef>

#include "rt/shapes/shapes.h"

namespace rt {

/// One primitive's part of a preview mesh: its kind, its triangles, and its numbers in the
/// set's frame. `solid` says that the primitive's transform keeps it the solid its kind names
/// there, with these numbers: a sphere (`centre`, `radius`), a box along the axes (`box`), a
/// torus about the y axis (`centre`, ring and tube radii in `radii`). A sphere scaled unevenly
/// (an ellipsoid), a box turned off the axes, a torus tilted, and the other kinds are not.
struct PreviewShape {
    ShapeKind kind = ShapeKind::Triangle;
    size_t first = 0, count = 0;  // its triangles in the mesh
    bool solid = false;
    Vec3 centre{0.0};
    double radius = 0;
    Vec2 radii{0.0};
    Bounds3 box;
};

/// Appends `shape` (a Sphere, Box, Cylinder, Cone or Torus), tessellated with `detail` segments
/// and mapped by `xf` into its set's frame (nullptr: as it is), every triangle tagged with
/// `material`; returns what it appended.
template <class S>
PreviewShape append_preview(const S& shape, const Transform* xf, int material, int detail,
                            PreviewMesh& out);
/// Appends a triangle (in its set's frame already) tagged with `material`.
PreviewShape append_preview(const Triangle& t, const TriangleAttribs& attribs, int material,
                            PreviewMesh& out);

}  // namespace rt
