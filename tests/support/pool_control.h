#pragma once
// A Control whose parallel loops run on a pool of their own with `workers` threads (the caller
// helps, core/parallel_for.h): for tests that compare results over thread counts.

#include <cstddef>
#include <memory>

#include "core/control.h"
#include "service/worker_pool.h"

namespace rollgap::test {

struct PoolControl {
    explicit PoolControl(std::size_t workers) : pool(service::local_pool(workers)) {
        control.executor = pool.get();
        control.threads = static_cast<int>(workers);
    }
    std::unique_ptr<service::WorkerPool> pool;
    core::Control control;
};

}  // namespace rollgap::test
