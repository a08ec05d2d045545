// The job store's rules, written once over the two SQL backends (sql_backend.h).

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>
#include <random>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "service/store/sql_backend.h"
#include "service/store/sql_scenario_store.h"

namespace rollgap::service::store {

std::string_view status_name(StoreStatus status) {
    switch (status) {
        case StoreStatus::ok: return "ok";
        case StoreStatus::not_found: return "not_found";
        case StoreStatus::conflict: return "conflict";
        case StoreStatus::invalid: return "invalid";
        case StoreStatus::full: return "full";
        case StoreStatus::unavailable: return "unavailable";
    }
    return "unknown";
}

namespace {
constexpr std::array<std::string_view, 5> state_names = {"queued", "running", "succeeded", "failed",
                                                         "cancelled"};
}

std::string_view job_state_name(JobState state) {
    return state_names.at(static_cast<std::size_t>(state));
}

std::optional<JobState> job_state_from_name(std::string_view name) {
    for (std::size_t i = 0; i < state_names.size(); ++i) {
        if (state_names[i] == name) return static_cast<JobState>(i);
    }
    return std::nullopt;
}

Millis system_millis() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

namespace detail {

std::string param_text(const Param& param) {
    if (const auto* i = std::get_if<std::int64_t>(&param)) return std::to_string(*i);
    if (const auto* d = std::get_if<double>(&param)) {
        std::array<char, 32> buffer{};
        const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), *d);
        return error == std::errc{} ? std::string(buffer.data(), end) : std::string("0");
    }
    if (const auto* s = std::get_if<std::string>(&param)) return *s;
    return {};
}

std::int64_t to_int(const Value& value) {
    if (!value) return 0;
    std::int64_t number = 0;
    std::from_chars(value->data(), value->data() + value->size(), number);
    return number;
}

namespace {

std::optional<std::int64_t> to_optional_int(const Value& value) {
    if (!value) return std::nullopt;
    return to_int(value);
}

double to_double(const Value& value) { return value ? std::strtod(value->c_str(), nullptr) : 0.0; }

// 32 lower-case hex digits from the operating system's random source: ids and lease tokens.
std::string random_hex() {
    std::random_device source;
    std::string text;
    text.reserve(32);
    for (int i = 0; i < 4; ++i) {
        std::array<char, 9> part{};
        std::snprintf(part.data(), part.size(), "%08x", static_cast<unsigned>(source()));
        text += part.data();
    }
    return text;
}

constexpr std::string_view job_columns =
    "j.id, j.analysis, j.request, j.state, j.progress, j.result, j.problem, j.instance, j.created_ms, "
    "j.started_ms, j.finished_ms, j.deadline_ms, j.cancel_requested, j.points, j.chunks, j.seq, "
    "(SELECT COUNT(*) FROM chunks c WHERE c.job_id = j.id AND c.state = 'done'), "
    "(SELECT COALESCE(SUM(c.end_point - c.begin_point), 0) FROM chunks c WHERE c.job_id = j.id AND c.state = 'done'), j.worker";

JobRecord job_from_row(const Row& r) {
    JobRecord job;
    job.id = r.at(0).value_or("");
    job.analysis = r.at(1).value_or("");
    job.request = r.at(2).value_or("");
    job.state = job_state_from_name(r.at(3).value_or("")).value_or(JobState::failed);
    job.result = r.at(5);
    job.problem = r.at(6);
    job.instance = r.at(7).value_or("");
    job.created_ms = to_int(r.at(8));
    job.started_ms = to_optional_int(r.at(9));
    job.finished_ms = to_optional_int(r.at(10));
    job.deadline_ms = to_int(r.at(11));
    job.cancel_requested = to_int(r.at(12)) != 0;
    job.points = to_int(r.at(13));
    job.chunks = to_int(r.at(14));
    job.chunks_done = to_int(r.at(16));
    job.points_done = to_int(r.at(17));
    job.worker = r.at(18);
    if (job.state == JobState::succeeded) {
        job.progress = 1.0;
    } else if (job.points > 0) {
        job.progress = static_cast<double>(job.points_done) / static_cast<double>(job.points);
    } else {
        job.progress = to_double(r.at(4));
    }
    return job;
}

class SqlJobStore final : public JobStore {
public:
    SqlJobStore(std::unique_ptr<Backend> backend, StoreLimits limits, Clock clock)
        : backend_(std::move(backend)), limits_(limits), clock_(std::move(clock)),
          scenarios_(*backend_, limits_, clock_) {}

