#include "sequence.h"

#include <cstdio>
#include <iostream>

#include "frames.h"
#include "output.h"
#include "rt/compile/compile.h"
#include "rt/render/plan.h"
#include "rt/render/render.h"
#include "rt/util/stopwatch.h"

namespace raytrace {

namespace {

// The whole sequence's progress from one frame's rows.
rt::ProgressFn frame_progress(const rt::ProgressFn& bar, int frame, int frames) {
    if (!bar) return {};
    return [=](int done, int total) {
        const int scale = total > 0 ? total : 1;
        bar(frame * scale + done, frames * scale);
    };
}

}  // namespace

int render_sequence(const Options& opt, const rt::SceneDesc& desc, rt::RenderScene& scene,
                    Timings t) {
    const AnimationOptions& a = opt.animation;
    if (!a.video.empty() && rtapp::find_program("ffmpeg").empty())
        std::cerr << "raytrace: warning: --video: ffmpeg is not installed (apt install ffmpeg); "
                     "writing the frames only\n";
    const rt::ProgressFn bar = terminal_progress_bar(opt.quiet);
    rt::RayCounters rays;
    const auto t_render = rt::Clock::now();
    for (int k = 0; k < a.frames; ++k) {
        const std::string path = rtapp::frame_path(opt.output, k);
        if (k > 0) {  // frame 0 is the compiled scene
            rt::Diagnostics diag;
            try {
                rt::animate(scene, desc, a.time(k), &diag);
            } catch (const rt::SceneError& e) {
                std::cerr << e.what() << "\n"
                          << "raytrace: frame " << k << " not written; " << k << " frame"
                          << (k == 1 ? "" : "s") << " before it were\n";
                return 1;
            }
            for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
        }
        const rt::RenderPlan plan = rt::make_render_plan(scene, opt);
        rt::RenderState state;
        rt::render_samples(state, scene, plan, opt, opt.spp, frame_progress(bar, k, a.frames));
        rays += state.rays;
        write_outputs(state.image(), path, {}, opt.scene, exr_output(opt, state, scene, plan));
    }
    t.render_s = rt::seconds_since(t_render);
    if (!opt.quiet) {
        print_render_summary(t, rays);
        std::printf("wrote     %d frame%s, %s .. %s (%.3f s per frame)\n", a.frames,
                    a.frames == 1 ? "" : "s", rtapp::frame_path(opt.output, 0).c_str(),
                    rtapp::frame_path(opt.output, a.frames - 1).c_str(), t.render_s / a.frames);
    }
    if (a.video.empty() || rtapp::find_program("ffmpeg").empty()) return 0;
    std::string error;
    if (!rtapp::encode_video(opt.output, a.frames, a.fps, a.video, &error)) {
        std::cerr << "raytrace: error: " << error << "\n";
        return 1;
    }
    if (!opt.quiet) std::printf("wrote     %s\n", a.video.c_str());
    return 0;
}

}  // namespace raytrace
