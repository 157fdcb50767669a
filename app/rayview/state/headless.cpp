#include "headless.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "loader.h"
#include "rt/render/plan.h"

namespace rt::view {

int render_headless(const std::string& path, MissingTextures missing,
                    const RenderSettings& settings, int spp, std::optional<Dialect> dialect) {
    const LoadResult r = load_scene({path, missing, false, dialect});  // no preview
    if (!r.scene) {
        std::cerr << r.error << "\n";
        return 1;
    }
    const LoadedScene* s = r.scene.get();
    const std::string out = std::filesystem::path(path).stem().string() + ".png";
    try {
        RenderState state;
        render_samples(state, s->scene, make_render_plan(s->scene, settings), settings, spp);
        save_image(state.image(), out);
    } catch (const std::exception& e) {
        std::cerr << "rayview: error: " << rtapp::error_text(e, "rendering " + path) << "\n";
        return 1;
    }
    std::printf("rayview: rendered %s headless (%dx%d, %d spp) to %s\n", path.c_str(),
                settings.width, settings.height, spp, out.c_str());
    return 0;
}

}  // namespace rt::view