    Result<Created> create(const NewJob& spec) override {
        if (spec.points < 0 || (spec.points > 0 && spec.chunk_size <= 0)) {
            return Result<Created>::failure(StoreStatus::invalid, "points and chunk_size");
        }
        const std::string id = random_hex();
        std::optional<std::string> existing;
        auto status = write(
            [&](Session& s) {
                const Millis now = clock_();
                purge_in(s, now);
                if (spec.idempotency_key) {
                    existing = earlier_job(s, *spec.idempotency_key, spec.body_hash);
                    if (existing) return;
                }
                const auto count = to_int(s.exec("SELECT COUNT(*) FROM jobs").at(0).at(0));
                if (count >= static_cast<std::int64_t>(limits_.max_jobs) && !evict_cancelled(s))
                    throw Abort{StoreStatus::full, "max_jobs"};
                const std::int64_t chunks =
                    spec.points > 0 ? (spec.points + spec.chunk_size - 1) / spec.chunk_size : 1;
                const Param key =
                    spec.idempotency_key ? Param{*spec.idempotency_key} : Param{nullptr};
                const Rows inserted = s.exec(
                    "INSERT INTO jobs (id, analysis, request, state, instance, created_ms, deadline_ms, "
                    "idempotency_key, body_hash, points, chunk_size, chunks) "
                    "VALUES ($1, $2, $3, 'queued', $4, $5, $6, $7, $8, $9, $10, $11) "
                    "ON CONFLICT (idempotency_key) DO NOTHING RETURNING seq",
                    {id, spec.analysis, spec.request, spec.instance, now, spec.deadline_ms, key,
                     spec.body_hash, spec.points, spec.chunk_size, chunks});
                if (inserted.empty()) {
                    // Another replica inserted the same key meanwhile (it is committed now).
                    existing = earlier_job(s, *spec.idempotency_key, spec.body_hash);
                    if (!existing) throw Abort{StoreStatus::unavailable, "idempotency race"};
                    return;
                }
                const std::int64_t seq = to_int(inserted.at(0).at(0));
                for (std::int64_t i = 0; i < chunks; ++i) {
                    const std::int64_t begin = spec.points > 0 ? i * spec.chunk_size : 0;
                    const std::int64_t end =
                        spec.points > 0 ? std::min(spec.points, begin + spec.chunk_size) : 0;
                    s.exec(
                        "INSERT INTO chunks (job_id, idx, job_seq, begin_point, end_point, state) "
                        "VALUES ($1, $2, $3, $4, $5, 'queued')",
                        {id, i, seq, begin, end});
                }
            },
            [&](Session& s) { return !s.exec("SELECT 1 FROM jobs WHERE id = $1", {id}).empty(); });
        if (status.status != StoreStatus::ok)
            return Result<Created>::failure(status.status, status.detail);
        auto job = get(existing.value_or(id));
        if (!job.ok()) return Result<Created>::failure(job.status, job.detail);
        return {StoreStatus::ok, Created{*job.value, !existing}, {}};
    }

    Result<JobRecord> get(const std::string& id) override {
        std::optional<JobRecord> job;
        auto status = read([&](Session& s) {
            const Rows rows =
                s.exec("SELECT " + std::string(job_columns) + " FROM jobs j WHERE j.id = $1", {id});
            if (rows.empty()) throw Abort{StoreStatus::not_found, {}};
            job = job_from_row(rows.at(0));
        });
        if (status.status != StoreStatus::ok)
            return Result<JobRecord>::failure(status.status, status.detail);
        return {StoreStatus::ok, std::move(job), {}};
    }

