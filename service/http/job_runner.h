#pragma once
// The workers' side of the durable jobs (docs/job-store.md, "The HTTP side"): every replica
// claims work items from the store while its batch lane has room, runs them on the
// WorkerPool's batch lane, renews their leases (a renewal is also how a DELETE on any replica
// reaches the worker), and writes each result in one transaction. A result whose lease was
// lost meanwhile is discarded: another replica holds the item now.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "service/http/service_state.h"
#include "service/store/job_store.h"

namespace rollgap::service::http {

class JobRunner {
public:
    explicit JobRunner(ServiceState& state) : state_(state) {}
    ~JobRunner() { stop(); }
    JobRunner(const JobRunner&) = delete;
    JobRunner& operator=(const JobRunner&) = delete;

    void start();  // the claim loop and the renewer
    // A job was submitted here: claim now instead of at the next poll.
    void wake();
    // The store answered a DELETE with cancel_requested: if this replica holds the job's work,
    // stop it now rather than at the next renewal.
    void cancel_local(const std::string& job_id);
    // Draining: claim nothing more and give back at once the items that have not started, so
    // other replicas take them. Running items stop with the drain timeout (hard_cancel) and
    // are given back too.
    void stop_claiming();
    std::size_t held() const;  // work items this replica holds (waiting or running)
    void stop();               // joins the threads; idempotent

    // How often the claim loop looks for work when nobody woke it.
    static constexpr std::chrono::milliseconds poll_interval{200};
    // How often expired leases are queued again and expired jobs purged.
    static constexpr std::chrono::seconds upkeep_interval{1};

private:
    struct Item;

    void claim_loop();
    void renew_loop();
    bool claim_one();
    void run(const std::shared_ptr<Item>& item);
    void finish(const std::shared_ptr<Item>& item, const char* outcome);
    void give_back(const std::shared_ptr<Item>& item);
    void upkeep();

    ServiceState& state_;
    mutable std::mutex mutex_;
    std::condition_variable claim_wake_, renew_wake_;
    std::vector<std::shared_ptr<Item>> items_;
    bool claiming_ = true;
    bool woken_ = false;
    bool stopping_ = false;
    std::thread claimer_, renewer_;
};

}  // namespace rollgap::service::http
