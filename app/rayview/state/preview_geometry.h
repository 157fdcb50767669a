// The preview's geometry before any GL: each placed set tessellated, with its CSG leaves'
// texels. Made off the interface thread while a scene loads (SceneLoader), so the frame that
// swaps the scene in only uploads it. No GL here.
#pragma once

#include <vector>

#include "csg_preview.h"
#include "rt/compile/render_scene.h"

namespace rt::view {

/// One entry per set of the scene; a set no instance places is left empty.
struct PreviewGeometry {
    struct Set {
        bool placed = false;
        PreviewMesh mesh;
        CsgTexels csg;
    };
    std::vector<Set> sets;
    int detail = 0;
};
PreviewGeometry prepare_preview(const RenderScene& scene, int detail = 48);

}  // namespace rt::view
