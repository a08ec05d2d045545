#include "service/http/job_runner.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include <spdlog/spdlog.h>

#include "service/chunked.h"
#include "service/http/compute.h"

namespace rollgap::service::http {

using nlohmann::json;

namespace {

enum Phase : int { waiting = 0, running = 1, given_back = 2 };

// Progress is written to the store at most this often: each write is a transaction.
constexpr std::chrono::milliseconds progress_interval{250};

}  // namespace

struct JobRunner::Item {
    std::shared_ptr<store::JobStore> store;
    store::WorkItem work;
    std::atomic<int> phase{waiting};
    std::atomic<bool> cancel{false};  // DELETE reached us (renewal or this replica's DELETE)
    std::atomic<bool> lost{false};    // the lease is gone: the result would be discarded
};

void JobRunner::start() {
    claimer_ = std::thread([this] { claim_loop(); });
    renewer_ = std::thread([this] { renew_loop(); });
}

void JobRunner::wake() {
    {
        std::lock_guard lock(mutex_);
        woken_ = true;
    }
    claim_wake_.notify_one();
}

void JobRunner::cancel_local(const std::string& job_id) {
    std::lock_guard lock(mutex_);
    for (const auto& item : items_) {
        if (item->work.lease.job_id == job_id) item->cancel = true;
    }
}

void JobRunner::stop_claiming() {
    std::vector<std::shared_ptr<Item>> items;
    {
        std::lock_guard lock(mutex_);
        claiming_ = false;
        items = items_;
    }
    for (const auto& item : items) give_back(item);
}

std::size_t JobRunner::held() const {
    std::lock_guard lock(mutex_);
    return items_.size();
}

void JobRunner::stop() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
        stopping_ = true;
        claiming_ = false;
    }
    claim_wake_.notify_all();
    renew_wake_.notify_all();
    if (claimer_.joinable()) claimer_.join();
    if (renewer_.joinable()) renewer_.join();
}

void JobRunner::claim_loop() {
    auto next_upkeep = SteadyClock::now();
    std::unique_lock lock(mutex_);
    while (!stopping_) {
        const bool room = claiming_ && items_.size() < state_.pool.stats().batch_concurrency;
        lock.unlock();
        const bool claimed = room && claim_one();
        if (SteadyClock::now() >= next_upkeep) {
            upkeep();
            next_upkeep = SteadyClock::now() + upkeep_interval;
        }
        lock.lock();
        if (claimed) continue;  // there may be more
        claim_wake_.wait_for(lock, poll_interval, [this] { return stopping_ || woken_; });
        woken_ = false;
    }
}

bool JobRunner::claim_one() {
    auto store = state_.store.get();
    if (!store) return false;
    auto claimed = store->claim(state_.config.instance, state_.config.lease);
    state_.store.report(claimed.status);
    if (!claimed.ok() || !claimed.value->has_value()) return false;
    auto item = std::make_shared<Item>();
    item->store = std::move(store);
    item->work = std::move(**claimed.value);
    {
        std::lock_guard lock(mutex_);
        items_.push_back(item);
    }
    if (!state_.pool.try_submit(
            Lane::batch, [this, item] { run(item); }, item.get())) {
        give_back(item);
        return false;
    }
    bool still_claiming = false;
    {
        std::lock_guard lock(mutex_);
        still_claiming = claiming_;
    }
    // stop_claiming may have run between the claim and the submission (give_back is once).
    if (!still_claiming) give_back(item);
    return still_claiming;
}

void JobRunner::give_back(const std::shared_ptr<Item>& item) {
    int expected = waiting;
    if (!item->phase.compare_exchange_strong(expected, given_back)) return;  // it runs
    state_.pool.withdraw(item.get());
    state_.store.report(item->store->release(item->work.lease));
    finish(item, "released");
}

void JobRunner::finish(const std::shared_ptr<Item>& item, const char* outcome) {
    state_.metrics.count_work_item(outcome);
    {
        std::lock_guard lock(mutex_);
        std::erase(items_, item);
        woken_ = true;  // room for another item
    }
    claim_wake_.notify_one();
}

