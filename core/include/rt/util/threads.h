// Whether this program can start threads, and how many the machine has. Every build can but the
// web page's single-thread program (WebAssembly without shared memory, for pages served without
// cross-origin isolation; linked from the same objects as the threads program, so this is
// asked at run time): there the work that would go to other threads runs on the caller's.
#pragma once

#include <algorithm>
#include <thread>

#ifdef __EMSCRIPTEN__
#include <emscripten/threading.h>
#endif

namespace rt {

inline bool have_threads() {
#ifdef __EMSCRIPTEN__
    return emscripten_has_threading_support();
#else
    return true;
#endif
}

/// The threads the machine runs at once (at least 1; 1 without threads).
inline unsigned hardware_threads() {
    return have_threads() ? std::max(1u, std::thread::hardware_concurrency()) : 1u;
}

}  // namespace rt
