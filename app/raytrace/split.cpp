#include "split.h"

#include <cstdio>
#include <iostream>
#include <sstream>

#include "part_file.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/util/stopwatch.h"

namespace raytrace {

std::string settings_line(const Options& o) {
    std::ostringstream s;
    s.precision(17);
    s << o.width << "x" << o.height << " depth " << o.max_depth << " cutoff " << o.cutoff
      << " shadows " << o.shadows << " seed " << o.seed << " light-samples " << o.light_samples
      << " light-radius " << o.light_radius << " aperture " << o.aperture << " focus "
      << o.focus_distance << " roughness " << o.roughness << " dialect "
      << (o.dialect ? rt::dialect_name(*o.dialect) : "auto") << " textures "
      << (o.missing_textures == rt::MissingTextures::Checker ? "checker" : "error");
    if (const std::optional<rt::SceneTime> t = o.animation.time()) {
        s << " time " << t->seconds << " " << rt::interpolation_name(t->interpolation) << " "
          << rt::rotation_name(t->rotation);
    } else {
        s << " time key0";
    }
    return s.str();
}

int render_part_output(const Options& opt, const rt::SceneDesc& desc, const rt::RenderScene& scene,
                       Timings t) {
    rtapp::PartFile f;
    f.header.scene_hash = rtapp::scene_hash(desc);
    f.header.settings = settings_line(opt);
    f.header.width = opt.width;
    f.header.height = opt.height;
    f.header.spp = static_cast<uint32_t>(opt.spp);
    rt::RenderPart& p = f.part;
    p.x0 = opt.split.x0, p.y0 = opt.split.y0, p.x1 = opt.split.x1, p.y1 = opt.split.y1;
    p.first = opt.split.first, p.count = opt.split.count, p.total = f.header.spp;
    const auto t_render = rt::Clock::now();
    const rt::RenderPlan plan = rt::make_render_plan(scene, opt);
    rt::render_part(p, scene, plan, opt, terminal_progress_bar(opt.quiet));
    t.render_s = rt::seconds_since(t_render);
    rtapp::write_part(opt.output, f);
    if (!opt.quiet) {
        print_render_summary(t, p.rays);
        std::printf("wrote     %s (pixels %d,%d..%d,%d, samples %u..%u of %u)\n",
                    opt.output.c_str(), p.x0, p.y0, p.x1 - 1, p.y1 - 1, p.first,
                    p.first + p.count - 1, p.total);
    }
    return 0;
}

}  // namespace raytrace
