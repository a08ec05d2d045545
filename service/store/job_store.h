#pragma once
// The durable job store: jobs, their work items (chunks) with leases, and stored stand
// scenarios, behind one interface with two backends (SQLite embedded, PostgreSQL shared by
// replicas). See docs/job-store.md for the design and the lease model.
//
// Every operation returns a status value; no exception leaves this interface. `unavailable`
// means the database could not be reached or did not answer in time (the service answers
// 503 with Retry-After); a transaction that failed that way left nothing half-written.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rollgap::service::store {

enum class StoreStatus {
    ok,
    not_found,
    conflict,     // idempotency key reused with another body, version mismatch, lost lease
    invalid,      // refused by the store's rules (reserved name, malformed chunk result, …)
    full,         // the size bound is reached even after purging expired jobs
    unavailable,  // the database cannot be reached now; retry later
};
std::string_view status_name(StoreStatus status);

template <class T>
struct Result {
    StoreStatus status = StoreStatus::ok;
    std::optional<T> value;  // set when status is ok
    std::string detail;      // for logs; never contains request bodies

    bool ok() const { return status == StoreStatus::ok; }
    static Result failure(StoreStatus s, std::string why = {}) {
        return {s, std::nullopt, std::move(why)};
    }
};

enum class JobState { queued, running, succeeded, failed, cancelled };
std::string_view job_state_name(JobState state);
std::optional<JobState> job_state_from_name(std::string_view name);

// Wall-clock milliseconds since the Unix epoch. Leases are compared with the clocks of the
// replicas, so they must be long compared with the clock skew between replicas.
using Millis = std::int64_t;
using Clock = std::function<Millis()>;
Millis system_millis();

struct NewJob {
    std::string analysis;
    std::string request;  // JSON text of the facade request
    Millis deadline_ms = 0;
    std::string instance;  // the replica that accepted it
    std::optional<std::string> idempotency_key;
    std::string body_hash;  // compared when the idempotency key is reused
    // 0: one work item whose result is stored verbatim. N > 0: N points split into chunks of
    // `chunk_size` points; each chunk's result is a JSON array of exactly its points, and the
    // job's result is their concatenation in point order.
    std::int64_t points = 0;
    std::int64_t chunk_size = 0;
    // The client's labels (name, value), names unique: a coil id, a line, an order; listed by
    // name. Kept as given and filterable (ListQuery::labels).
    std::vector<std::pair<std::string, std::string>> labels;
    // How long the job is kept once finished; nothing: the store's retention (StoreLimits).
    std::optional<Millis> retention_ms;
    // Where the job's completion is announced (a webhook): when the job finishes, a delivery
    // is queued in the same transaction (claim_delivery).
    std::optional<std::string> callback_url;
};

// A job's completion callback as the job document shows it.
struct CallbackStatus {
    std::string url;
    // pending: the job has not finished, or its delivery waits for (another) attempt;
    // delivered: a 2xx answer; failed: every attempt made without one.
    std::string state = "pending";
    std::int64_t attempts = 0;
    std::optional<std::string> last_error;  // "HTTP 500", "connection refused", ...
};

struct JobRecord {
    std::string id;
    std::string analysis;
    std::string request;
    JobState state = JobState::queued;
    double progress = 0.0;               // 0..1; for chunked jobs the share of finished points
    std::optional<std::string> result;   // JSON text, when succeeded
    std::optional<std::string> problem;  // JSON text, when failed
    std::string instance;                // the replica that accepted it
    std::optional<std::string> worker;   // the replica that claimed its work last
    Millis created_ms = 0;
    std::optional<Millis> started_ms;
    std::optional<Millis> finished_ms;
    Millis deadline_ms = 0;
    bool cancel_requested = false;
    std::int64_t points = 0;
    std::int64_t points_done = 0;
    std::int64_t chunks = 1;
    std::int64_t chunks_done = 0;
    std::vector<std::pair<std::string, std::string>> labels;  // by name
    std::optional<Millis> retention_ms;                       // nothing: the store's
    std::optional<CallbackStatus> callback;                   // a job with a callback_url
};

struct JobCounts {
    std::size_t queued = 0, running = 0, succeeded = 0, failed = 0, cancelled = 0;
    std::size_t total() const { return queued + running + succeeded + failed + cancelled; }
    std::size_t active() const { return queued + running; }
};

struct Created {
    JobRecord job;
    bool created = false;  // false: an earlier job with the same idempotency key and body
};

struct ListQuery {
    std::optional<JobState> state;
    std::size_t limit = 50;
    std::optional<std::string> cursor;  // next_cursor of the previous page
    // Only jobs carrying every one of these labels (name and value).
    std::vector<std::pair<std::string, std::string>> labels = {};
};

struct JobPage {
    std::vector<JobRecord> jobs;  // newest first
    std::optional<std::string> next_cursor;
};

