// The viewer's preview mesh of a whole geometry set (PreviewMesh and each shape's tessellate()
// are in shapes.h, each shape's code in its own file).
#pragma once

#include <cstdint>
#include <vector>

#include "rt/compile/render_scene.h"

namespace rt {

/// Every primitive of a set in the set's frame, tagged with its material. Instances draw it
/// with their world_from_set transform.
PreviewMesh tessellate_set(const GeometrySet& set, int detail);

}  // namespace rt
