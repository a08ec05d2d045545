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
            const auto count = to_int(s.exec("SELECT COUNT(*) FROM jobs").at(0).at(0));
            if (count >= static_cast<std::int64_t>(limits_.max_jobs) && !evict_cancelled(s))
                throw Abort{StoreStatus::full, "max_jobs"};
            const std::int64_t chunks =
                spec.points > 0 ? (spec.points + spec.chunk_size - 1) / spec.chunk_size : 1;
            const Param key = spec.idempotency_key ? Param{*spec.idempotency_key} : Param{nullptr};
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

bool SqlJobStore::evict_cancelled(Session& s) {
    const Rows oldest =
        s.exec("SELECT id FROM jobs WHERE state = 'cancelled' ORDER BY finished_ms, seq LIMIT 1");
    if (oldest.empty()) return false;
    const Param id{oldest.at(0).at(0).value_or("")};
    s.exec("DELETE FROM chunks WHERE job_id = $1", {id});
    s.exec("DELETE FROM jobs WHERE id = $1", {id});
    return true;
}

std::size_t SqlJobStore::purge_in(Session& s, Millis now) {
    const Millis cutoff = now - limits_.retention.count();
    s.exec("DELETE FROM chunks WHERE job_id IN (SELECT id FROM jobs WHERE finished_ms < $1)",
           {cutoff});
    return s.exec("DELETE FROM jobs WHERE finished_ms < $1 RETURNING id", {cutoff}).size();
}

std::shared_ptr<JobStore> make_sql_job_store(std::unique_ptr<Backend> backend, StoreLimits limits,
                                             Clock clock) {
    return std::make_shared<SqlJobStore>(std::move(backend), limits, std::move(clock));
}

}  // namespace rollgap::service::store::detail
