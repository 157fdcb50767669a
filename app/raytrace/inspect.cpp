#include "inspect.h"

#include <iostream>

#include "rt/render/inspect.h"
#include "rt/render/plan.h"
#include "rt/util/file_io.h"

namespace raytrace {

int run_inspect(const Options& opt, const rt::SceneDesc& desc, const rt::RenderScene& scene,
                const rt::CompileReport& report) {
    const rt::RenderPlan plan = rt::make_render_plan(scene, opt);
    const InspectOptions& in = opt.inspect;
    const rt::PixelTree tree =
        rt::inspect_pixel(scene, plan, opt, in.x, in.y, static_cast<uint32_t>(in.sample), opt.spp);
    const rt::InspectNames names{&desc, &report.prim_locs, &report.material_names};
    if (!in.json.empty()) rt::write_file_atomic(in.json, rt::inspect_json(tree, scene, names));
    std::cout << rt::inspect_text(tree, scene, names);
    if (!in.json.empty() && !opt.quiet) std::cout << "wrote     " << in.json << "\n";
    return 0;
}

}  // namespace raytrace
