// Whether this program can start threads, and how many the machine has. Every build can but the
// web page's single-thread program (WebAssembly without shared memory, for pages served without
// cross-origin isolation; linked from the same objects as the threads program, so this is
// asked at run time): there the work that would go to other threads runs on the caller's.
#pragma once

#include <algorithm>
#include <thread>

#if defined(__linux__) && !defined(__EMSCRIPTEN__)
#include <sched.h>
#endif

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

/// Whether this is the web page's main browser thread. Threads started from it make progress only
/// while it lets them (their file access is proxied to it), so work that would fan out to
/// threads and wait for them stays on it (a scene the page opens at start-up is parsed there).
inline bool on_browser_main_thread() {
#ifdef __EMSCRIPTEN__
    return emscripten_is_main_browser_thread();
#else
    return false;
#endif
}

/// The threads this process may run at once (at least 1; 1 without threads): the CPUs it is bound
/// to where it is bound (a cluster's scheduler or `mpirun` binds each rank to its cores), else the
/// machine's.
inline unsigned hardware_threads() {
    if (!have_threads()) return 1u;
#if defined(__linux__) && !defined(__EMSCRIPTEN__)
    cpu_set_t cpus;
    CPU_ZERO(&cpus);
    if (sched_getaffinity(0, sizeof cpus, &cpus) == 0 && CPU_COUNT(&cpus) > 0)
        return static_cast<unsigned>(CPU_COUNT(&cpus));
#endif
    return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace rt
