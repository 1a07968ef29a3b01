#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra::session {

// A few threads for work that must not run on a network thread (loading a volume, scanning the
// data folder). Tasks run in the order posted, each on whichever thread is free.
class WorkerPool {
public:
    explicit WorkerPool(int threads);

    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    // Finishes the task in hand on each thread, drops the rest, and joins the threads.
    ~WorkerPool();

    void post(std::function<void()> task);

private:
    void run();

    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<std::function<void()>> tasks_;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace penumbra::session
