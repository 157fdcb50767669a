// Wall-clock timing for the programs' reports and the progressive time limit.
#pragma once

#include <chrono>

namespace rt {

using Clock = std::chrono::steady_clock;

/// Seconds elapsed since `t0`.
inline double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace rt
