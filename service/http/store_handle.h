#pragma once
// The job store as the HTTP layer sees it: opened lazily and re-opened after failures, so a
// database that is down at start-up or goes away later never stops the service. Synchronous
// analyses do not touch the store; job and stored-scenario requests get 503 + Retry-After
// while it is unavailable (docs/job-store.md).

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>

#include "service/store/job_store.h"

namespace rollgap::service::http {

class StoreHandle {
public:
    StoreHandle(std::string setting, store::StoreLimits limits);

    // The store, or nullptr while it cannot be opened (an attempt at most once per
    // `retry_interval`, so a down database costs a request no connect timeout each).
    std::shared_ptr<store::JobStore> get();

    // What an operation on the store answered: `unavailable` marks the store down (logged
    // once per outage), anything else marks it up (logged when it comes back).
    void report(store::StoreStatus status);

    bool up() const { return up_.load(); }

    static constexpr std::chrono::seconds retry_interval{1};

private:
    std::string setting_;
    store::StoreLimits limits_;
    std::mutex mutex_;
    std::shared_ptr<store::JobStore> store_;
    std::chrono::steady_clock::time_point next_attempt_{};
    std::atomic<bool> up_{false};
    std::atomic<bool> down_logged_{false};  // one warning per outage while it cannot be opened
};

}  // namespace rollgap::service::http
