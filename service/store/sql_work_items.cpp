// The job store's work items: a job's chunks (one for a job that does not split), claimed by a
// replica under a lease, renewed, completed or released, and given back when a lease runs out
// (docs/job-store.md); and the replicas' heartbeat.

#include "service/store/sql_job_store.h"

#include <algorithm>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "service/store/job_rows.h"

namespace rollgap::service::store::detail {

Result<JobCounts> SqlJobStore::probe(const std::string& owner) {
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

Result<std::optional<WorkItem>> SqlJobStore::claim(const std::string& owner,
                                                   std::chrono::milliseconds lease) {
    std::optional<WorkItem> item;
    const std::string token = random_hex();
    auto status = write(
        [&](Session& s) {
            const Millis now = clock_();
            const std::string skip_locked =
                backend_->dialect() == Dialect::postgresql ? " FOR UPDATE OF c SKIP LOCKED" : "";
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

Result<Renewed> SqlJobStore::renew(const Lease& lease, std::chrono::milliseconds extend) {
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

StoreStatus SqlJobStore::progress(const Lease& lease, double fraction) {
    return write(
               [&](Session& s) {
                   const Rows rows = s.exec(
                       "UPDATE jobs SET progress = $4 WHERE id = $1 AND EXISTS (SELECT 1 FROM chunks c "
                       "WHERE c.job_id = $1 AND c.idx = $2 AND c.lease_token = $3 AND c.state = 'running') "
                       "RETURNING id",
                       {lease.job_id, lease.chunk, lease.token, std::clamp(fraction, 0.0, 1.0)});
                   if (rows.empty()) throw Abort{StoreStatus::conflict, "lease lost"};
               },
               {})
        .status;
}

Result<JobState> SqlJobStore::complete(const Lease& lease, FinalState outcome,
                                       const std::string& text) {
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
                const std::string state = outcome == FinalState::failed ? "failed" : "cancelled";
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
                if (!points.is_array() || static_cast<std::int64_t>(points.size()) != expected) {
                    throw Abort{StoreStatus::invalid, "a chunk's result is an array of its points"};
                }
            }
            s.exec(
                "UPDATE chunks SET state = 'done', result = $4, lease_until_ms = NULL "
                "WHERE job_id = $1 AND idx = $2 AND lease_token = $3",
                {lease.job_id, lease.chunk, lease.token, text});
            const auto left =
                to_int(s.exec("SELECT COUNT(*) FROM chunks WHERE job_id = $1 AND state <> 'done'",
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

StoreStatus SqlJobStore::release(const Lease& lease) {
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

Result<std::size_t> SqlJobStore::expire_leases() {
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
            for (const Row& r : s.exec(
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

void SqlJobStore::finish_job(Session& s, const std::string& id, const std::string& state,
                             Millis now) {
    s.exec(
        "UPDATE chunks SET state = 'cancelled', lease_token = NULL, lease_until_ms = NULL "
        "WHERE job_id = $1 AND state IN ('queued', 'running')",
        {id});
    s.exec("UPDATE jobs SET state = $2, finished_ms = $3 WHERE id = $1", {id, state, now});
    // The completion callback is queued with the completion itself: a finished job that asked
    // for one always has its delivery, whichever replica finished it (docs/job-store.md).
    s.exec(
        "INSERT INTO webhook_deliveries (id, job_id, url, job_state, state, attempts, next_at_ms, "
        "created_ms) SELECT CAST($2 AS TEXT), id, callback_url, CAST($3 AS TEXT), 'pending', 0, "
        "CAST($4 AS BIGINT), CAST($4 AS BIGINT) FROM jobs "
        "WHERE id = $1 AND callback_url IS NOT NULL ON CONFLICT (job_id) DO NOTHING",
        {id, random_hex(), state, now});
}

}  // namespace rollgap::service::store::detail
