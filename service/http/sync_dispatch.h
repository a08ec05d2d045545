#pragma once
// Synchronous compute requests: a validated request is queued on the interactive lane and its
// connection thread waits for the outcome until the request's deadline (504). Every request
// that was queued gets a complete answer: a worker that takes it too late completes it at
// once, and at the drain timeout stop_all() answers every waiting request 503.

#include <memory>
#include <mutex>
#include <set>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "service/http/service_state.h"

namespace rollgap::service::http {

struct SyncCall;

class SyncDispatch {
public:
    explicit SyncDispatch(ServiceState& state) : state_(state) {}

    // Computes `request` (valid: the facade's validate() found nothing) and answers.
    void run(nlohmann::json request, SteadyClock::time_point arrival, httplib::Response& response);

    // The drain timeout passed: every waiting request is answered 503 now, whatever its
    // computation does.
    void stop_all();

private:
    ServiceState& state_;
    std::mutex mutex_;
    std::set<std::shared_ptr<SyncCall>> waiting_;
};

}  // namespace rollgap::service::http