// A claimed work item: the whole job (chunks == 1, points == 0) or one chunk of points
// [begin, end).
struct Lease {
    std::string job_id;
    std::int64_t chunk = 0;
    std::string token;  // identifies this claim; a later claim of the same chunk gets another
};

struct WorkItem {
    Lease lease;
    std::string analysis;
    std::string request;
    std::int64_t chunks = 1;
    std::int64_t begin = 0, end = 0;
    Millis lease_until_ms = 0;
    Millis deadline_ms = 0;  // the job's deadline
};

struct Renewed {
    Millis lease_until_ms = 0;
    bool cancel_requested = false;  // the worker stops and completes with `cancelled`
};

enum class FinalState { succeeded, failed, cancelled };

// A completion callback due for an attempt (the outbox, docs/job-store.md "Callbacks"): one per
// finished job that asked for one, claimed by one replica at a time under a lease.
struct Delivery {
    std::string id;  // the delivery id the receiver sees on every attempt (Rollgap-Delivery)
    std::string job_id;
    std::string url;
    JobState job_state = JobState::succeeded;  // the state the job finished in
    std::optional<std::string> body;           // fixed at the first attempt; every retry sends it
    std::int64_t attempts = 0;                 // made before this one
    std::string token;                         // this claim's lease
};

enum class DeliveryOutcome {
    delivered,  // a 2xx answer: done
    retry,      // no 2xx: attempt again at next_at_ms
    failed,     // no 2xx and no attempt left
};

enum class CancelResult { cancelled, cancel_requested, deleted };

struct ChunkResult {
    std::int64_t chunk = 0;
    std::int64_t begin = 0, end = 0;
    std::string result;  // JSON array of the chunk's points
};

// One version of a stored scenario (table scenario_versions): versions of a name count up
// for ever, across deletes, so an ETag never names two different scenarios.
// What a stored document is (column scenario_versions.kind): a stand scenario or a tandem
// mill's document (docs/http-api.md, stored mills). A name is one thing at a time: the
// versions of a name count up across kinds, and a write of the other kind over a live name is
// refused (`conflict`, detail kind_conflict_detail).
enum class StoredKind { stand, mill };
std::string_view stored_kind_name(StoredKind kind);
inline constexpr std::string_view kind_conflict_detail = "the name holds the other kind";

struct StoredScenario {
    std::string name;
    std::string body;  // JSON text
    std::int64_t version = 0;
    Millis updated_ms = 0;  // when this version was written
    std::string author;     // who wrote it: the client key's name, or "anonymous"
    bool created = false;   // put_scenario: the name held no scenario before this version
    StoredKind kind = StoredKind::stand;
    // The calibration posterior this version was fitted with (JSON {parameters, correlation},
    // docs/model.md §11.6); empty: none.
    std::string posterior;
};

struct ScenarioQuery {
    std::size_t limit = 50;
    std::optional<std::string> cursor;    // next_cursor of the previous page
    StoredKind kind = StoredKind::stand;  // the page lists names of this kind only
};

struct ScenarioPage {
    std::vector<StoredScenario> scenarios;  // by name, bodies omitted
    std::optional<std::string> next_cursor;
};

struct StoreLimits {
    std::size_t max_jobs = 1000;  // jobs queued or running; beyond: full
    // Finished jobs kept at most; beyond, the oldest finished are removed first (whatever
    // their retention): the store's size is bounded by max_jobs + max_finished_jobs.
    std::size_t max_finished_jobs = 1000;
    std::chrono::milliseconds retention{3'600'000};  // a finished job is kept this long
    // The longest retention a job may ask for (NewJob::retention_ms).
    std::chrono::milliseconds max_retention{86'400'000};
    std::size_t max_scenarios = 1000;   // stored scenarios (names not deleted)
    std::size_t scenario_history = 20;  // versions kept per name, newest first
    // Deleted names whose marker row is kept (it holds the name's version counter); beyond it
    // the oldest markers go and their versions raise a floor that every new name starts above.
    std::size_t deleted_names = 1000;
    // The store executor (store_executor.h): its threads, each with at most one database
    // connection, and how long a caller waits for one operation before it answers
    // `unavailable` (a write's outcome is then unknown).
    std::size_t connections = 4;
    std::chrono::milliseconds deadline{2000};
    // How the database names this replica's connections (PostgreSQL `application_name`, seen
    // in pg_stat_activity): "rollgap/<instance>", so an operator sees which replica holds which
    // connection. A DSN that sets application_name itself keeps its own.
    std::string client_name = "rollgap";
};

class JobStore {
public:
    virtual ~JobStore() = default;

    // Jobs.
    virtual Result<Created> create(const NewJob& job) = 0;
    virtual Result<JobRecord> get(const std::string& id) = 0;
    virtual Result<JobPage> list(const ListQuery& query) = 0;
    // The finished chunks of a chunked job so far, in point order (partial results).
    virtual Result<std::vector<ChunkResult>> finished_chunks(const std::string& id) = 0;
    virtual Result<CancelResult> cancel(const std::string& id) = 0;
    // Jobs by state (one cheap query: metrics are scraped every few seconds).
    virtual Result<JobCounts> counts() = 0;
    // The background health probe: a write the store must accept (the heartbeat row of
    // `owner`), so a store that still reads but no longer writes (read-only file or file
    // system, full disk) is unavailable, then the jobs by state.
    virtual Result<JobCounts> probe(const std::string& owner) = 0;

