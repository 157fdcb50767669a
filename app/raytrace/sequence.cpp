#include "sequence.h"

#include <cstdio>
#include <iostream>

#include "cli.h"
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

// Frame k: the scene's joints moved to its time (frame 0 is the compiled scene), rendered and
// written. Throws on failure (a SceneError carries its place; others are runtime errors).
void render_frame(const Options& opt, const rt::SceneDesc& desc, rt::RenderScene& scene, int k,
                  const rt::ProgressFn& progress, rt::RayCounters* rays) {
    if (k > 0) {
        rt::Diagnostics diag;
        rt::animate(scene, desc, opt.animation.time(k), &diag);
        for (const rt::Warning& w : diag.warnings()) std::cerr << w.str() << "\n";
    }
    const rt::RenderPlan plan = rt::make_render_plan(scene, opt);
    rt::RenderState state;
    rt::render_samples(state, scene, plan, opt, opt.spp, progress);
    *rays += state.rays;
    write_outputs(state.image(), rtapp::frame_path(opt.output, k), {}, opt.scene,
                  exr_output(opt, state, scene, plan));
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
    rtapp::WrittenFrames written;
    for (int k = 0; k < a.frames; ++k) {
        // Any failure (the animation at this time, a full disk) ends the run with no frame of
        // it left: a sequence is whole or not there (as raytrace-mpi's, docs/cluster.md).
        std::string why;
        try {
            render_frame(opt, desc, scene, k, frame_progress(bar, k, a.frames), &rays);
        } catch (const rt::SceneError& e) {  // its own line: file:line:col: error: ...
            std::cerr << e.what() << "\n";
            why = "the animation failed there";
        } catch (const std::exception& e) {  // std::bad_alloc: "out of memory while ..."
            why = rtapp::error_text(e, "rendering it");
        }
        if (!why.empty()) {
            std::cerr << "raytrace: error: frame " << k << " not written (" << why << "); "
                      << written.remove_all() << "\n";
            return 1;
        }
        written.add(rtapp::frame_path(opt.output, k));
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
