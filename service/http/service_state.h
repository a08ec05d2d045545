#pragma once
// What the parts of the HTTP layer share: the resolved configuration, the evaluator, the
// compute workers, the durable job store, the metrics, and the drain flags.

#include <atomic>
#include <chrono>
#include <string>

#include <httplib.h>

#include "service/client_keys.h"
#include "service/config.h"
#include "service/http/evaluator.h"
#include "service/http/store_handle.h"
#include "service/metrics.h"
#include "service/worker_pool.h"

namespace rollgap::service::http {

using SteadyClock = std::chrono::steady_clock;

struct ServiceState {
    ServiceState(ServerConfig resolved, Evaluator evaluate);

    ServerConfig config;
    Evaluator evaluator;
    Metrics metrics;
    WorkerPool pool;
    StoreHandle store;  // the durable store: jobs, chunks, stored scenarios
    KeyRing keys;       // the bearer token and the client keys (never in the store)

    std::atomic<bool> draining{false};     // SIGTERM: no new work, /readyz fails
    std::atomic<bool> hard_cancel{false};  // the drain timeout passed: stop everything
    std::atomic<int> in_flight{0};         // synchronous compute requests between read and answer
    const std::chrono::system_clock::time_point start_time = std::chrono::system_clock::now();

    // 503 + Retry-After.
    void overloaded(httplib::Response& response, std::string detail) const;
    // 503 store_unavailable + Retry-After; marks the store down.
    void store_unavailable(httplib::Response& response, std::string detail);
    // Synchronous requests or work items on this replica (jobs queued in the store wait for
    // any replica and do not hold a drain).
    bool busy() const { return in_flight.load() > 0 || !pool.idle(); }
};

}  // namespace rollgap::service::http
