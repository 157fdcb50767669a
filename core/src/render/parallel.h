// Tiled parallel work for the render loop: threads claim tiles one at a time until none is left
// or a stop is requested.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "rt/render/shading.h"

namespace rt {

/// Helper threads that outlive the calls, for the web page's threads build: there a thread is
/// started by the browser's main thread, which the trace's controller thread cannot count on
/// (the interface thread waits for it in Tracer::stop()), so parallel_tiles() must not wait for
/// threads to start. run() hands `work` to up to `helpers` helpers (started when first needed,
/// then reused) and runs it on the calling thread too; it returns once every helper that took
/// the work has finished it. A helper that had not taken it by then never will, so the caller
/// never waits for a thread to start.
class HelperPool {
public:
    static HelperPool& instance();
    void run(int helpers, const std::function<void()>& work);
    int threads() const;  // the helpers started so far

private:
    struct Job {
        const std::function<void()>* work;
        int slots;       // helpers that may still take it
        int active = 0;  // helpers running it
    };
    void loop();

    mutable std::mutex m_mutex;
    std::condition_variable m_work, m_done;
    std::vector<Job*> m_jobs;  // open jobs
    int m_threads = 0;
};

#ifdef __EMSCRIPTEN__
inline constexpr bool kPersistentHelpers = true;
#else
inline constexpr bool kPersistentHelpers = false;  // a thread per helper and call (below)
#endif

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
    const int helpers = std::min(threads, tiles) - 1;
    if (kPersistentHelpers && helpers > 0) {
        HelperPool::instance().run(helpers, worker);
    } else {
        std::vector<std::thread> pool;
        for (int i = 0; i < helpers; ++i) pool.emplace_back(worker);
        worker();
        for (std::thread& t : pool) t.join();
    }
    if (error) std::rethrow_exception(error);
    return !stopped;
}

}  // namespace rt
