// An index range cut over the machine's threads: the load's loops over a mesh's directives and
// primitives (the parse's pages, the compile's bounds, vertices and packed blocks). Not for
// code built without exceptions (the web build's SIMD kernels).
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

#include "rt/util/threads.h"

namespace rt {

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
