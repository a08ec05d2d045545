#pragma once
// The job store as the HTTP layer sees it. A background probe opens it (and opens it again
// while it cannot be opened), and checks it every `probe_interval` with a write (a heartbeat
// row) and the job counts: its last answer is what /readyz's body and /metrics report, so
// health and metrics never wait on the store. Synchronous analyses do not touch the store; job
// and stored-scenario requests get 503 + Retry-After while it is unavailable
// (docs/job-store.md).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "service/store/job_store.h"

namespace rollgap::service::http {

class StoreHandle {
public:
    // `instance` names this replica's heartbeat row.
    StoreHandle(std::string setting, store::StoreLimits limits, std::string instance);
    ~StoreHandle();
    StoreHandle(const StoreHandle&) = delete;
    StoreHandle& operator=(const StoreHandle&) = delete;

    // The store, or nullptr while it cannot be opened. Never waits on the database, except
    // the very first call, which waits (at most the store deadline) for the first opening.
    std::shared_ptr<store::JobStore> get();

    // What an operation on the store answered: `unavailable` marks the store down at once
    // (logged once per outage). Only a write marks it up again (the probe's, or see
    // report_write): a read that succeeds on a store that refuses writes must not flip the
    // state (and the log) back and forth.
    void report(store::StoreStatus status);
    // The same after an operation that writes whenever it succeeds (a job created, a result
    // stored): success also marks the store up, as the probe's write does.
    void report_write(store::StoreStatus status);

    // The probe's last view.
    struct Snapshot {
        bool up = false;
        std::string reason;                      // why it is down, for /readyz (no secret in it)
        std::optional<store::JobCounts> counts;  // the last counts read, also while down
    };
    Snapshot snapshot();
    bool up() { return snapshot().up; }

    static constexpr std::chrono::seconds probe_interval{1};

private:
    void start();
    void probe_loop();
    void probe_once();
    // Under mutex_.
    void mark_down(std::string reason, std::string_view detail);
    void mark_up();

    std::string setting_;
    store::StoreLimits limits_;
    std::string instance_;

    std::once_flag started_;
    std::thread prober_;
    std::mutex mutex_;
    std::condition_variable changed_;
    bool stopping_ = false;
    bool attempted_ = false;  // the first opening was tried
    std::shared_ptr<store::JobStore> store_;
    enum class State { unknown, up, down };
    State state_ = State::unknown;      // transitions are logged, nothing else
    bool open_failure_logged_ = false;  // "cannot be opened": once per outage
    std::string reason_ = "the job store has not been opened yet";
    std::optional<store::JobCounts> counts_;
};

}  // namespace rollgap::service::http
