#pragma once
// Rows of the jobs table as records, and the random ids and lease tokens of new rows: the
// mapping the job store's SQL (sql_job_store.cpp, sql_work_items.cpp) shares.

#include <string>
#include <string_view>

#include "service/store/job_store.h"
#include "service/store/sql_backend.h"

namespace rollgap::service::store::detail {

// The columns job_from_row reads, in its order, from `jobs j` (and its chunks' counts).
inline constexpr std::string_view job_columns =
    "j.id, j.analysis, j.request, j.state, j.progress, j.result, j.problem, j.instance, j.created_ms, "
    "j.started_ms, j.finished_ms, j.deadline_ms, j.cancel_requested, j.points, j.chunks, j.seq, "
    "(SELECT COUNT(*) FROM chunks c WHERE c.job_id = j.id AND c.state = 'done'), "
    "(SELECT COALESCE(SUM(c.end_point - c.begin_point), 0) FROM chunks c WHERE c.job_id = j.id AND c.state = 'done'), j.worker, "
    "j.labels, j.retention_ms, j.callback_url, "
    "(SELECT w.state FROM webhook_deliveries w WHERE w.job_id = j.id), "
    "(SELECT w.attempts FROM webhook_deliveries w WHERE w.job_id = j.id), "
    "(SELECT w.last_error FROM webhook_deliveries w WHERE w.job_id = j.id)";

// Labels as the jobs.labels column keeps them: "name=value" lines, by name (names and values
// hold no line break; the service checks them).
std::string labels_text(const std::vector<std::pair<std::string, std::string>>& labels);
std::vector<std::pair<std::string, std::string>> labels_from_text(std::string_view text);

JobRecord job_from_row(const Row& r);

// 32 lower-case hex digits from the operating system's random source: ids and lease tokens.
std::string random_hex();

}  // namespace rollgap::service::store::detail
