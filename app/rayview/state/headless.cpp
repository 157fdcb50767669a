#include "state/headless.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "rt/render/plan.h"
#include "state/compare_view.h"
#include "state/loader.h"

namespace rt::view {

int render_headless(const std::string& path, MissingTextures missing,
                    const RenderSettings& settings, int spp, std::optional<Dialect> dialect,
                    const std::string& compare) {
    const LoadResult r = load_scene({path, missing, false, dialect});  // no preview
    if (!r.scene) {
        std::cerr << r.error << "\n";
        return 1;
    }
    const LoadedScene* s = r.scene.get();
    if (!compare.empty()) {  // raycompare's job for one image: the figures
        CompareView c;
        c.path = compare;
        try {
            c.theirs = load_image(compare);
        } catch (const std::exception& e) {
            std::cerr << "rayview: error: cannot compare with " << compare << ": " << e.what()
                      << "\n";
            return 1;
        }
        c.settings.linear = holds_linear(image_format_from_path(compare));
        RenderSettings rs = settings;
        rs.width = c.theirs.width;
        rs.height = c.theirs.height;
        RenderState state;
        render_samples(state, s->scene, make_render_plan(s->scene, rs), rs, spp);
        c.reference = state.image();
        c.current = true;
        c.recompare();
        std::printf("rayview: %s\n", compare_status(c).c_str());
        return 0;
    }
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
