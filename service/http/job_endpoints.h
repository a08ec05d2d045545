#pragma once
// The job endpoints over the durable store: POST /v1/jobs (the facade's envelope check, then a
// row in the store), GET /v1/jobs (a page of jobs), GET and DELETE /v1/jobs/{id} on any
// replica. A job's scenario and options are checked when it runs.

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "service/http/job_runner.h"
#include "service/http/service_state.h"

namespace rollgap::service::http {

class JobEndpoints {
public:
    JobEndpoints(ServiceState& state, JobRunner& runner) : state_(state), runner_(runner) {}

    // `idempotency_key`: the Idempotency-Key header ("" when absent).
    void create(nlohmann::json request, const std::string& idempotency_key,
                httplib::Response& response);
    // The job document, as JSON or, for a finished job, its result's CSV table as `request`
    // asks (set_outcome).
    void get(const httplib::Request& request, const std::string& id, httplib::Response& response);
    void list(const httplib::Request& request, httplib::Response& response);
    void cancel(const std::string& id, httplib::Response& response);
    // GET /v1/jobs/{id}/events: the job's document (summary) as a server-sent event each time
    // it changes, then `end`; a comment line at least every event_heartbeat.
    void events(const std::string& id, httplib::Response& response);

    static constexpr std::size_t max_idempotency_key = 200;
    static constexpr std::size_t default_page = 20;
    static constexpr std::size_t max_page = 100;
    // The most chunks a batch is split into (each chunk parses the whole stored batch).
    static constexpr std::int64_t max_batch_chunks = 64;

private:
    // The store, or nullptr after answering 503 store_unavailable.
    std::shared_ptr<store::JobStore> store_or_503(httplib::Response& response);
    // Answers a failed store operation (not found, unavailable, …).
    void store_failure(store::StoreStatus status, const std::string& id,
                       httplib::Response& response);
    void not_found(const std::string& id, httplib::Response& response);
    // The job, or nothing after answering 404 (absent or past its retention) or the store's
    // failure.
    std::optional<store::JobRecord> live_job(store::JobStore& store, const std::string& id,
                                             httplib::Response& response);
    // The job document with what needs the store or the request: a chunked job's result
    // assembled from its points, or its partial result while it runs.
    nlohmann::json full_document(store::JobStore& store, const store::JobRecord& job);

    ServiceState& state_;
    JobRunner& runner_;
    std::shared_ptr<std::atomic<std::size_t>> open_streams_ =
        std::make_shared<std::atomic<std::size_t>>(0);
};

}  // namespace rollgap::service::http
