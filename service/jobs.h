#pragma once
// Jobs as clients see them: the job document (the OpenAPI schema Job) rendered from the
// durable store's record, and the hash that recognises a retried submission.
// The jobs themselves live in the store (service/store/job_store.h, docs/job-store.md).

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "service/store/job_store.h"

namespace rollgap::service {

// What the document carries besides the job's state.
enum class JobDetail {
    summary,  // list entries: no result, problem or partial result
    full,     // GET /v1/jobs/{id}
};

// The job document. `retention`: how long a finished job is kept (its expires_at).
nlohmann::json job_document(const store::JobRecord& job, std::chrono::milliseconds retention,
                            JobDetail detail);

// Whether a finished job's retention has passed at `now_ms` (the store purges it soon; until
// then it is no longer served).
bool job_expired(const store::JobRecord& job, std::chrono::milliseconds retention,
                 store::Millis now_ms);

// FNV-1a 64 of `text` as 16 lower-case hex digits: the stored hash of a job's canonical
// request, stable across processes and builds (std::hash is neither).
std::string body_hash(std::string_view text);

// RFC 3339 UTC with milliseconds: 2024-05-01T12:34:56.789Z
std::string rfc3339(std::chrono::system_clock::time_point time);
std::string rfc3339(store::Millis since_epoch_ms);

}  // namespace rollgap::service
