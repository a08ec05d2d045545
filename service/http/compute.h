#pragma once
// Running an analysis on a compute worker, for synchronous requests and jobs alike: an
// escaping exception becomes the problem `internal` (service::guarded), and the metrics record
// how it ended.

#include <chrono>
#include <functional>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/problem.h"
#include "core/control.h"
#include "service/evaluate.h"
#include "service/http/service_state.h"

namespace rollgap::service::http {

// Why a computation stops or stopped: decided here, once, for synchronous requests
// (sync_dispatch), jobs (job_runner) and the metrics (compute). The facade cannot know the
// reason and answers `cancelled` for every one (evaluate.h); its caller asks this.
enum class StopReason {
    none,
    lease_lost,  // a job item's lease went to another replica: the result is not ours to store
    cancelled,   // the client cancelled the job (DELETE /v1/jobs/{id})
    shutdown,    // the drain timeout passed, or the drain answered a waiting request
    deadline,    // the request's or the job's deadline passed
    abandoned,   // the connection thread answered already (504 or 503) and left
};

// What the caller can see; each flag is one reason.
struct StopSignals {
    bool lease_lost = false;
    bool cancelled = false;
    bool shutdown = false;
    bool late = false;
    bool abandoned = false;
};

// The first reason in the order of StopReason: a lost lease makes everything else moot; a
// client's cancel beats the drain (the job ends cancelled instead of going to another replica);
// the drain beats a deadline (503, retry elsewhere, rather than 504).
StopReason stop_reason(const StopSignals& signals);

// Runs `work`, the computation of an analysis named `analysis` (the metrics label), on this
// worker under the one exception guard (service::guarded). `stopped` says, after it returned,
// why it may have been stopped.
Outcome compute(ServiceState& state, std::string_view analysis,
                const std::function<Outcome()>& work, const std::function<StopReason()>& stopped);
// A request as JSON by the service's evaluator: a job's stored request, prepared again on the
// replica that runs it (jobs run from stored JSON on any replica, DECISIONS R).
Outcome compute(ServiceState& state, const nlohmann::json& request, const core::Control& control,
                const std::function<StopReason()>& stopped);
// The same with another evaluator than the service's (a chunk of a sweep's points).
Outcome compute(ServiceState& state, const nlohmann::json& request, const core::Control& control,
                const std::function<StopReason()>& stopped, const Evaluator& evaluator);

// A Control that stops when `stop` says so, whose inner loops run on the process's one pool
// (state.pool) within the configured thread budget.
core::Control control_for(ServiceState& state, std::function<bool()> stop);

api::Problem deadline_problem(std::chrono::milliseconds budget);

}  // namespace rollgap::service::http
