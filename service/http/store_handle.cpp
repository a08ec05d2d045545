#include "service/http/store_handle.h"

#include <spdlog/spdlog.h>

#include "service/config.h"

namespace rollgap::service::http {
namespace {

// Why the store is down, in words for /readyz (which anyone on the admin port may read): the
// database's own text, which may name hosts and users, stays in the log.
std::string reason_for(std::string_view detail) {
    if (detail == store::moved_detail)
        return "the SQLite file was deleted or moved while open; restore it or restart";
    if (detail == store::deadline_detail || detail == store::stalled_detail ||
        detail == store::queue_full_detail)
        return "the job store does not answer within the store deadline";
    return "the job store refuses writes or cannot be reached (see the log)";
}

}  // namespace

StoreHandle::StoreHandle(std::string setting, store::StoreLimits limits, std::string instance)
    : setting_(std::move(setting)), limits_(limits), instance_(std::move(instance)) {}

StoreHandle::~StoreHandle() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    changed_.notify_all();
    if (prober_.joinable()) prober_.join();
}

void StoreHandle::start() {
    std::call_once(started_, [this] { prober_ = std::thread([this] { probe_loop(); }); });
}

std::shared_ptr<store::JobStore> StoreHandle::get() {
    start();
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, limits_.deadline, [this] { return attempted_ || stopping_; });
    return store_;
}

StoreHandle::Snapshot StoreHandle::snapshot() {
    start();
    std::lock_guard lock(mutex_);
    return {state_ == State::up, state_ == State::up ? std::string() : reason_, counts_};
}

void StoreHandle::report(store::StoreStatus status) {
    if (status != store::StoreStatus::unavailable) return;
    std::lock_guard lock(mutex_);
    if (state_ != State::down)
        mark_down("a job store operation failed (see the log)", "an operation failed");
}

void StoreHandle::report_write(store::StoreStatus status) {
    if (status != store::StoreStatus::ok) return report(status);
    std::lock_guard lock(mutex_);
    mark_up();
}

void StoreHandle::mark_down(std::string reason, std::string_view detail) {
    reason_ = std::move(reason);
    if (state_ == State::down) return;
    state_ = State::down;
    spdlog::warn(
        "job store unavailable ({}); jobs and stored scenarios answer 503 until it answers again",
        detail);
}

void StoreHandle::mark_up() {
    if (state_ == State::down) spdlog::info("job store available again");
    state_ = State::up;
}

void StoreHandle::probe_loop() {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
        lock.unlock();
        probe_once();
        lock.lock();
        changed_.wait_for(lock, probe_interval, [this] { return stopping_; });
    }
}

void StoreHandle::probe_once() {
    std::shared_ptr<store::JobStore> store;
    {
        std::lock_guard lock(mutex_);
        store = store_;
    }
    if (!store) {
        auto opened = store::open_store(setting_, limits_);
        std::lock_guard lock(mutex_);
        attempted_ = true;
        changed_.notify_all();
        if (!opened.ok()) {
            // The detail never holds the DSN (open_store keeps it out).
            if (!open_failure_logged_) {
                open_failure_logged_ = true;
                spdlog::warn(
                    "job store {} unavailable ({}): {}; jobs and stored scenarios answer 503",
                    redacted_store(setting_), store::status_name(opened.status), opened.detail);
            }
            reason_ = "the job store cannot be opened (see the log)";
            state_ = State::down;  // logged just above, once
            return;
        }
        store_ = *opened.value;
        store = store_;
        open_failure_logged_ = false;
        spdlog::info("job store {} open", redacted_store(setting_));
    }
    auto probed = store->probe(instance_);
    std::lock_guard lock(mutex_);
    if (probed.ok()) {
        counts_ = *probed.value;
        mark_up();
    } else {
        mark_down(reason_for(probed.detail), probed.detail);
    }
}

}  // namespace rollgap::service::http
