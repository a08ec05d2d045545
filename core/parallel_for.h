#pragma once
// Runs body(i) for i in [0, n) on the caller's thread and on up to budget - 1 helper tasks
// posted to an executor. Each index is independent and writes only its own output, so results
// do not depend on the budget or on which thread ran which index.
//
// The caller helps: indices come from one shared counter, taken by the caller and by the
// helpers that happen to start. A helper that starts after every index is taken returns at
// once, and the caller waits only for helpers that are running an index. So a loop never waits
// for a queued task, and parallel loops nested inside tasks of the same pool (a sweep of
// critical-speed searches, a fit whose model runs a search) cannot deadlock, even when every
// worker is busy: in the worst case the caller runs every index itself.
//
// Without an executor (or with a budget of 1) the loop runs serially on the caller's thread.
// An exception thrown by body stops handing out indices; the first one is rethrown to the
// caller once no helper runs an index any more.

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>

#include "core/control.h"
#include "core/executor.h"

namespace rollgap::core {

namespace detail {

// Shared by the caller and its helpers; a helper holds it by shared_ptr because it may start
// (and return at once) after the caller has returned.
struct ParallelLoop {
    ParallelLoop(int count, const std::function<void(int)>* loop_body)
        : n(count), body(loop_body) {}

    const int n;
    // Dereferenced only while an index below n is held: the caller is still waiting then.
    const std::function<void(int)>* const body;
    std::atomic<int> next{0};
    std::mutex mutex;
    std::condition_variable helpers_done;
    int running = 0;  // helpers inside run_indices(), under mutex
    std::exception_ptr error;

    void run_indices() {
        for (int i = next++; i < n; i = next++) {
            try {
                (*body)(i);
            } catch (...) {
                std::lock_guard lock(mutex);
                if (!error) error = std::current_exception();
                next.store(n);  // no further index for anyone
            }
        }
    }

    void help() {
        if (next.load() >= n) return;  // nothing left: the caller does not wait for this task
        {
            std::lock_guard lock(mutex);
            ++running;
        }
        run_indices();
        std::lock_guard lock(mutex);
        if (--running == 0) helpers_done.notify_all();
    }
};

}  // namespace detail

// The loop over `budget` threads of `executor` at most (the caller included).
template <class Body>
void parallel_for(int n, int budget, Executor* executor, Body&& body) {
    if (n <= 0) return;
    const int helpers = executor == nullptr ? 0 : std::clamp(budget, 1, n) - 1;
    if (helpers == 0) {
        for (int i = 0; i < n; ++i) body(i);
        return;
    }
    const std::function<void(int)> loop_body = [&body](int i) { body(i); };
    const auto loop = std::make_shared<detail::ParallelLoop>(n, &loop_body);
    for (int h = 0; h < helpers; ++h) executor->post([loop] { loop->help(); });
    loop->run_indices();
    std::unique_lock lock(loop->mutex);
    // Every index is taken; a helper that takes none from now on never touches loop_body.
    loop->helpers_done.wait(lock, [&] { return loop->running == 0; });
    if (loop->error) std::rethrow_exception(loop->error);
}

// The loop over the executor and thread budget of `control`.
template <class Body>
void parallel_for(int n, const Control& control, Body&& body) {
    parallel_for(n, control.thread_budget(), control.executor, std::forward<Body>(body));
}

}  // namespace rollgap::core
