#include "state/timeline.h"

#include <algorithm>

namespace rt::view {

bool Timeline::advance(double real_seconds, double length) {
    if (!playing || length <= 0) return false;
    const double before = time;
    time += real_seconds * speed;
    if (time >= length || time < 0) {
        if (loop) {
            time = std::fmod(time, length);
            if (time < 0) time += length;
        } else {
            time = std::clamp(time, 0.0, length);
            playing = false;
        }
    }
    return time != before;
}

void Timeline::seek(double t, double length) {
    time = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, std::max(0.0, length));
}

double animation_length(const SceneDesc& desc) {
    double length = 0;
    for (const KeyTrack& t : desc.tracks) length = std::max(length, t.duration);
    return length;
}

}  // namespace rt::view