    Result<JobPage> list(const ListQuery& query) override {
        std::string sql = "SELECT " + std::string(job_columns) + " FROM jobs j WHERE 1 = 1";
        std::vector<Param> params;
        if (query.state) {
            params.emplace_back(std::string(job_state_name(*query.state)));
            sql += " AND j.state = $" + std::to_string(params.size());
        }
        if (query.cursor) {
            const auto& c = *query.cursor;
            std::int64_t seq = 0;
            const auto [end, error] = std::from_chars(c.data(), c.data() + c.size(), seq);
            if (c.empty() || error != std::errc{} || end != c.data() + c.size() || seq <= 0) {
                return Result<JobPage>::failure(StoreStatus::invalid, "cursor");
            }
            params.emplace_back(seq);
            sql += " AND j.seq < $" + std::to_string(params.size());
        }
        const std::size_t limit = std::clamp<std::size_t>(query.limit, 1, 1000);
        params.emplace_back(static_cast<std::int64_t>(limit + 1));
        sql += " ORDER BY j.seq DESC LIMIT $" + std::to_string(params.size());
        JobPage page;
        auto status = read([&](Session& s) {
            const Rows rows = s.exec(sql, params);
            for (std::size_t i = 0; i < rows.size() && i < limit; ++i)
                page.jobs.push_back(job_from_row(rows[i]));
            if (rows.size() > limit) page.next_cursor = rows.at(limit - 1).at(15);
        });
        if (status.status != StoreStatus::ok)
            return Result<JobPage>::failure(status.status, status.detail);
        return {StoreStatus::ok, std::move(page), {}};
    }

    Result<std::vector<ChunkResult>> finished_chunks(const std::string& id) override {
        std::vector<ChunkResult> chunks;
        auto status = read([&](Session& s) {
            if (s.exec("SELECT 1 FROM jobs WHERE id = $1", {id}).empty())
                throw Abort{StoreStatus::not_found, {}};
            for (const Row& r : s.exec("SELECT idx, begin_point, end_point, result FROM chunks "
                                       "WHERE job_id = $1 AND state = 'done' ORDER BY idx",
                                       {id})) {
                chunks.push_back(
                    {to_int(r.at(0)), to_int(r.at(1)), to_int(r.at(2)), r.at(3).value_or("")});
            }
        });
        if (status.status != StoreStatus::ok) {
            return Result<std::vector<ChunkResult>>::failure(status.status, status.detail);
        }
        return {StoreStatus::ok, std::move(chunks), {}};
    }

    Result<CancelResult> cancel(const std::string& id) override {
        CancelResult result = CancelResult::cancelled;
        auto status = write(
            [&](Session& s) {
                const Millis now = clock_();
                const Rows rows = s.exec("SELECT state FROM jobs WHERE id = $1" + lock(), {id});
                if (rows.empty()) throw Abort{StoreStatus::not_found, {}};
                const auto state = job_state_from_name(rows.at(0).at(0).value_or(""));
                if (state == JobState::queued || state == JobState::running) {
                    const bool leased =
                        !s.exec("SELECT 1 FROM chunks WHERE job_id = $1 AND state = 'running'",
                                {id})
                             .empty();
                    if (leased) {
                        s.exec("UPDATE jobs SET cancel_requested = 1 WHERE id = $1", {id});
                        result = CancelResult::cancel_requested;
                    } else {
                        finish_job(s, id, "cancelled", now);
                        result = CancelResult::cancelled;
                    }
                } else {
                    s.exec("DELETE FROM chunks WHERE job_id = $1", {id});
                    s.exec("DELETE FROM jobs WHERE id = $1", {id});
                    result = CancelResult::deleted;
                }
            },
            {});
        if (status.status != StoreStatus::ok)
            return Result<CancelResult>::failure(status.status, status.detail);
        return {StoreStatus::ok, result, {}};
    }

    Result<JobCounts> counts() override {
        JobCounts counts;
        auto status = read([&](Session& s) {
            for (const Row& r : s.exec("SELECT state, COUNT(*) FROM jobs GROUP BY state")) {
                const auto n = static_cast<std::size_t>(to_int(r.at(1)));
                switch (job_state_from_name(r.at(0).value_or("")).value_or(JobState::failed)) {
                    case JobState::queued: counts.queued += n; break;
                    case JobState::running: counts.running += n; break;
                    case JobState::succeeded: counts.succeeded += n; break;
                    case JobState::failed: counts.failed += n; break;
                    case JobState::cancelled: counts.cancelled += n; break;
                }
            }
        });
        if (status.status != StoreStatus::ok)
            return Result<JobCounts>::failure(status.status, status.detail);
        return {StoreStatus::ok, counts, {}};
    }

    Result<JobCounts> probe(const std::string& owner) override {
        auto status = write(
            [&](Session& s) {
                const Millis now = clock_();
                s.exec(
                    "INSERT INTO store_heartbeat (instance, at_ms) VALUES ($1, $2) "
                    "ON CONFLICT (instance) DO UPDATE SET at_ms = excluded.at_ms",
                    {owner, now});
                // Replicas come and go under new names: a day-old row is nobody's.
                s.exec("DELETE FROM store_heartbeat WHERE at_ms < $1", {now - 86'400'000});
            },
            {});
        if (status.status != StoreStatus::ok)
            return Result<JobCounts>::failure(status.status, status.detail);
        return counts();
    }

