#pragma once
// Synchronous compute requests: a validated request is queued on the interactive lane and its
// connection thread waits for the outcome until the request's deadline (504). Every request
// that was queued gets a complete answer: a worker that takes it too late completes it at
// once, and at the drain timeout stop_all() answers every waiting request 503.

#include <functional>
#include <memory>
#include <mutex>
#include <set>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "service/evaluate.h"
#include "service/http/service_state.h"

namespace rollgap::service::http {

struct SyncCall;

class SyncDispatch {
public:
    explicit SyncDispatch(ServiceState& state) : state_(state) {}

    // Computes `ready`, what the facade's prepare() made of `request` on the connection thread,
    // on a worker (the service's evaluator is handed `request` instead when it is not the
    // facade: tests), and answers `http_request` as it asks (set_outcome: JSON or CSV).
    // `answer`, when given, answers a successful outcome instead (a stored stand's calibration
    // stores it first); problems are answered as always.
    using Answer = std::function<void(const Outcome& outcome, httplib::Response& response)>;
    void run(const httplib::Request& http_request, nlohmann::json request, PreparedRequest ready,
             SteadyClock::time_point arrival, httplib::Response& response,
             const Answer& answer = nullptr);

    // The drain timeout passed: every waiting request is answered 503 now, whatever its
    // computation does.
    void stop_all();

private:
    ServiceState& state_;
    std::mutex mutex_;
    std::set<std::shared_ptr<SyncCall>> waiting_;
};

}  // namespace rollgap::service::http
