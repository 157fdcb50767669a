#include "preview_geometry.h"

#include "rt/shapes/tessellate.h"

namespace rt::view {

PreviewGeometry prepare_preview(const RenderScene& scene, int detail) {
    // Sets no instance places are not tessellated.
    PreviewGeometry g;
    g.detail = detail;
    g.sets.resize(scene.sets.size());
    for (const Instance& inst : scene.instances)
        g.sets[static_cast<size_t>(inst.set)].placed = true;
    for (size_t si = 0; si < scene.sets.size(); ++si) {
        PreviewGeometry::Set& s = g.sets[si];
        if (!s.placed) continue;
        s.mesh = tessellate_set(scene.sets[si], detail);
        add_csg_leaves(scene.sets[si], &s.mesh, &s.csg);
    }
    return g;
}

}  // namespace rt::view
