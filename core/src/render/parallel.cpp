#include "parallel.h"

#include <algorithm>

namespace rt {

HelperPool& HelperPool::instance() {
    static HelperPool* pool = new HelperPool;  // never destroyed: its threads never end
    return *pool;
}

int HelperPool::threads() const {
    std::lock_guard lock(m_mutex);
    return m_threads;
}

void HelperPool::run(int helpers, const std::function<void()>& work) {
    Job job{&work, helpers};
    {
        std::lock_guard lock(m_mutex);
        m_jobs.push_back(&job);
        for (; m_threads < helpers; ++m_threads) std::thread([this] { loop(); }).detach();
    }
    m_work.notify_all();
    work();
    std::unique_lock lock(m_mutex);
    m_jobs.erase(std::find(m_jobs.begin(), m_jobs.end(), &job));  // no helper takes it now
    m_done.wait(lock, [&] { return job.active == 0; });
}

void HelperPool::loop() {
    std::unique_lock lock(m_mutex);
    for (;;) {
        Job* job = nullptr;
        m_work.wait(lock, [&] {
            for (Job* j : m_jobs)
                if (j->slots > 0) return (job = j) != nullptr;
            return false;
        });
        --job->slots;
        ++job->active;
        lock.unlock();
        (*job->work)();
        lock.lock();
        if (--job->active == 0) m_done.notify_all();
    }
}

}  // namespace rt
