#include "service/evaluate.h"

#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <spdlog/spdlog.h>

#include "api/field_errors.h"
#include "api/json_text.h"
#include "api/request_json.h"
#include "api/scenario_json.h"
#include "api/text.h"
#include "service/analyses/table.h"

namespace rollgap::service {
namespace {

Outcome internal_error(std::string_view what) {
    spdlog::error("internal error while evaluating a request: {}", what);
    return problem_outcome(
        api::make_problem(api::ProblemCode::internal,
                          "the analysis failed unexpectedly; the service log has the cause"));
}

// The request's envelope is valid and names an offered analysis.
struct Envelope {
    api::AnalysisRequest parsed;
    const Analysis* analysis = nullptr;
};

std::variant<Outcome, Envelope> check_envelope_of(const nlohmann::json& request,
                                                  std::span<const Analysis> offered) {
    // Everything below walks the request recursively; text input was bounded by the parser
    // already, this covers JSON built in code.
    if (api::nests_deeper_than(request, api::max_json_depth)) {
        return problem_outcome(
            api::make_problem(api::ProblemCode::invalid_request,
                              api::concat("request nests deeper than ",
                                          std::to_string(api::max_json_depth), " levels")));
    }

    api::FieldErrors envelope_errors;
    Envelope envelope;
    envelope.parsed = api::analysis_request_from_json(request, envelope_errors);
    if (!envelope_errors.empty()) {
        return problem_outcome(envelope_errors.to_problem(api::ProblemCode::invalid_request,
                                                          "the request envelope is invalid"));
    }

    envelope.analysis = find_analysis(offered, envelope.parsed.analysis);
    if (envelope.analysis == nullptr) {
        return problem_outcome(unknown_analysis_problem(offered, envelope.parsed.analysis));
    }
    return envelope;
}

}  // namespace

std::variant<Outcome, PreparedRequest> prepare_request(const nlohmann::json& request,
                                                       std::span<const Analysis> offered) {
    auto checked = check_envelope_of(request, offered);
    if (auto* problem = std::get_if<Outcome>(&checked)) return std::move(*problem);
    const Envelope& envelope = std::get<Envelope>(checked);
    if (envelope.parsed.unresolved_base) {
        // Only the HTTP service has the store; it resolves "base" before it calls the facade.
        return problem_outcome(api::make_problem(
            api::ProblemCode::invalid_request,
            "stored scenarios need the service: \"base\" names a scenario stored with "
            "PUT /v1/scenarios/{name}",
            {{"/base",
              api::concat("stored scenarios need the service (rollgap serve); here send the "
                          "scenario itself, e.g. the body of GET /v1/scenarios/",
                          *envelope.parsed.unresolved_base, ", as \"scenario\""),
              std::nullopt, std::nullopt}}));
    }

    // Scenario and options violations are reported together.
    api::FieldErrors errors;
    PreparedRequest ready;
    ready.analysis = envelope.analysis;
    ready.base = envelope.parsed.base;
    ready.scenario = api::scenario_from_patch(envelope.parsed.scenario_patch, "/scenario", errors);
    ready.prepared =
        envelope.analysis->prepare(ready.scenario, envelope.parsed.options, "/options", errors);
    // An analysis may add scenario violations of its own (tension_cycle: the sinusoid's limits).
    const bool scenario_valid = !errors.has_error_at_or_below("/scenario");
    if (!errors.empty()) {
        const std::string detail = api::concat(
            std::to_string(errors.size()), errors.size() == 1 ? " violation" : " violations",
            scenario_valid ? " in the options" : " in the scenario and options");
        return problem_outcome(errors.to_problem(
            scenario_valid ? api::ProblemCode::invalid_options : api::ProblemCode::invalid_scenario,
            detail));
    }
    return ready;
}

Outcome cancelled_outcome() {
    return problem_outcome(api::make_problem(
        api::ProblemCode::cancelled, "the analysis was stopped by its caller before it finished"));
}

Outcome result_outcome(PreparedRequest& ready, nlohmann::json result) {
    Outcome outcome;
    outcome.body = {
        {"analysis", ready.analysis->name},
        {"scenario", api::resolved_scenario_json(ready.scenario)},
        {"options", std::move(ready.prepared.resolved_options)},
        {"result", std::move(result)},
    };
    if (ready.base) outcome.body["base"] = api::scenario_base_json(*ready.base);
    return outcome;
}

namespace {

Outcome evaluate_unguarded(const nlohmann::json& request, std::span<const Analysis> offered,
                           const core::Control& control) {
    auto prepared = prepare_request(request, offered);
    if (auto* problem = std::get_if<Outcome>(&prepared)) return std::move(*problem);
    PreparedRequest& ready = std::get<PreparedRequest>(prepared);

    if (control.should_stop()) return cancelled_outcome();  // e.g. the deadline passed while queued
    nlohmann::json result;
    try {
        result = ready.prepared.run(control);
    } catch (const AnalysisCancelled&) {
        return cancelled_outcome();
    }
    control.report(1.0);  // not every analysis reports its own end
    return result_outcome(ready, std::move(result));
}

// Runs `check` and turns an escaping exception into the problem `internal`.
template <class Check>
std::optional<Outcome> guarded_check(Check check) {
    try {
        return check();
    } catch (const std::exception& error) {
        return internal_error(error.what());
    } catch (...) {
        return internal_error("a non-standard exception");
    }
}

}  // namespace

std::string_view Outcome::media_type() const {
    return ok() ? std::string_view("application/json") : api::problem_media_type;
}

Outcome problem_outcome(const api::Problem& problem) {
    Outcome outcome;
    outcome.http_status = problem.http_status();
    outcome.body = api::problem_json(problem);
    outcome.problem = problem.code;
    return outcome;
}

Outcome evaluate(const nlohmann::json& request, const core::Control& control) {
    return evaluate(request, analyses(), control);
}

Outcome guarded(const std::function<Outcome()>& compute) {
    try {
        return compute();
    } catch (const std::exception& error) {
        return internal_error(error.what());
    } catch (...) {
        return internal_error("a non-standard exception");
    }
}

Outcome evaluate(const nlohmann::json& request, std::span<const Analysis> offered,
                 const core::Control& control) {
    return guarded([&] { return evaluate_unguarded(request, offered, control); });
}

std::optional<Outcome> check_envelope(const nlohmann::json& request) {
    return guarded_check([&]() -> std::optional<Outcome> {
        auto checked = check_envelope_of(request, analyses());
        if (auto* problem = std::get_if<Outcome>(&checked)) return std::move(*problem);
        return std::nullopt;
    });
}

std::optional<Outcome> validate(const nlohmann::json& request) {
    return guarded_check([&]() -> std::optional<Outcome> {
        auto prepared = prepare_request(request, analyses());
        if (auto* problem = std::get_if<Outcome>(&prepared)) return std::move(*problem);
        return std::nullopt;
    });
}

Outcome evaluate_text(std::string_view text, const core::Control& control) {
    return guarded([&] {
        if (text.size() > max_request_bytes) {
            return problem_outcome(api::make_problem(
                api::ProblemCode::payload_too_large,
                api::concat("the request has ", std::to_string(text.size()),
                            " bytes; the limit is ", std::to_string(max_request_bytes))));
        }
        auto parsed = api::parse_json_text(text);
        if (auto* problem = std::get_if<api::Problem>(&parsed)) return problem_outcome(*problem);
        return evaluate(std::get<nlohmann::json>(parsed), control);
    });
}

}  // namespace rollgap::service
