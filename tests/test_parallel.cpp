// The render loop's tiles over threads (src/render/parallel.h): every tile once, and the
// helper pool of the web page's threads build, which never waits for a helper to start. The
// compile's ranges over threads (rt/util/parallel_ranges.h).
#include <gtest/gtest.h>

#if defined(__linux__)
#include <sched.h>
#endif

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "render/parallel.h"
#include "rt/util/parallel_ranges.h"
#include "rt/util/threads.h"

namespace rt {
namespace {

TEST(Parallel, EveryTileOnceForAnyThreadCount) {
    for (int threads : {1, 2, 5}) {
        std::vector<std::atomic<int>> done(97);
        RayCounters total;
        const bool finished = parallel_tiles(threads, 97, nullptr, total, [&](int t, RayCounters&) {
            ++done[static_cast<size_t>(t)];
            return true;
        });
        EXPECT_TRUE(finished);
        for (const auto& d : done) EXPECT_EQ(d.load(), 1) << threads << " threads";
    }
}

// run() returns only once every helper that took the work has finished it, and it reuses its
// helpers: a hundred calls start no more threads than the largest call asked for.
TEST(Parallel, TheHelperPoolFinishesWhatItTookAndReusesItsThreads) {
    HelperPool& pool = HelperPool::instance();
    for (int call = 0; call < 100; ++call) {
        std::atomic<int> entered{0}, left{0};
        pool.run(3, [&] {
            ++entered;
            std::this_thread::sleep_for(std::chrono::microseconds(200));
            ++left;
        });
        EXPECT_GE(entered.load(), 1);  // the caller at least
        EXPECT_LE(entered.load(), 4);
        EXPECT_EQ(left.load(), entered.load()) << "run() returned while a helper worked";
    }
    EXPECT_EQ(pool.threads(), 3);
}

// The tiles of one call are shared by the caller and the helpers that came: each tile once,
// with calls from two threads at once.
TEST(Parallel, TheHelperPoolSharesTilesBetweenConcurrentCalls) {
    auto one_call = [] {
        std::atomic<int> next{0};
        std::vector<std::atomic<int>> done(200);
        HelperPool::instance().run(2, [&] {
            for (int t; (t = next.fetch_add(1)) < 200;) ++done[static_cast<size_t>(t)];
        });
        int once = 0;
        for (const auto& d : done) once += d.load() == 1;
        return once;
    };
    int a = 0, b = 0;
    std::thread other([&] { a = one_call(); });
    b = one_call();
    other.join();
    EXPECT_EQ(a, 200);
    EXPECT_EQ(b, 200);
}

// Consecutive ranges that cover [0, n) once, none shorter than the grain, no more than the
// threads asked for.
TEST(Parallel, RangesCoverEveryIndexOnce) {
    for (const size_t n : {0, 1, 99, 100, 1001}) {
        for (const unsigned threads : {1u, 2u, 7u}) {
            std::mutex mutex;
            std::vector<std::pair<size_t, size_t>> ranges;
            std::vector<std::atomic<int>> done(n);
            parallel_ranges(
                n, 100,
                [&](size_t begin, size_t end) {
                    for (size_t i = begin; i < end; ++i) ++done[i];
                    const std::lock_guard lock(mutex);
                    ranges.emplace_back(begin, end);
                },
                threads);
            for (const auto& d : done) EXPECT_EQ(d.load(), 1) << n << " items, " << threads;
            EXPECT_LE(ranges.size(), std::max<size_t>(1, std::min<size_t>(threads, n / 100)));
            if (ranges.size() > 1) {
                for (const auto& [begin, end] : ranges) EXPECT_GE(end - begin, 100u);
            }
        }
    }
}

#if defined(__linux__)
// A thread bound to one CPU may run one thread at a time: hardware_threads() counts the CPUs it
// is bound to (as a cluster's scheduler or mpirun binds a rank), not the machine's.
TEST(Parallel, HardwareThreadsAreTheCpusThisThreadIsBoundTo) {
    cpu_set_t all;
    ASSERT_EQ(sched_getaffinity(0, sizeof all, &all), 0);
    EXPECT_EQ(hardware_threads(), static_cast<unsigned>(CPU_COUNT(&all)));
    unsigned bound = 0;
    std::thread t([&] {  // its own affinity, so the test's other threads keep theirs
        cpu_set_t one;
        CPU_ZERO(&one);
        for (int c = 0; c < CPU_SETSIZE; ++c)
            if (CPU_ISSET(c, &all)) {
                CPU_SET(c, &one);
                break;
            }
        if (sched_setaffinity(0, sizeof one, &one) == 0) bound = hardware_threads();
    });
    t.join();
    EXPECT_EQ(bound, 1u);
}
#endif

// When several ranges throw, the error is the one of the lowest range: the first a loop in order
// would meet.
TEST(Parallel, RangesRethrowTheFirstErrorInOrder) {
    for (int run = 0; run < 20; ++run) {
        try {
            parallel_ranges(
                4000, 1000,
                [](size_t begin, size_t) {
                    if (begin > 0) throw std::runtime_error("range at " + std::to_string(begin));
                },
                4);
            FAIL() << "nothing thrown";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), "range at 1000");
        }
    }
}

}  // namespace
}  // namespace rt
