#pragma once
// The compute workers of the HTTP service: N threads behind two bounded queues, separate from
// the HTTP I/O threads.
//
// - The interactive lane holds synchronous requests: at most `interactive_capacity` wait; a
//   full lane refuses at once (the server answers 503 + Retry-After).
// - The batch lane holds asynchronous jobs: at most `batch_capacity` wait, and at most
//   `batch_concurrency` of them run at once, so jobs cannot take every worker away from the
//   synchronous requests (with one worker they can: there is only one).
// A free worker takes the oldest interactive task first, then the oldest batch task.
// Tasks must not block on the pool itself; an exception escaping a task is caught and logged.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace rollgap::service {

enum class Lane { interactive, batch };

struct WorkerPoolStats {
    std::size_t workers = 0;
    std::size_t busy = 0;  // workers running a task
    std::size_t interactive_queued = 0;
    std::size_t interactive_capacity = 0;
    std::size_t batch_queued = 0;
    std::size_t batch_capacity = 0;
    std::size_t batch_running = 0;
    std::size_t batch_concurrency = 0;
};

class WorkerPool {
public:
    using Task = std::function<void()>;

    WorkerPool(std::size_t workers, std::size_t interactive_capacity, std::size_t batch_capacity,
               std::size_t batch_concurrency);
    ~WorkerPool();  // shutdown()
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    // Queues `task`; false (and `task` dropped) if the lane is full or the pool shuts down.
    // `key` names the task for withdraw().
    bool try_submit(Lane lane, Task task, const void* key = nullptr);

    // Removes the queued task submitted with `key` (not null) without running it; false if it
    // is not queued (running, done, or never submitted).
    bool withdraw(const void* key);

    // Stops accepting tasks, runs the ones already queued, joins the workers. Idempotent.
    void shutdown();

    WorkerPoolStats stats() const;
    bool idle() const;  // nothing queued, nothing running

private:
    void work();
    bool can_take() const;  // under mutex_

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    struct Queued {
        Task task;
        const void* key;
    };
    std::deque<Queued> interactive_;
    std::deque<Queued> batch_;
    std::size_t interactive_capacity_;
    std::size_t batch_capacity_;
    std::size_t batch_concurrency_;
    std::size_t busy_ = 0;
    std::size_t batch_running_ = 0;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace rollgap::service
