#pragma once
// How a caller steers a long computation from outside: cancel it (a deadline, a deleted job),
// hear how far it got, and lend it threads. All are optional; core never blocks on them.

#include <algorithm>
#include <functional>

#include "core/executor.h"

namespace rollgap::core {

struct Control {
    std::function<bool()> cancelled;       // polled between units of work
    std::function<void(double)> progress;  // fraction done, 0..1
    // The process's compute pool (core/parallel_for.h); none: everything runs on the caller's
    // thread. It must outlive the computation.
    Executor* executor = nullptr;
    // The most threads one computation may spread over (the scan speeds of a critical-speed
    // search, the points of a sweep), the caller's included; 0: the executor's. Results do not
    // depend on it.
    int threads = 0;

    bool should_stop() const { return cancelled && cancelled(); }
    int thread_budget() const {
        if (executor == nullptr) return 1;
        const int pool = std::max(1, executor->concurrency());
        return threads > 0 ? std::min(threads, pool) : pool;
    }
    void report(double fraction) const {
        if (progress) progress(fraction);
    }
    // For a part of this computation: the same cancellation and executor, no progress (the
    // part's caller reports), a budget of `budget` threads.
    Control nested(int budget) const {
        Control part;
        part.cancelled = cancelled;
        part.executor = executor;
        part.threads = std::max(1, budget);
        return part;
    }
};

}  // namespace rollgap::core
