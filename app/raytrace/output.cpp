#include "output.h"

#include <filesystem>
#include <fstream>
#include <iostream>

#include "rt/util/file_io.h"

namespace raytrace {

namespace {

namespace fs = std::filesystem;

bool probe_writable(const std::string& path, std::string* why) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        *why = "it is a directory";
        return false;
    }
    const std::string probe = path + ".part";
    {
        std::ofstream f(probe, std::ios::binary);
        if (!f) {
            *why = "cannot create files there";
            return false;
        }
    }
    fs::remove(probe, ec);
    return true;
}

}  // namespace

bool probe_outputs(const std::vector<std::string>& paths) {
    for (const std::string& path : paths) {
        if (path.empty()) continue;
        std::string why;
        if (!probe_writable(path, &why)) {
            std::cerr << "raytrace: error: cannot write '" << path << "': " << why << "\n";
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
    std::vector<std::string> staged;
    try {
        for (const auto& [path, text] : texts) {
            try {
                rt::write_file_atomic(path + ".part", text);
            } catch (const std::runtime_error&) {
                throw std::runtime_error("cannot write '" + path + "'");
            }
            staged.push_back(path);
        }
        if (const size_t bad = rt::count_non_finite(image))
            std::cerr << scene << ": warning: " << bad << " non-finite pixel values written as 0\n";
        if (rt::image_format_from_path(image_path) == rt::ImageFormat::Exr)
            rt::save_exr(image, exr.channels, exr.full_float, image_path);
        else
            rt::save_image(image, image_path);
        for (const std::string& path : staged) fs::rename(path + ".part", path);
    } catch (const std::exception&) {
        std::error_code ec;
        for (const std::string& path : staged) fs::remove(path + ".part", ec);
        throw;
    }
}

}  // namespace raytrace
