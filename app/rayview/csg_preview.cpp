#include "csg_preview.h"

namespace rt::view {

// No set holds CSG nodes before the CSG render path: nothing to add.
void add_csg_leaves(const GeometrySet& /*set*/, int /*detail*/, PreviewMesh* /*mesh*/,
                    CsgTexels* /*texels*/) {}

}  // namespace rt::view
