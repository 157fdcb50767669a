#include "data_dir.h"

#include <cstdlib>
#include <stdexcept>
#include <system_error>

#ifndef RT_DATA_RELATIVE
#error "RT_DATA_RELATIVE (the data directory relative to the programs) comes from CMake"
#endif

namespace rtapp {

namespace fs = std::filesystem;

fs::path executable_dir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe.parent_path();
}

std::vector<fs::path> data_dir_candidates() {
    std::vector<fs::path> dirs;
    if (const char* env = std::getenv("RAYTRACER_DATA_DIR"); env && *env) dirs.emplace_back(env);
    if (const fs::path exe = executable_dir(); !exe.empty())
        dirs.push_back((exe / RT_DATA_RELATIVE).lexically_normal());
    return dirs;
}

fs::path find_data_dir(const std::string& entry) {
    std::string looked;
    for (const fs::path& dir : data_dir_candidates()) {
        std::error_code ec;
        if (fs::exists(dir / entry, ec)) return dir;
        looked += (looked.empty() ? "" : ", ") + dir.string();
    }
    throw std::runtime_error("cannot find " + entry + " (looked in " +
                             (looked.empty() ? std::string("no place") : looked) +
                             "; set RAYTRACER_DATA_DIR to the directory that holds it)");
}

}  // namespace rtapp
