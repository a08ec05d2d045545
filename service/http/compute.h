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

// Runs `work`, the computation of an analysis named `analysis` (the metrics label), on this
// worker. `late` and `cancelled_by_client` say, after it returned, why it may have been stopped.
Outcome compute(ServiceState& state, std::string_view analysis,
                const std::function<Outcome()>& work, const std::function<bool()>& late,
                const std::function<bool()>& cancelled_by_client);
// A request as JSON by the service's evaluator: a job's stored request, prepared again on the
// replica that runs it (jobs run from stored JSON on any replica, DECISIONS R).
Outcome compute(ServiceState& state, const nlohmann::json& request, const core::Control& control,
                const std::function<bool()>& late,
                const std::function<bool()>& cancelled_by_client);
// The same with another evaluator than the service's (a chunk of a sweep's points).
Outcome compute(ServiceState& state, const nlohmann::json& request, const core::Control& control,
                const std::function<bool()>& late, const std::function<bool()>& cancelled_by_client,
                const Evaluator& evaluator);

// A Control that stops when `stop` says so, whose inner loops run on the process's one pool
// (state.pool) within the configured thread budget.
core::Control control_for(ServiceState& state, std::function<bool()> stop);

api::Problem deadline_problem(std::chrono::milliseconds budget);

}  // namespace rollgap::service::http
