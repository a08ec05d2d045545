#pragma once
// Running the evaluator on a compute worker, for synchronous requests and jobs alike: an
// escaping exception becomes the problem `internal`, and the metrics record how it ended.

#include <functional>

#include <nlohmann/json.hpp>

#include "api/problem.h"
#include "core/control.h"
#include "service/evaluate.h"
#include "service/http/service_state.h"

namespace rollgap::service::http {

// `late` and `cancelled_by_client` say, after it returned, why it may have been stopped.
Outcome compute(ServiceState& state, const nlohmann::json& request, const core::Control& control,
                const std::function<bool()>& late,
                const std::function<bool()>& cancelled_by_client);
// The same with another evaluator than the service's (a chunk of a sweep's points).
Outcome compute(ServiceState& state, const nlohmann::json& request, const core::Control& control,
                const std::function<bool()>& late, const std::function<bool()>& cancelled_by_client,
                const Evaluator& evaluator);

// A Control that stops when `stop` says so, with the configured thread budget.
core::Control control_for(const ServiceState& state, std::function<bool()> stop);

api::Problem deadline_problem(std::chrono::milliseconds budget);

}  // namespace rollgap::service::http
