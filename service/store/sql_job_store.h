#pragma once
// The job store's rules over the two SQL backends (sql_backend.h), one class in four files:
// the jobs (sql_job_store.cpp), their work items with leases (sql_work_items.cpp), the outbox
// of completion callbacks (sql_deliveries.cpp) and the mapping of rows to records
// (job_rows.h). Stored scenarios have their own rules (sql_scenario_store.h); this class
// forwards to them.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "service/store/job_store.h"
#include "service/store/sql_backend.h"
#include "service/store/sql_scenario_store.h"

namespace rollgap::service::store::detail {

class SqlJobStore final : public JobStore {
public:
    SqlJobStore(std::unique_ptr<Backend> backend, StoreLimits limits, Clock clock)
        : backend_(std::move(backend)), limits_(limits), clock_(std::move(clock)),
          scenarios_(*backend_, limits_, clock_) {}

    // Jobs (sql_job_store.cpp).
    Result<Created> create(const NewJob& spec) override;
    Result<JobRecord> get(const std::string& id) override;
    Result<JobPage> list(const ListQuery& query) override;
    Result<std::vector<ChunkResult>> finished_chunks(const std::string& id) override;
    Result<CancelResult> cancel(const std::string& id) override;
    Result<JobCounts> counts() override;
    Result<std::size_t> purge() override;

    // Work items: chunks, their leases and the replicas' heartbeat (sql_work_items.cpp).
    Result<JobCounts> probe(const std::string& owner) override;

    Result<std::optional<WorkItem>> claim(const std::string& owner,
                                          std::chrono::milliseconds lease) override;
    Result<Renewed> renew(const Lease& lease, std::chrono::milliseconds extend) override;
    StoreStatus progress(const Lease& lease, double fraction) override;
    Result<JobState> complete(const Lease& lease, FinalState outcome,
                              const std::string& text) override;
    StoreStatus release(const Lease& lease) override;
    Result<std::size_t> expire_leases() override;

    // Completion callbacks, the outbox (sql_deliveries.cpp).
    Result<std::optional<Delivery>> claim_delivery(const std::string& owner,
                                                   std::chrono::milliseconds lease) override;
    StoreStatus set_delivery_body(const Delivery& delivery, const std::string& body) override;
    StoreStatus record_delivery(const Delivery& delivery, DeliveryOutcome outcome,
                                Millis next_at_ms, const std::string& error) override;

    // Stored scenarios: their own rules (sql_scenario_store.cpp).
    Result<StoredScenario> put_scenario(const std::string& name, const std::string& body,
                                        std::optional<std::int64_t> if_match,
                                        const std::string& author, StoredKind kind,
                                        const std::string& posterior) override {
        return scenarios_.put(name, body, if_match, author, kind, posterior);
    }
    Result<StoredScenario> get_scenario(const std::string& name,
                                        std::optional<std::int64_t> version) override {
        return scenarios_.get(name, version);
    }
    using JobStore::get_scenario;
    StoreStatus delete_scenario(const std::string& name, std::optional<std::int64_t> if_match,
                                const std::string& author, StoredKind kind) override {
        return scenarios_.remove(name, if_match, author, kind);
    }
    Result<std::vector<StoredScenario>> list_scenarios() override {
        // Bounded by max_scenarios: one page holding them all.
        auto all = scenarios_.page({limits_.max_scenarios + 1, std::nullopt, StoredKind::stand});
        if (!all.ok()) return Result<std::vector<StoredScenario>>::failure(all.status, all.detail);
        return {StoreStatus::ok, std::move(all.value->scenarios), {}};
    }
    Result<ScenarioPage> list_scenario_page(const ScenarioQuery& query) override {
        return scenarios_.page(query);
    }

private:
    struct Done {
        StoreStatus status;
        std::string detail;
    };

    Done write(const std::function<void(Session&)>& body,
               const std::function<bool(Session&)>& verify) {
        Done done{StoreStatus::ok, {}};
        done.status = backend_->transact(true, body, verify, done.detail);
        return done;
    }
    Done read(const std::function<void(Session&)>& body) {
        Done done{StoreStatus::ok, {}};
        done.status = backend_->transact(false, body, {}, done.detail);
        return done;
    }

    // Row lock for read-then-write on PostgreSQL; SQLite's BEGIN IMMEDIATE already holds the
    // database's write lock.
    std::string lock() const {
        return backend_->dialect() == Dialect::postgresql ? " FOR UPDATE" : "";
    }

    // The id of the job created earlier with `key`; conflict if its body differs.
    static std::optional<std::string> earlier_job(Session& s, const std::string& key,
                                                  const std::string& hash);

    // Every unfinished chunk stops counting as work; the job gets its final state.
    static void finish_job(Session& s, const std::string& id, const std::string& state, Millis now);

    // A client that cancelled a job gave up its slot: when the store is full, the cancelled
    // job that finished first makes room. False if there is none.
    // Removes a job, its chunks and its labels.
    static void delete_job(Session& s, const Param& id);
    // Keeps the finished jobs within max_finished_jobs: the oldest finished go first.
    void evict_finished(Session& s);

    std::size_t purge_in(Session& s, Millis now);

    std::unique_ptr<Backend> backend_;
    StoreLimits limits_;
    Clock clock_;
    SqlScenarioStore scenarios_;
};

}  // namespace rollgap::service::store::detail
