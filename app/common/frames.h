// Image sequences, shared by raytrace --frames and rayview's "render animation": frame file
// names from a printf-style pattern, and the optional video encoding by ffmpeg.
#pragma once

#include <string>
#include <vector>

namespace rtapp {

/// Frame k's file name from a pattern holding one %d (with an optional 0 flag and width:
/// "frame_%04d.png"; "%%" is a literal %). Throws std::invalid_argument for another pattern.
std::string frame_path(const std::string& pattern, int k);

/// The frames a sequence run (raytrace --frames, raytrace-mpi --frames) has written. A run that
/// fails removes them (docs/cluster.md): a sequence is whole or not there, never a prefix that
/// looks finished.
class WrittenFrames {
public:
    void add(const std::string& path) { m_paths.push_back(path); }
    int count() const { return static_cast<int>(m_paths.size()); }
    /// Removes them; says so for the failure's message: "no frame was written", "the 3 frames
    /// written so far were removed".
    std::string remove_all();

private:
    std::vector<std::string> m_paths;
};

/// The full path of `program` found on PATH, or "" when it is not installed.
std::string find_program(const std::string& program);

/// Encodes frames pattern(0) .. pattern(frames - 1) at `fps` into `video` with ffmpeg (H.264,
/// yuv420p; written under a temporary name, renamed when complete). False with `error` set when
/// ffmpeg is missing or fails; nothing is left at `video` then.
bool encode_video(const std::string& pattern, int frames, double fps, const std::string& video,
                  std::string* error);

}  // namespace rtapp