    Result<std::optional<WorkItem>> claim(const std::string& owner,
                                          std::chrono::milliseconds lease) override {
        std::optional<WorkItem> item;
        const std::string token = random_hex();
        auto status = write(
            [&](Session& s) {
                const Millis now = clock_();
                const std::string skip_locked = backend_->dialect() == Dialect::postgresql
                                                    ? " FOR UPDATE OF c SKIP LOCKED"
                                                    : "";
                const Rows rows = s.exec(
                    "SELECT c.job_id, c.idx, c.begin_point, c.end_point, j.analysis, j.request, j.chunks, "
                    "j.deadline_ms "
                    "FROM chunks c JOIN jobs j ON j.id = c.job_id "
                    "WHERE j.state IN ('queued', 'running') AND j.cancel_requested = 0 "
                    "AND (c.state = 'queued' OR (c.state = 'running' AND c.lease_until_ms < $1)) "
                    "ORDER BY c.job_seq, c.idx LIMIT 1" +
                        skip_locked,
                    {now});
                if (rows.empty()) return;
                const Row& r = rows.at(0);
                WorkItem w;
                w.lease = {r.at(0).value_or(""), to_int(r.at(1)), token};
                w.begin = to_int(r.at(2));
                w.end = to_int(r.at(3));
                w.analysis = r.at(4).value_or("");
                w.request = r.at(5).value_or("");
                w.chunks = to_int(r.at(6));
                w.deadline_ms = to_int(r.at(7));
                w.lease_until_ms = now + lease.count();
                s.exec(
                    "UPDATE chunks SET state = 'running', lease_token = $3, lease_owner = $4, lease_until_ms = $5 "
                    "WHERE job_id = $1 AND idx = $2",
                    {w.lease.job_id, w.lease.chunk, token, owner, w.lease_until_ms});
                s.exec(
                    "UPDATE jobs SET state = 'running', started_ms = COALESCE(started_ms, $2), worker = $3 "
                    "WHERE id = $1",
                    {w.lease.job_id, now, owner});
                item = std::move(w);
            },
            [&](Session& s) {
                return !s.exec("SELECT 1 FROM chunks WHERE lease_token = $1", {token}).empty();
            });
        if (status.status != StoreStatus::ok) {
            return Result<std::optional<WorkItem>>::failure(status.status, status.detail);
        }
        return {StoreStatus::ok, std::move(item), {}};
    }

    Result<Renewed> renew(const Lease& lease, std::chrono::milliseconds extend) override {
        Renewed renewed;
        auto status = write(
            [&](Session& s) {
                renewed.lease_until_ms = clock_() + extend.count();
                const Rows rows = s.exec(
                    "UPDATE chunks SET lease_until_ms = $4 WHERE job_id = $1 AND idx = $2 AND lease_token = $3 "
                    "AND state = 'running' RETURNING idx",
                    {lease.job_id, lease.chunk, lease.token, renewed.lease_until_ms});
                if (rows.empty()) throw Abort{StoreStatus::conflict, "lease lost"};
                const Rows job =
                    s.exec("SELECT cancel_requested FROM jobs WHERE id = $1", {lease.job_id});
                renewed.cancel_requested = !job.empty() && to_int(job.at(0).at(0)) != 0;
            },
            {});
        if (status.status != StoreStatus::ok)
            return Result<Renewed>::failure(status.status, status.detail);
        return {StoreStatus::ok, renewed, {}};
    }

    StoreStatus progress(const Lease& lease, double fraction) override {
        return write(
                   [&](Session& s) {
                       const Rows rows = s.exec(
                           "UPDATE jobs SET progress = $4 WHERE id = $1 AND EXISTS (SELECT 1 FROM chunks c "
                           "WHERE c.job_id = $1 AND c.idx = $2 AND c.lease_token = $3 AND c.state = 'running') "
                           "RETURNING id",
                           {lease.job_id, lease.chunk, lease.token,
                            std::clamp(fraction, 0.0, 1.0)});
                       if (rows.empty()) throw Abort{StoreStatus::conflict, "lease lost"};
                   },
                   {})
            .status;
    }

