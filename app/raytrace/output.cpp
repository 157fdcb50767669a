#include "output.h"

#include <iostream>

#include "rt/util/file_io.h"

namespace raytrace {

bool probe_outputs(const std::vector<std::string>& paths) {
    for (const std::string& path : paths) {
        if (path.empty()) continue;
        if (const std::string why = rt::writable_error(path); !why.empty()) {
            std::cerr << "raytrace: error: " << why << "\n";
            return false;
        }
    }
    return true;
}

ExrOutput exr_output(const Options& opt, const rt::RenderState& state, const rt::RenderScene& scene,
                     const rt::RenderPlan& plan) {
    ExrOutput out;
    out.full_float = opt.exr.full_float;
    if (!opt.exr.aovs.any()) return out;
    rt::RenderSettings settings = opt;
    // Progressive passes place every sample by the progressive sequence (run_progressive()).
    if (opt.progressive.enabled) settings.centre_first_sample = false;
    out.channels = rt::aov_channels(opt.exr.aovs, state, scene, plan, settings);
    return out;
}

void write_outputs(const rt::Image& image, const std::string& image_path,
                   const std::vector<TextFile>& texts, const std::string& scene,
                   const ExrOutput& exr) {
    std::vector<std::pair<std::string, std::string>> staged;  // (scratch file, its name)
    try {
        for (const auto& [path, text] : texts)
            staged.emplace_back(rt::write_scratch_file(path, text), path);
        if (const size_t bad = rt::count_non_finite(image))
            std::cerr << scene << ": warning: " << bad << " non-finite pixel values written as 0\n";
        if (rt::image_format_from_path(image_path) == rt::ImageFormat::Exr)
            rt::save_exr(image, exr.channels, exr.full_float, image_path);
        else
            rt::save_image(image, image_path);
        for (const auto& [scratch, path] : staged) rt::commit_scratch_file(scratch, path);
    } catch (const std::exception&) {
        for (const auto& [scratch, path] : staged) rt::discard_scratch_file(scratch);
        throw;
    }
}

}  // namespace raytrace
