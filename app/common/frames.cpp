#include "frames.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "rt/util/file_io.h"

extern char** environ;

namespace rtapp {

namespace fs = std::filesystem;

std::string frame_path(const std::string& pattern, int k) {
    std::string out;
    int fields = 0;
    for (size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') {
            out += pattern[i];
            continue;
        }
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            out += '%', ++i;
            continue;
        }
        size_t j = i + 1;
        const bool zero = j < pattern.size() && pattern[j] == '0';
        if (zero) ++j;
        int width = 0;
        for (; j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])); ++j)
            width = std::min(width * 10 + (pattern[j] - '0'), 32);
        if (j >= pattern.size() || pattern[j] != 'd')
            throw std::invalid_argument("'" + pattern + "': only %d, %0Nd and %% may follow a %");
        std::string num = std::to_string(k);
        if (static_cast<int>(num.size()) < width)
            num.insert(0, static_cast<size_t>(width) - num.size(), zero ? '0' : ' ');
        out += num;
        ++fields;
        i = j;
    }
    if (fields != 1)
        throw std::invalid_argument(
            "a sequence needs one frame number in its file name, such as "
            "frame_%04d.png; got '" +
            pattern + "'");
    return out;
}

std::string WrittenFrames::remove_all() {
    const size_t n = m_paths.size();
    std::error_code ec;
    for (const std::string& path : m_paths) fs::remove(path, ec);
    m_paths.clear();
    if (n == 0) return "no frame was written";
    return n == 1 ? "the 1 frame written so far was removed"
                  : "the " + std::to_string(n) + " frames written so far were removed";
}

std::string find_program(const std::string& program) {
    const char* path = std::getenv("PATH");
    if (!path) return "";
    std::string dirs = path;
    for (size_t start = 0; start <= dirs.size();) {
        size_t end = dirs.find(':', start);
        if (end == std::string::npos) end = dirs.size();
        const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
        const std::string candidate = dir + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate))
            return candidate;
        start = end + 1;
    }
    return "";
}

bool encode_video(const std::string& pattern, int frames, double fps, const std::string& video,
                  std::string* error) {
    const std::string ffmpeg = find_program("ffmpeg");
    if (ffmpeg.empty()) {
        *error =
            "ffmpeg is not installed (apt install ffmpeg); the frames are written, the video "
            "is not";
        return false;
    }
    // ffmpeg picks the container by the extension: the scratch file's name keeps it (and it
    // is new, so ffmpeg -y overwrites nothing of the user's).
    const fs::path out(video);
    fs::path part;
    try {
        part = rt::create_scratch_file(video, nullptr, out.extension().string());
    } catch (const std::exception& e) {
        *error = e.what();
        return false;
    }
    const std::string rate = std::to_string(fps), count = std::to_string(frames);
    std::vector<std::string> args = {ffmpeg,      "-nostdin",      "-y",
                                     "-loglevel", "error",         "-framerate",
                                     rate,        "-start_number", "0",
                                     "-i",        pattern,         "-frames:v",
                                     count,       "-vf",           "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                     "-pix_fmt",  "yuv420p",       part.string()};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawn(&pid, ffmpeg.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
        rt::discard_scratch_file(part);
        *error = "cannot run " + ffmpeg;
        return false;
    }
    rt::set_scratch_writer(pid);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
    }
    rt::set_scratch_writer(0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        rt::discard_scratch_file(part);
        *error = "ffmpeg failed to encode " + video + " (its messages are above)";
        return false;
    }
    try {
        rt::commit_scratch_file(part, video);
    } catch (const std::exception& e) {
        *error = e.what();
        return false;
    }
    return true;
}

}  // namespace rtapp
