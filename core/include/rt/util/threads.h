// Whether this program can start threads, and how many the machine has. Every build can but the
// web page's single-thread program (WebAssembly without shared memory, for pages served without
// cross-origin isolation; linked from the same objects as the threads program, so this is
// asked at run time): there the work that would go to other threads runs on the caller's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

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

/// Runs fn(begin, end) over [0, n) cut into consecutive ranges of at least `grain` items, one
/// per thread (at most `threads`); the calling thread takes the first, and a range no thread can
/// be started for runs on the caller. Returns once every range is done. When ranges throw, the
/// exception of the lowest one is rethrown: the error a loop over [0, n) in order meets first,
/// provided fn stops at the first error of its range.
template <class F>
void parallel_ranges(std::size_t n, std::size_t grain, F&& fn,
                     unsigned threads = hardware_threads()) {
    const std::size_t most = std::max<std::size_t>(1, n / std::max<std::size_t>(grain, 1));
    const std::size_t parts = std::min<std::size_t>(std::max(threads, 1u), most);
    if (parts < 2) {
        if (n > 0) fn(std::size_t{0}, n);
        return;
    }
    std::vector<std::exception_ptr> errors(parts);
    auto range = [&](std::size_t p) {
        try {
            fn(p * n / parts, (p + 1) * n / parts);
        } catch (...) {
            errors[p] = std::current_exception();
        }
    };
    std::vector<std::thread> helpers;
    helpers.reserve(parts - 1);
    for (std::size_t p = 1; p < parts; ++p) {
        try {
            helpers.emplace_back(range, p);
        } catch (const std::system_error&) {
            range(p);  // no thread to be had
        }
    }
    range(0);
    for (std::thread& t : helpers) t.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

}  // namespace rt
