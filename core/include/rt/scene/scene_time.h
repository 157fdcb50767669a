// The render time of spec §14.7 and what it does to a description: the value of every bound DOF
// at that time, and the static scene a frame equals (every joint a plain group holding J(t)).
// Without a time (std::nullopt) every joint holds its key 0 as read.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rt/scene/animation.h"
#include "rt/scene/scene_desc.h"
#include "rt/util/error.h"

namespace rt {

/// `--at T` with its interpolation and rotation (the defaults are the spec's).
struct SceneTime {
    double seconds = 0;
    Interpolation interpolation = Interpolation::CatmullRom;
    Rotation rotation = Rotation::Quaternion;
    bool operator==(const SceneTime&) const = default;
};

/// J of each track at a time, and whether it is singular by the §4.1 test (spec §14.6: the
/// shapes of its joints are then omitted).
struct JointValues {
    std::vector<Mat4> matrix;
    std::vector<char> singular;
};

/// The values of `tracks` at `time` (key 0 as read without one); one warning per singular track
/// into `diag`, when given. Throws SceneError where a quaternion normalizes to nothing.
JointValues joint_values(const std::vector<KeyTrack>& tracks, const std::optional<SceneTime>& time,
                         Diagnostics* diag = nullptr);

/// "t = 1.5", or "key 0" for no time: how messages name a time.
std::string time_name(const std::optional<SceneTime>& time);

/// The static description a frame at `time` renders like: every bound joint becomes a plain
/// group holding J(t), an empty one where J(t) is singular, and the tracks are dropped.
SceneDesc scene_at_time(const SceneDesc& desc, const std::optional<SceneTime>& time,
                        Diagnostics* diag = nullptr);

}  // namespace rt
