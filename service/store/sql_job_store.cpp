// The job store's jobs: created (idempotently, within the store's bound), read, listed,
// cancelled or deleted, counted, and purged after their retention. Their work items are
// sql_work_items.cpp's.

#include "service/store/sql_job_store.h"

#include <algorithm>
#include <charconv>
#include <string>
#include <utility>

#include "service/store/job_rows.h"

namespace rollgap::service::store::detail {

Result<Created> SqlJobStore::create(const NewJob& spec) {
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
            const auto active =
                to_int(s.exec("SELECT COUNT(*) FROM jobs WHERE state IN ('queued', 'running')")
                           .at(0)
                           .at(0));
            if (active >= static_cast<std::int64_t>(limits_.max_jobs))
                throw Abort{StoreStatus::full, "max_jobs"};
            evict_finished(s);
            const std::int64_t chunks =
                spec.points > 0 ? (spec.points + spec.chunk_size - 1) / spec.chunk_size : 1;
            const Param key = spec.idempotency_key ? Param{*spec.idempotency_key} : Param{nullptr};
            const Param labels =
                spec.labels.empty() ? Param{nullptr} : Param{labels_text(spec.labels)};
            const Param retention = spec.retention_ms ? Param{*spec.retention_ms} : Param{nullptr};
            const Param callback = spec.callback_url ? Param{*spec.callback_url} : Param{nullptr};
            const Rows inserted = s.exec(
                "INSERT INTO jobs (id, analysis, request, state, instance, created_ms, deadline_ms, "
                "idempotency_key, body_hash, points, chunk_size, chunks, labels, retention_ms, "
                "callback_url) "
                "VALUES ($1, $2, $3, 'queued', $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14) "
                "ON CONFLICT (idempotency_key) DO NOTHING RETURNING seq",
                {id, spec.analysis, spec.request, spec.instance, now, spec.deadline_ms, key,
                 spec.body_hash, spec.points, spec.chunk_size, chunks, labels, retention,
                 callback});
            if (inserted.empty()) {
                // Another replica inserted the same key meanwhile (it is committed now).
                existing = earlier_job(s, *spec.idempotency_key, spec.body_hash);
                if (!existing) throw Abort{StoreStatus::unavailable, "idempotency race"};
                return;
            }
            const std::int64_t seq = to_int(inserted.at(0).at(0));
            for (const auto& [name, value] : spec.labels) {
                s.exec("INSERT INTO job_labels (job_id, name, value) VALUES ($1, $2, $3)",
                       {id, name, value});
            }
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

Result<JobRecord> SqlJobStore::get(const std::string& id) {
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

Result<JobPage> SqlJobStore::list(const ListQuery& query) {
    std::string sql = "SELECT " + std::string(job_columns) + " FROM jobs j WHERE 1 = 1";
    std::vector<Param> params;
    if (query.state) {
        params.emplace_back(std::string(job_state_name(*query.state)));
        sql += " AND j.state = $" + std::to_string(params.size());
    }
    for (const auto& [name, value] : query.labels) {
        params.emplace_back(name);
        params.emplace_back(value);
        sql += " AND EXISTS (SELECT 1 FROM job_labels l WHERE l.job_id = j.id AND l.name = $" +
               std::to_string(params.size() - 1) + " AND l.value = $" +
               std::to_string(params.size()) + ")";
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

Result<std::vector<ChunkResult>> SqlJobStore::finished_chunks(const std::string& id) {
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

Result<CancelResult> SqlJobStore::cancel(const std::string& id) {
    CancelResult result = CancelResult::cancelled;
    auto status = write(
        [&](Session& s) {
            const Millis now = clock_();
            const Rows rows = s.exec("SELECT state FROM jobs WHERE id = $1" + lock(), {id});
            if (rows.empty()) throw Abort{StoreStatus::not_found, {}};
            const auto state = job_state_from_name(rows.at(0).at(0).value_or(""));
            if (state == JobState::queued || state == JobState::running) {
                const bool leased =
                    !s.exec("SELECT 1 FROM chunks WHERE job_id = $1 AND state = 'running'", {id})
                         .empty();
                if (leased) {
                    s.exec("UPDATE jobs SET cancel_requested = 1 WHERE id = $1", {id});
                    result = CancelResult::cancel_requested;
                } else {
                    finish_job(s, id, "cancelled", now);
                    result = CancelResult::cancelled;
                }
            } else {
                delete_job(s, id);
                result = CancelResult::deleted;
            }
        },
        {});
    if (status.status != StoreStatus::ok)
        return Result<CancelResult>::failure(status.status, status.detail);
    return {StoreStatus::ok, result, {}};
}

Result<JobCounts> SqlJobStore::counts() {
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

Result<std::size_t> SqlJobStore::purge() {
    std::size_t count = 0;
    auto status = write([&](Session& s) { count = purge_in(s, clock_()); }, {});
    if (status.status != StoreStatus::ok)
        return Result<std::size_t>::failure(status.status, status.detail);
    return {StoreStatus::ok, count, {}};
}

std::optional<std::string> SqlJobStore::earlier_job(Session& s, const std::string& key,
                                                    const std::string& hash) {
    const Rows rows = s.exec("SELECT id, body_hash FROM jobs WHERE idempotency_key = $1", {key});
    if (rows.empty()) return std::nullopt;
    if (rows.at(0).at(1).value_or("") != hash)
        throw Abort{StoreStatus::conflict, "idempotency key reused"};
    return rows.at(0).at(0);
}

void SqlJobStore::delete_job(Session& s, const Param& id) {
    s.exec("DELETE FROM chunks WHERE job_id = $1", {id});
    s.exec("DELETE FROM job_labels WHERE job_id = $1", {id});
    s.exec("DELETE FROM jobs WHERE id = $1", {id});
}

void SqlJobStore::evict_finished(Session& s) {
    const auto finished =
        to_int(s.exec("SELECT COUNT(*) FROM jobs WHERE finished_ms IS NOT NULL").at(0).at(0));
    const std::int64_t excess = finished - static_cast<std::int64_t>(limits_.max_finished_jobs);
    if (excess <= 0) return;
    for (const Row& row :
         s.exec("SELECT id FROM jobs WHERE finished_ms IS NOT NULL ORDER BY finished_ms, seq "
                "LIMIT $1",
                {excess}))
        delete_job(s, Param{row.at(0).value_or("")});
}

std::size_t SqlJobStore::purge_in(Session& s, Millis now) {
    // A job's own retention, or the store's.
    const std::string expired =
        "SELECT id FROM jobs WHERE finished_ms < CAST($1 AS BIGINT) - COALESCE(retention_ms, "
        "CAST($2 AS BIGINT))";
    const std::vector<Param> at{now, static_cast<std::int64_t>(limits_.retention.count())};
    s.exec("DELETE FROM chunks WHERE job_id IN (" + expired + ")", at);
    s.exec("DELETE FROM job_labels WHERE job_id IN (" + expired + ")", at);
    const std::size_t purged =
        s.exec(
             "DELETE FROM jobs WHERE finished_ms < CAST($1 AS BIGINT) - COALESCE(retention_ms, "
             "CAST($2 AS BIGINT)) RETURNING id",
             at)
            .size();
    // A delivery outlives its job while it is pending (its body is its own); once done, it
    // goes with the job.
    s.exec(
        "DELETE FROM webhook_deliveries WHERE state IN ('delivered', 'failed') "
        "AND NOT EXISTS (SELECT 1 FROM jobs j WHERE j.id = webhook_deliveries.job_id)");
    return purged;
}

std::shared_ptr<JobStore> make_sql_job_store(std::unique_ptr<Backend> backend, StoreLimits limits,
                                             Clock clock) {
    return std::make_shared<SqlJobStore>(std::move(backend), limits, std::move(clock));
}

}  // namespace rollgap::service::store::detail