void JobRunner::run(const std::shared_ptr<Item>& item) {
    int expected = waiting;
    if (!item->phase.compare_exchange_strong(expected, running)) return;  // given back
    const store::WorkItem& work = item->work;
    store::JobStore& store = *item->store;

    const auto late = [&work] { return store::system_millis() >= work.deadline_ms; };
    // Why the item stops; the metrics of the computation leave a lost lease out.
    const auto stopped = [this, &item, late](bool with_lease) {
        return stop_reason({.lease_lost = with_lease && item->lost.load(),
                            .cancelled = item->cancel.load(),
                            .shutdown = state_.hard_cancel.load(),
                            .late = late()});
    };
    core::Control control =
        control_for(state_, [stopped] { return stopped(true) != StopReason::none; });
    // A chunk of a sweep's or map's points: the job's progress is its share of finished
    // points, which the store counts itself.
    const bool chunk = work.end > work.begin;
    auto last_progress = SteadyClock::now() - progress_interval;
    if (!chunk)
        control.progress = [&](double fraction) {
            const auto now = SteadyClock::now();
            if (!std::isfinite(fraction) || now - last_progress < progress_interval) return;
            last_progress = now;
            if (store.progress(work.lease, std::clamp(fraction, 0.0, 1.0)) ==
                store::StoreStatus::conflict)
                item->lost = true;
        };

    const json request = json::parse(work.request, nullptr, false);
    const auto for_metrics = [stopped] { return stopped(false); };
    Outcome outcome = chunk ? compute(state_, request, control, for_metrics,
                                      [&work](const json& whole, const core::Control& stop) {
                                          return evaluate_points(whole, work.begin, work.end, stop);
                                      })
                            : compute(state_, request, control, for_metrics);

    const StopReason reason = stopped(true);
    if (reason == StopReason::lease_lost) {
        finish(item, "lost");
        return;
    }
    if (reason == StopReason::shutdown) {
        // The drain timeout passed: the work goes back to the store for another replica.
        state_.store.report(store.release(work.lease));
        finish(item, "released");
        return;
    }
    store::FinalState stored = store::FinalState::succeeded;
    std::string text;
    const char* label = "succeeded";
    if (reason == StopReason::cancelled) {
        stored = store::FinalState::cancelled;
        label = "cancelled";
    } else if (reason == StopReason::deadline) {
        stored = store::FinalState::failed;
        text = problem_outcome(deadline_problem(state_.config.job_deadline)).body.dump();
        label = "failed";
    } else {
        text = outcome.body.dump();
        if (!outcome.ok()) {
            stored = store::FinalState::failed;
            label = "failed";
        }
    }
    auto completed = store.complete(work.lease, stored, text);
    // A computed result is not thrown away because the store did not answer once: the commit
    // is tried again (the store replaces a broken connection; a completion that did commit
    // unheard is recognised by its lease token) until it is stored, the lease is lost, the
    // job's deadline passes or the drain timeout cancels everything.
    for (auto pause = std::chrono::milliseconds(100);
         completed.status == store::StoreStatus::unavailable && !item->lost &&
         !state_.hard_cancel && !late();
         pause = std::min(2 * pause, std::chrono::milliseconds(2000))) {
        state_.store.report(completed.status);
        std::this_thread::sleep_for(pause);
        completed = store.complete(work.lease, stored, text);
    }
    state_.store.report_write(completed.status);
    if (completed.status == store::StoreStatus::conflict) {
        spdlog::info("job {} item {}: lease lost while computing; result discarded",
                     work.lease.job_id, work.lease.chunk);
        label = "lost";
    } else if (!completed.ok()) {
        spdlog::warn(
            "job {} item {}: result not stored ({}): {}; the lease runs out and the item "
            "is computed again",
            work.lease.job_id, work.lease.chunk, store::status_name(completed.status),
            completed.detail);
        label = "unstored";
    }
    finish(item, label);
}

void JobRunner::renew_loop() {
    const auto every = std::max(state_.config.lease / 3, std::chrono::milliseconds(10));
    std::unique_lock lock(mutex_);
    while (!stopping_) {
        renew_wake_.wait_for(lock, every, [this] { return stopping_; });
        if (stopping_) break;
        const auto items = items_;
        lock.unlock();
        for (const auto& item : items) {
            if (item->phase.load() == given_back) continue;
            const auto renewed = item->store->renew(item->work.lease, state_.config.lease);
            state_.store.report(renewed.status);
            if (renewed.status == store::StoreStatus::conflict ||
                renewed.status == store::StoreStatus::not_found) {
                item->lost = true;
            } else if (renewed.ok() && renewed.value->cancel_requested) {
                item->cancel = true;
            }
        }
        lock.lock();
    }
}

void JobRunner::upkeep() {
    auto store = state_.store.get();
    if (!store) return;
    const auto expired = store->expire_leases();
    state_.store.report(expired.status);
    if (expired.ok() && *expired.value > 0)
        spdlog::info("{} work item(s) whose lease ran out queued again", *expired.value);
    state_.store.report(store->purge().status);
}

}  // namespace rollgap::service::http
