// The animation's clock in the viewer: the time the joints hold, playback (loop,
// speed) and the interpolation and rotation choices. No GL or ImGui: ViewerState owns one and
// its restart path moves the joints to timeline.scene_time().
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "rt/scene/scene_desc.h"
#include "rt/scene/scene_time.h"

namespace rt::view {

struct Timeline {
    double time = 0;  // seconds into the animation
    bool playing = false;
    bool loop = true;  // at the end: back to 0 (else playback stops at the end)
    double speed = 1;  // animation seconds per second of real time
    double fps = 24;   // the frames the timeline counts and "render animation" writes
    Interpolation interpolation = Interpolation::CatmullRom;
    Rotation rotation = Rotation::Quaternion;
    std::string joint_warning;  // the last singular-joint warning noted (said once)

    SceneTime scene_time() const { return {time, interpolation, rotation}; }
    /// The frame shown: floor(time * fps).
    int frame() const { return static_cast<int>(std::floor(time * fps + 1e-9)); }
    /// Advances by `real_seconds` times the speed while playing, over an animation `length`
    /// seconds long (the loop wraps, without it playback stops at the end). Returns whether the
    /// time changed.
    bool advance(double real_seconds, double length);
    /// Jumps to `t`, clamped to [0, length].
    void seek(double t, double length);
    /// Play or pause; playing from the end of an animation that does not loop starts at 0.
    void toggle_play(double length) {
        if (!playing && time >= length && !loop) time = 0;
        playing = !playing;
    }
    void set_fps(double f) { fps = std::clamp(f, 1.0, 240.0); }
    void set_speed(double s) { speed = std::clamp(s, 0.05, 8.0); }
    void set_loop(bool on) { loop = on; }
    void pause() { playing = false; }
    void set_choices(Interpolation i, Rotation r) {
        interpolation = i;
        rotation = r;
    }
};

/// The length of a scene's animation: its longest key file's duration (0 when no joint is
/// bound to a key file).
double animation_length(const SceneDesc& desc);

}  // namespace rt::view
