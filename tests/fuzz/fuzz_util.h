// What the fuzz targets share: a private temporary directory to work in (made on first use,
// entered, removed at exit), and writing a file there.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace rt_fuzz {

inline std::string g_dir;

inline void remove_dir() {
    std::error_code ec;
    std::filesystem::remove_all(g_dir, ec);
}

/// The directory; the first call makes it and enters it, so relative names stay inside it.
inline const std::string& work_dir() {
    if (!g_dir.empty()) return g_dir;
    std::string tmpl = (std::filesystem::temp_directory_path() / "rt_fuzz_XXXXXX").string();
    if (!mkdtemp(tmpl.data())) {
        std::perror("mkdtemp");
        std::abort();
    }
    g_dir = tmpl;
    std::atexit(remove_dir);
    if (chdir(g_dir.c_str()) != 0) {
        std::perror("chdir");
        std::abort();
    }
    return g_dir;
}

/// Writes `data` to `name` in the directory (replacing it); returns its path.
inline std::string write_file(const std::string& name, std::string_view data) {
    const std::string path = work_dir() + "/" + name;
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(data.data(), static_cast<std::streamsize>(data.size()));
    return path;
}

}  // namespace rt_fuzz