    Result<JobState> complete(const Lease& lease, FinalState outcome,
                              const std::string& text) override {
        JobState after = JobState::running;
        auto status = write(
            [&](Session& s) {
                const Millis now = clock_();
                const Rows job =
                    s.exec("SELECT state, points FROM jobs WHERE id = $1" + lock(), {lease.job_id});
                if (job.empty()) throw Abort{StoreStatus::not_found, {}};
                const Rows chunk = s.exec(
                    "SELECT begin_point, end_point FROM chunks WHERE job_id = $1 AND idx = $2 AND lease_token = $3 "
                    "AND state = 'running'",
                    {lease.job_id, lease.chunk, lease.token});
                if (chunk.empty()) {
                    // This lease's result is stored already: an earlier attempt committed
                    // although its caller did not hear so (deadline, lost answer). Completing
                    // again is that same completion.
                    if (outcome == FinalState::succeeded &&
                        !s.exec("SELECT 1 FROM chunks WHERE job_id = $1 AND idx = $2 AND "
                                "lease_token = $3 AND state = 'done'",
                                {lease.job_id, lease.chunk, lease.token})
                             .empty()) {
                        after = job_state_from_name(job.at(0).at(0).value_or(""))
                                    .value_or(JobState::running);
                        return;
                    }
                    throw Abort{StoreStatus::conflict, "lease lost"};
                }
                const bool chunked = to_int(job.at(0).at(1)) > 0;
                if (outcome != FinalState::succeeded) {
                    const std::string state =
                        outcome == FinalState::failed ? "failed" : "cancelled";
                    if (outcome == FinalState::failed) {
                        s.exec("UPDATE jobs SET problem = $2 WHERE id = $1", {lease.job_id, text});
                    }
                    finish_job(s, lease.job_id, state, now);
                    after = outcome == FinalState::failed ? JobState::failed : JobState::cancelled;
                    return;
                }
                if (chunked) {
                    const auto points = nlohmann::json::parse(text, nullptr, false);
                    const auto expected = to_int(chunk.at(0).at(1)) - to_int(chunk.at(0).at(0));
                    if (!points.is_array() ||
                        static_cast<std::int64_t>(points.size()) != expected) {
                        throw Abort{StoreStatus::invalid,
                                    "a chunk's result is an array of its points"};
                    }
                }
                s.exec(
                    "UPDATE chunks SET state = 'done', result = $4, lease_until_ms = NULL "
                    "WHERE job_id = $1 AND idx = $2 AND lease_token = $3",
                    {lease.job_id, lease.chunk, lease.token, text});
                const auto left = to_int(
                    s.exec("SELECT COUNT(*) FROM chunks WHERE job_id = $1 AND state <> 'done'",
                           {lease.job_id})
                        .at(0)
                        .at(0));
                if (left > 0) return;
                std::string result = text;
                if (chunked) {
                    auto all = nlohmann::json::array();
                    for (const Row& r :
                         s.exec("SELECT result FROM chunks WHERE job_id = $1 ORDER BY idx",
                                {lease.job_id})) {
                        for (auto& point : nlohmann::json::parse(r.at(0).value_or("[]")))
                            all.push_back(std::move(point));
                    }
                    result = all.dump();
                }
                s.exec("UPDATE jobs SET result = $2 WHERE id = $1", {lease.job_id, result});
                finish_job(s, lease.job_id, "succeeded", now);
                after = JobState::succeeded;
            },
            [&](Session& s) {
                return !s.exec(
                             "SELECT 1 FROM chunks WHERE job_id = $1 AND idx = $2 AND lease_token = $3 "
                             "AND state <> 'running'",
                             {lease.job_id, lease.chunk, lease.token})
                            .empty();
            });
        if (status.status != StoreStatus::ok)
            return Result<JobState>::failure(status.status, status.detail);
        return {StoreStatus::ok, after, {}};
    }

    StoreStatus release(const Lease& lease) override {
        return write(
                   [&](Session& s) {
                       const Rows rows = s.exec(
                           "UPDATE chunks SET state = 'queued', lease_token = NULL, lease_owner = NULL, "
                           "lease_until_ms = NULL WHERE job_id = $1 AND idx = $2 AND lease_token = $3 "
                           "AND state = 'running' RETURNING idx",
                           {lease.job_id, lease.chunk, lease.token});
                       if (rows.empty()) throw Abort{StoreStatus::conflict, "lease lost"};
                   },
                   {})
            .status;
    }

