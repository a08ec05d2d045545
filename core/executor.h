#pragma once
// Where core runs the inner parallelism of a computation (the scan speeds of a critical-speed
// search, the points of a sweep, the Jacobian columns of a fit). Core starts no threads of its
// own: the process owns one pool sized by its CPU quota and lends it through Control, so an
// analysis never adds threads to those the process already has.

#include <functional>

namespace rollgap::core {

class Executor {
public:
    virtual ~Executor() = default;
    // Runs `task` on one of the executor's threads, some time later. It may also drop the task
    // (the executor is shutting down): parallel_for's helpers are optional, the caller runs
    // whatever no helper took.
    virtual void post(std::function<void()> task) = 0;
    // The executor's threads: the most a computation can use at once.
    virtual int concurrency() const = 0;
};

}  // namespace rollgap::core
