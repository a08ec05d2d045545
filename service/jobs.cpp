#include "service/jobs.h"

#include <algorithm>
#include <array>
#include <ctime>

#include <spdlog/fmt/fmt.h>

#include "service/job_settings.h"
#include "service/webhooks.h"

namespace rollgap::service {

using nlohmann::json;

std::string rfc3339(std::chrono::system_clock::time_point time) {
    const auto since_epoch = time.time_since_epoch();
    const auto seconds = std::chrono::floor<std::chrono::seconds>(since_epoch);
    const auto millis =
        std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - seconds).count();
    const std::time_t t = static_cast<std::time_t>(seconds.count());
    std::tm utc{};
    gmtime_r(&t, &utc);
    std::array<char, 32> text{};
    const std::size_t n = std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%S", &utc);
    return fmt::format("{}.{:03d}Z", std::string_view(text.data(), n), static_cast<int>(millis));
}

std::string rfc3339(store::Millis since_epoch_ms) {
    return rfc3339(std::chrono::system_clock::time_point(
        std::chrono::duration_cast<std::chrono::system_clock::duration>(
            std::chrono::milliseconds(since_epoch_ms))));
}

std::string body_hash(std::string_view text) {
    std::uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a 64 offset basis
    for (const char c : text) {
        hash ^= static_cast<unsigned char>(c);
        hash *= 0x100000001b3ULL;  // FNV-1a 64 prime
    }
    return fmt::format("{:016x}", hash);
}

namespace {

// The job's own retention, or the server's.
store::Millis retention_of(const store::JobRecord& job, std::chrono::milliseconds retention) {
    return job.retention_ms.value_or(retention.count());
}

}  // namespace

bool job_expired(const store::JobRecord& job, std::chrono::milliseconds retention,
                 store::Millis now_ms) {
    return job.finished_ms && *job.finished_ms + retention_of(job, retention) <= now_ms;
}

json job_document(const store::JobRecord& job, std::chrono::milliseconds retention,
                  JobDetail detail) {
    json document = {
        {"id", job.id},
        {"analysis", job.analysis},
        {"state", store::job_state_name(job.state)},
        {"progress", std::clamp(job.progress, 0.0, 1.0)},
        {"instance", job.instance},
        {"created_at", rfc3339(job.created_ms)},
    };
    if (job.worker) document["worker"] = *job.worker;
    if (job.started_ms) document["started_at"] = rfc3339(*job.started_ms);
    if (job.finished_ms) {
        document["finished_at"] = rfc3339(*job.finished_ms);
        document["expires_at"] = rfc3339(*job.finished_ms + retention_of(job, retention));
    }
    if (!job.labels.empty()) document["labels"] = labels_json(job.labels);
    if (job.retention_ms) document["retention_s"] = *job.retention_ms / 1000;
    if (job.callback) {
        // Its query replaced by "?…": a receiver's token often rides there, and every client
        // that may read jobs sees this document (and so does the callback's own body).
        document["callback_url"] = redacted_callback_url(job.callback->url);
        json callback = {{"state", job.callback->state}, {"attempts", job.callback->attempts}};
        if (job.callback->last_error) callback["last_error"] = *job.callback->last_error;
        document["callback"] = std::move(callback);
    }
    if (job.cancel_requested) document["cancel_requested"] = true;
    if (job.points > 0) {
        document["points_total"] = job.points;
        document["points_done"] =
            job.state == store::JobState::succeeded ? job.points : job.points_done;
    }
    if (detail == JobDetail::full) {
        // The store holds what the worker wrote; text that does not parse is no answer.
        if (job.result) document["result"] = json::parse(*job.result, nullptr, false);
        if (job.problem) document["problem"] = json::parse(*job.problem, nullptr, false);
    }
    return document;
}

}  // namespace rollgap::service
