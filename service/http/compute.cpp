#include "service/http/compute.h"

#include <string_view>

#include <spdlog/spdlog.h>

#include "api/text.h"
#include "service/analyses/table.h"

namespace rollgap::service::http {
namespace {

using nlohmann::json;

std::string_view analysis_label(const json& request) {
    const auto name = request.find("analysis");
    if (name == request.end() || !name->is_string()) return "unknown";
    const Analysis* analysis = find_analysis(analyses(), name->get_ref<const std::string&>());
    return analysis == nullptr ? std::string_view("unknown") : analysis->name;
}

}  // namespace

core::Control control_for(ServiceState& state, std::function<bool()> stop) {
    core::Control control;
    control.executor = &state.pool;
    control.threads = static_cast<int>(state.config.analysis_threads);
    control.cancelled = std::move(stop);
    return control;
}

api::Problem deadline_problem(std::chrono::milliseconds budget) {
    return api::make_problem(
        api::ProblemCode::deadline_exceeded,
        api::concat("the analysis did not finish within ", std::to_string(budget.count()),
                    " ms and was stopped; run it as a job (POST /v1/jobs) for a longer budget"));
}

StopReason stop_reason(const StopSignals& signals) {
    if (signals.lease_lost) return StopReason::lease_lost;
    if (signals.cancelled) return StopReason::cancelled;
    if (signals.shutdown) return StopReason::shutdown;
    if (signals.late) return StopReason::deadline;
    if (signals.abandoned) return StopReason::abandoned;
    return StopReason::none;
}

Outcome compute(ServiceState& state, const json& request, const core::Control& control,
                const std::function<StopReason()>& stopped) {
    return compute(state, request, control, stopped, state.evaluator);
}

Outcome compute(ServiceState& state, const json& request, const core::Control& control,
                const std::function<StopReason()>& stopped, const Evaluator& evaluator) {
    return compute(
        state, analysis_label(request), [&] { return evaluator(request, control); }, stopped);
}

Outcome compute(ServiceState& state, std::string_view analysis,
                const std::function<Outcome()>& work, const std::function<StopReason()>& stopped) {
    const auto start = SteadyClock::now();
    Outcome outcome = guarded(work, analysis);
    const double seconds = std::chrono::duration<double>(SteadyClock::now() - start).count();

    std::string_view label = "succeeded";
    const StopReason reason = stopped();
    if (reason == StopReason::cancelled) {
        label = "cancelled";
    } else if (reason == StopReason::shutdown || reason == StopReason::deadline) {
        label = "deadline_exceeded";
    } else if (outcome.ok()) {
        if (outcome.status == ResultStatus::solver_failure)
            state.metrics.count_solver_failure(analysis, "solver_failure");
    } else if (outcome.problem == api::ProblemCode::deadline_exceeded) {
        label = "deadline_exceeded";
    } else if (outcome.problem == api::ProblemCode::cancelled) {
        label = "cancelled";
    } else if (outcome.http_status >= 500) {
        label = "failed";
        state.metrics.count_solver_failure(analysis, "internal");
    } else {
        label = "rejected";
    }
    state.metrics.observe_analysis(analysis, label, seconds);
    return outcome;
}

}  // namespace rollgap::service::http