    Result<std::size_t> expire_leases() override {
        std::size_t count = 0;
        auto status = write(
            [&](Session& s) {
                const Millis now = clock_();
                count =
                    s.exec(
                         "UPDATE chunks SET state = 'queued', lease_token = NULL, lease_owner = NULL, "
                         "lease_until_ms = NULL WHERE state = 'running' AND lease_until_ms < $1 RETURNING idx",
                         {now})
                        .size();
                // A cancel waiting for a worker that died: nobody will report it, so finish it
                // here.
                for (
                    const Row& r : s.exec(
                        "SELECT id FROM jobs j WHERE j.cancel_requested = 1 AND j.state = 'running' "
                        "AND NOT EXISTS (SELECT 1 FROM chunks c WHERE c.job_id = j.id "
                        "AND c.state = 'running')")) {
                    finish_job(s, r.at(0).value_or(""), "cancelled", now);
                }
            },
            {});
        if (status.status != StoreStatus::ok)
            return Result<std::size_t>::failure(status.status, status.detail);
        return {StoreStatus::ok, count, {}};
    }

    Result<std::size_t> purge() override {
        std::size_t count = 0;
        auto status = write([&](Session& s) { count = purge_in(s, clock_()); }, {});
        if (status.status != StoreStatus::ok)
            return Result<std::size_t>::failure(status.status, status.detail);
        return {StoreStatus::ok, count, {}};
    }

    // Stored scenarios: their own rules (sql_scenario_store.cpp).
    Result<StoredScenario> put_scenario(const std::string& name, const std::string& body,
                                        std::optional<std::int64_t> if_match,
                                        const std::string& author) override {
        return scenarios_.put(name, body, if_match, author);
    }
    Result<StoredScenario> get_scenario(const std::string& name) override {
        return scenarios_.get(name);
    }
    StoreStatus delete_scenario(const std::string& name, std::optional<std::int64_t> if_match,
                                const std::string& author) override {
        return scenarios_.remove(name, if_match, author);
    }
    Result<std::vector<StoredScenario>> list_scenarios() override {
        // Bounded by max_scenarios: one page holding them all.
        auto all = scenarios_.page({limits_.max_scenarios + 1, std::nullopt});
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
                                                  const std::string& hash) {
        const Rows rows =
            s.exec("SELECT id, body_hash FROM jobs WHERE idempotency_key = $1", {key});
        if (rows.empty()) return std::nullopt;
        if (rows.at(0).at(1).value_or("") != hash)
            throw Abort{StoreStatus::conflict, "idempotency key reused"};
        return rows.at(0).at(0);
    }

    // Every unfinished chunk stops counting as work; the job gets its final state.
    static void finish_job(Session& s, const std::string& id, const std::string& state,
                           Millis now) {
        s.exec(
            "UPDATE chunks SET state = 'cancelled', lease_token = NULL, lease_until_ms = NULL "
            "WHERE job_id = $1 AND state IN ('queued', 'running')",
            {id});
        s.exec("UPDATE jobs SET state = $2, finished_ms = $3 WHERE id = $1", {id, state, now});
    }

    // A client that cancelled a job gave up its slot: when the store is full, the cancelled
    // job that finished first makes room. False if there is none.
    static bool evict_cancelled(Session& s) {
        const Rows oldest = s.exec(
            "SELECT id FROM jobs WHERE state = 'cancelled' ORDER BY finished_ms, seq LIMIT 1");
        if (oldest.empty()) return false;
        const Param id{oldest.at(0).at(0).value_or("")};
        s.exec("DELETE FROM chunks WHERE job_id = $1", {id});
        s.exec("DELETE FROM jobs WHERE id = $1", {id});
        return true;
    }

    std::size_t purge_in(Session& s, Millis now) {
        const Millis cutoff = now - limits_.retention.count();
        s.exec("DELETE FROM chunks WHERE job_id IN (SELECT id FROM jobs WHERE finished_ms < $1)",
               {cutoff});
        return s.exec("DELETE FROM jobs WHERE finished_ms < $1 RETURNING id", {cutoff}).size();
    }

    std::unique_ptr<Backend> backend_;
    StoreLimits limits_;
    Clock clock_;
    SqlScenarioStore scenarios_;
};

}  // namespace

std::shared_ptr<JobStore> make_sql_job_store(std::unique_ptr<Backend> backend, StoreLimits limits,
                                             Clock clock) {
    return std::make_shared<SqlJobStore>(std::move(backend), limits, std::move(clock));
}

}  // namespace detail
}  // namespace rollgap::service::store
