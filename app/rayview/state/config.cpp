#include "state/config.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "rt/util/file_io.h"

namespace rt::view {

std::string config_path() {
    const char* xdg = std::getenv("XDG_CONFIG_HOME");
    if (xdg && *xdg) return std::string(xdg) + "/rayview/rayview.conf";
    const char* home = std::getenv("HOME");
    if (home && *home) return std::string(home) + "/.config/rayview/rayview.conf";
    return "";
}

namespace {

std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

}  // namespace

UserConfig read_config(const std::string& path, std::string* problem) {
    UserConfig c;
    std::string text, why;
    std::error_code ec;
    // Absent on a first run: the defaults, quietly. Anything else unreadable is said.
    if (!read_file(path, &text, &why) && problem && std::filesystem::exists(path, ec))
        *problem = why;
    std::istringstream f(text);
    for (std::string line; std::getline(f, line);) {
        const size_t eq = line.find('=');
        if (line.empty() || line[0] == '#' || eq == std::string::npos) continue;
        const std::string key = trim(line.substr(0, eq)), value = trim(line.substr(eq + 1));
        std::istringstream v(value);
        if (key == "window") {
            int w = 0, h = 0;
            char x = 0;
            if (v >> w >> x >> h && x == 'x' && w >= 64 && h >= 64 && w <= 16384 && h <= 16384)
                c.window_w = w, c.window_h = h;
        } else if (key == "ui_scale") {
            float s = 0;
            if (v >> s && std::isfinite(s) && s >= 0.5f && s <= 4.0f) c.ui_scale = s;
        } else if (key == "recent" && !value.empty() && c.recent.size() < UserConfig::kMaxRecent) {
            c.recent.push_back(value);
        }
    }
    return c;
}

bool write_config(const std::string& path, const UserConfig& c) {
    if (path.empty()) return false;
    std::ostringstream out;
    out << "# rayview's settings, written when it closes\n";
    out << "window = " << c.window_w << "x" << c.window_h << "\n";
    out << "ui_scale = " << c.ui_scale << "\n";
    for (size_t i = 0; i < c.recent.size() && i < UserConfig::kMaxRecent; ++i)
        out << "recent = " << c.recent[i] << "\n";
    try {
        std::filesystem::create_directories(std::filesystem::path(path).parent_path());
        write_file_atomic(path, out.str());
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace rt::view
