#pragma once
// The one compute pool of the process: N threads behind two bounded queues, separate from the
// HTTP I/O threads, which also run the inner parallelism of the analyses.
//
// Why one pool, sized by the CPU quota (service/cpu_quota.h): threads beyond the CPUs the
// process may use only add switching and memory, and hardware_concurrency() counts the node's
// cores, not the container's limit (a pod limited to 2 CPUs on a 64-core node would start 64
// threads per analysis). So the workers that take requests and jobs are also the threads the
// analyses spread their scan speeds, sweep points and Jacobian columns over: the pool is the
// core::Executor that core receives through its Control, and the process never runs more compute
// threads than its workers (the caller of a parallel loop is itself a worker and helps, see
// core/parallel_for.h, so nested loops cannot deadlock however busy the pool is).
//
// - The interactive lane holds synchronous requests: at most `interactive_capacity` wait; a
//   full lane refuses at once (the server answers 503 + Retry-After).
// - The batch lane holds asynchronous jobs: at most `batch_capacity` wait, and at most
//   `batch_concurrency` of them run at once, so jobs cannot take every worker away from the
//   synchronous requests (with one worker they can: there is only one).
// - The inner lane holds helper tasks posted by running analyses (post()): unbounded (a loop
//   posts fewer helpers than the pool has workers), never refused, and taken before anything
//   else, because it finishes work already admitted instead of admitting more.
// A free worker takes the oldest inner task first, then the oldest interactive task, then the
// oldest batch task. Tasks must not wait for tasks queued on the pool (parallel_for waits only
// for helpers already running); an exception escaping a task is caught and logged.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "core/executor.h"

namespace rollgap::service {

enum class Lane { interactive, batch };

struct WorkerPoolStats {
    std::size_t workers = 0;
    std::size_t busy = 0;  // workers running a task (a helper of an analysis included)
    std::size_t inner_queued = 0;
    std::size_t interactive_queued = 0;
    std::size_t interactive_capacity = 0;
    std::size_t batch_queued = 0;
    std::size_t batch_capacity = 0;
    std::size_t batch_running = 0;
    std::size_t batch_concurrency = 0;
};

class WorkerPool final : public core::Executor {
public:
    using Task = std::function<void()>;

    WorkerPool(std::size_t workers, std::size_t interactive_capacity, std::size_t batch_capacity,
               std::size_t batch_concurrency);
    ~WorkerPool() override;  // shutdown()
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    // Queues `task`; false (and `task` dropped) if the lane is full or the pool shuts down.
    // `key` names the task for withdraw().
    bool try_submit(Lane lane, Task task, const void* key = nullptr);

    // Removes the queued task submitted with `key` (not null) without running it; false if it
    // is not queued (running, done, or never submitted).
    bool withdraw(const void* key);

    // core::Executor: queues a helper of a running analysis on the inner lane. Dropped once the
    // pool has stopped and nothing runs on it any more (a helper is optional).
    void post(std::function<void()> task) override;
    int concurrency() const override { return static_cast<int>(workers_); }

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
    std::deque<Task> inner_;
    std::deque<Queued> interactive_;
    std::deque<Queued> batch_;
    const std::size_t workers_;
    std::size_t interactive_capacity_;
    std::size_t batch_capacity_;
    std::size_t batch_concurrency_;
    std::size_t busy_ = 0;
    std::size_t batch_running_ = 0;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

// The pool of a process that computes on its own thread (`rollgap run`, the benches, the
// tools): `workers` threads (0: the CPUs the process may use, service/cpu_quota.h) that only
// help the caller's parallel loops; no request lanes.
std::unique_ptr<WorkerPool> local_pool(std::size_t workers = 0);

}  // namespace rollgap::service
