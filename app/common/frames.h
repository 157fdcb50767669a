// Image sequences, shared by raytrace --frames and rayview's "render animation": frame file
// names from a printf-style pattern, and the optional video encoding by ffmpeg.
#pragma once

#include <string>

namespace rtapp {

/// Frame k's file name from a pattern holding one %d (with an optional 0 flag and width:
/// "frame_%04d.png"; "%%" is a literal %). Throws std::invalid_argument for another pattern.
std::string frame_path(const std::string& pattern, int k);

/// The full path of `program` found on PATH, or "" when it is not installed.
std::string find_program(const std::string& program);

/// Encodes frames pattern(0) .. pattern(frames - 1) at `fps` into `video` with ffmpeg (H.264,
/// yuv420p; written under a temporary name, renamed when complete). False with `error` set when
/// ffmpeg is missing or fails; nothing is left at `video` then.
bool encode_video(const std::string& pattern, int frames, double fps, const std::string& video,
                  std::string* error);

}  // namespace rtapp
