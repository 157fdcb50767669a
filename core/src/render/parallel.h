// Tiled parallel work for the render loop: threads claim tiles one at a time until none is left
// or a stop is requested.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "rt/render/shading.h"

namespace rt {

/// Runs fn(tile, rays) for every tile in [0, tiles) on up to `threads` threads (the calling
/// thread among them); each thread counts its rays in its own `rays`, summed into `total` at the
/// end. `stop`, when set, is polled before each tile; fn returns false when it saw a stop request
/// part way through its tile. Returns false when stopped (some tiles may then be undone). An
/// exception thrown by fn stops every thread and is rethrown here once all have joined.
template <class F>
bool parallel_tiles(int threads, int tiles, const std::atomic<bool>* stop, RayCounters& total,
                    F&& fn) {
    std::atomic<int> next{0};
    std::atomic<bool> stopped{false};
    std::mutex mutex;
    std::exception_ptr error;
    auto worker = [&]() {
        RayCounters rays;
        try {
            while (!stopped.load(std::memory_order_relaxed)) {
                if (stop && stop->load(std::memory_order_relaxed)) {
                    stopped = true;
                    break;
                }
                const int tile = next.fetch_add(1);
                if (tile >= tiles) break;
                if (!fn(tile, rays)) stopped = true;
            }
        } catch (...) {
            stopped = true;
            std::lock_guard lock(mutex);
            if (!error) error = std::current_exception();
        }
        std::lock_guard lock(mutex);
        total += rays;
    };
    std::vector<std::thread> pool;
    for (int i = 1; i < std::min(threads, tiles); ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
    return !stopped;
}

}  // namespace rt