    // Work. `owner` names the replica (for the job document and logs).
    virtual Result<std::optional<WorkItem>> claim(const std::string& owner,
                                                  std::chrono::milliseconds lease) = 0;
    virtual Result<Renewed> renew(const Lease& lease, std::chrono::milliseconds extend) = 0;
    virtual StoreStatus progress(const Lease& lease, double fraction) = 0;
    // Writes the item's result (or the job's problem) in one transaction, only while `lease`
    // is held (conflict otherwise). Returns the job's state afterwards.
    virtual Result<JobState> complete(const Lease& lease, FinalState outcome,
                                      const std::string& text) = 0;
    // Gives the item back (draining replica): it is queued again for any replica.
    virtual StoreStatus release(const Lease& lease) = 0;
    // Queues again every item whose lease ran out; returns how many.
    virtual Result<std::size_t> expire_leases() = 0;
    // Deletes finished jobs older than the retention; returns how many. Deliveries that are
    // done (delivered or failed) and whose job is gone go with them.
    virtual Result<std::size_t> purge() = 0;

    // Completion callbacks. A delivery due now (next attempt time reached, no live lease), or
    // nothing; the claim holds it for `lease`.
    virtual Result<std::optional<Delivery>> claim_delivery(const std::string& owner,
                                                           std::chrono::milliseconds lease) = 0;
    // Fixes the body of a claimed delivery that has none yet (its first attempt); conflict when
    // the lease was lost.
    virtual StoreStatus set_delivery_body(const Delivery& delivery, const std::string& body) = 0;
    // The attempt's outcome; `error` says why it was not delivered ("HTTP 503", "connection
    // refused"); `next_at_ms` is when a retry is due. Conflict when the lease was lost.
    virtual StoreStatus record_delivery(const Delivery& delivery, DeliveryOutcome outcome,
                                        Millis next_at_ms, const std::string& error) = 0;

    // Stored stand scenarios and mills (`kind`); `default` is reserved (invalid). `if_match`:
    // the version the caller last saw; a mismatch (or a missing scenario) is a conflict, as is
    // replacing a live name of the other kind (detail kind_conflict_detail). A new name beyond
    // StoreLimits::max_scenarios (both kinds together) is `full`. `author` is recorded on the
    // version written (a delete is a version too: who removed the stand).
    virtual Result<StoredScenario> put_scenario(const std::string& name, const std::string& body,
                                                std::optional<std::int64_t> if_match,
                                                const std::string& author = "anonymous",
                                                StoredKind kind = StoredKind::stand,
                                                const std::string& posterior = {}) = 0;
    // Any kind: the caller compares StoredScenario::kind with what it expects. `version`: that
    // version of the name (one of the last StoreLimits::scenario_history kept), not_found if it
    // is not kept or is a delete; none: the current one.
    virtual Result<StoredScenario> get_scenario(const std::string& name,
                                                std::optional<std::int64_t> version) = 0;
    Result<StoredScenario> get_scenario(const std::string& name) {
        return get_scenario(name, std::nullopt);
    }
    // A live name of another kind than `kind` is not_found (it is not in that collection).
    virtual StoreStatus delete_scenario(const std::string& name,
                                        std::optional<std::int64_t> if_match,
                                        const std::string& author = "anonymous",
                                        StoredKind kind = StoredKind::stand) = 0;
    // Stand scenarios by name, bodies omitted.
    virtual Result<std::vector<StoredScenario>> list_scenarios() = 0;
    // A page of list_scenarios(); a cursor that is no scenario name is `invalid`.
    virtual Result<ScenarioPage> list_scenario_page(const ScenarioQuery& query) = 0;
};

// From the `--store` setting: `sqlite:/path/to/file.db`, a `postgresql://…` (or
// `postgres://…`) DSN, or `postgresql-file:/path` naming a file that holds the DSN (a
// Kubernetes Secret). `invalid` for anything else; `unavailable` if the database cannot be
// opened or migrated now.
Result<std::shared_ptr<JobStore>> open_store(const std::string& setting, StoreLimits limits = {},
                                             Clock clock = system_millis);

// The details of `unavailable` that the store gives itself (the rest come from the database).
inline constexpr std::string_view deadline_detail = "the store did not answer within the deadline";
inline constexpr std::string_view stalled_detail =
    "the store is not answering (every store thread is stuck past the deadline)";
inline constexpr std::string_view queue_full_detail = "the store's queue is full";
inline constexpr std::string_view moved_detail =
    "the SQLite file was deleted or moved while the service had it open";

}  // namespace rollgap::service::store
