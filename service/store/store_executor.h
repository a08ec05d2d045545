#pragma once
// Internal to the job store: the bounded store executor. Every transaction of a store runs on
// one of its N threads (N = --store-connections; the PostgreSQL backend then holds at most N
// connections); the caller waits at most the store deadline and then gives the call up, so a
// frozen database or disk never holds an HTTP thread longer than that. libpqxx 6.4 has no
// per-call timeout and statement_timeout does nothing in a partition, hence threads of its own.

#include <chrono>
#include <cstddef>
#include <memory>
#include <string_view>
#include <thread>
#include <vector>

#include "service/store/sql_backend.h"

namespace rollgap::service::store::detail {

struct ExecutorOptions {
    std::size_t threads = 4;
    std::chrono::milliseconds deadline{2000};
    std::size_t queue = 256;  // calls waiting for a thread; beyond: unavailable at once
};

class StoreExecutor final : public Backend {
public:
    StoreExecutor(std::unique_ptr<Backend> inner, ExecutorOptions options);
    ~StoreExecutor() override;
    StoreExecutor(const StoreExecutor&) = delete;
    StoreExecutor& operator=(const StoreExecutor&) = delete;

    Dialect dialect() const override;
    // Runs the inner backend's transact on an executor thread; `unavailable` with
    // deadline_detail when it did not finish in time (a write's outcome is then unknown: it may
    // still commit), with stalled_detail or queue_full_detail at once when it cannot start.
    StoreStatus transact(bool write, const std::function<void(Session&)>& body,
                         const std::function<bool(Session&)>& verify, std::string& detail) override;

    // The deadline of later calls (the start-up migration runs with a longer one).
    void set_deadline(std::chrono::milliseconds deadline);

    struct Shared;

private:
    std::shared_ptr<Shared> shared_;
    std::vector<std::thread> threads_;
};

}  // namespace rollgap::service::store::detail
