#include "service/evaluate.h"

#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <spdlog/spdlog.h>

#include "api/field_errors.h"
#include "api/plant_units.h"
#include "api/json_text.h"
#include "api/request_json.h"
#include "api/scenario_json.h"
#include "api/tandem_json.h"
#include "api/text.h"
#include "service/analyses/table.h"

namespace rollgap::service {
namespace {

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
    // A batch has no subject of its own: its items carry theirs (in its options).
    if (envelope.analysis->subject() == Subject::batch) {
        for (const char* member : {"scenario", "tandem", "base"}) {
            if (!request.contains(member) || request.at(member).is_null()) continue;
            envelope_errors.add(
                {api::concat("/", member),
                 api::concat("a batch gives \"", member, "\" in its options: /options/", member,
                             " for every item, /options/items/N/", member, " for one"),
                 std::nullopt, std::nullopt});
        }
        if (!envelope_errors.empty()) {
            return problem_outcome(envelope_errors.to_problem(api::ProblemCode::invalid_request,
                                                              "the request envelope is invalid"));
        }
        return envelope;
    }
    // A stand's analysis takes "scenario", a mill's "tandem" (docs/model.md §12.8).
    const bool of_mill = envelope.analysis->subject() == Subject::mill;
    const bool has_scenario = request.contains("scenario") && !request.at("scenario").is_null();
    if (of_mill ? has_scenario : envelope.parsed.tandem_patch.has_value()) {
        const std::string name(envelope.analysis->name);
        envelope_errors.add(
            of_mill ? api::FieldError{"/scenario",
                                      api::concat("\"", name,
                                                  "\" analyses a tandem mill: send the mill as "
                                                  "\"tandem\" (each stand's scenario patch in "
                                                  "/tandem/stands, shared ones in "
                                                  "/tandem/stand_defaults)"),
                                      std::nullopt, std::nullopt}
                    : api::FieldError{"/tandem",
                                      api::concat("\"", name,
                                                  "\" analyses one stand, given as "
                                                  "\"scenario\"; a tandem mill is analysed by "
                                                  "\"tandem\""),
                                      std::nullopt, std::nullopt});
        return problem_outcome(envelope_errors.to_problem(api::ProblemCode::invalid_request,
                                                          "the request envelope is invalid"));
    }
    return envelope;
}

}  // namespace

std::variant<Outcome, PreparedRequest> prepare_request(const nlohmann::json& request,
                                                       std::span<const Analysis> offered) {
    auto checked = check_envelope_of(request, offered);
    if (auto* problem = std::get_if<Outcome>(&checked)) return std::move(*problem);
    Envelope& envelope = std::get<Envelope>(checked);
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
    const bool of_mill = envelope.analysis->subject() == Subject::mill;
    const bool of_batch = envelope.analysis->subject() == Subject::batch;
    const std::string subject_pointer = of_mill ? "/tandem" : "/scenario";
    // Plant units (api/plant_units.h): every document this request carries in canonical keys
    // before anything reads or merges it; the HTTP layer did so already, before it merged a
    // stored base (then this finds nothing to do).
    api::canonicalise_scenario_patch(envelope.parsed.scenario_patch, "/scenario", errors);
    if (envelope.parsed.tandem_patch)
        api::canonicalise_tandem_patch(*envelope.parsed.tandem_patch, "/tandem", errors);
    api::canonicalise_request_units(envelope.parsed.options, "/options", errors);
    if (of_batch) {
        ready.prepared = envelope.analysis->prepare_batch(std::move(envelope.parsed.options),
                                                          "/options", errors);
    } else if (of_mill) {
        ready.mill =
            api::mill_from_patch(envelope.parsed.tandem_patch.value_or(nlohmann::json::object()),
                                 "/tandem", errors, &ready.stand_bases);
        ready.prepared = envelope.analysis->prepare_mill(*ready.mill, envelope.parsed.options,
                                                         "/options", errors);
    } else {
        ready.scenario =
            api::scenario_from_patch(envelope.parsed.scenario_patch, "/scenario", errors);
        ready.prepared =
            envelope.analysis->prepare(ready.scenario, envelope.parsed.options, "/options", errors);
    }
    // An analysis may add scenario violations of its own (tension_cycle: the sinusoid's limits).
    const bool scenario_valid = !errors.has_error_at_or_below(subject_pointer) &&
                                !errors.has_error_at_or_below("/scenario");
    if (!errors.empty()) {
        const std::string detail = api::concat(
            std::to_string(errors.size()), errors.size() == 1 ? " violation" : " violations",
            scenario_valid
                ? " in the options"
                : (of_mill ? " in the mill and options" : " in the scenario and options"));
        return problem_outcome(errors.to_problem(
            scenario_valid ? api::ProblemCode::invalid_options : api::ProblemCode::invalid_scenario,
            detail));
    }
    // Values a cold mill does not have, likely a unit slip: accepted, and said (plant units).
    if (of_mill) {
        ready.warnings = api::typical_range_warnings(*ready.mill, "/tandem");
    } else if (!of_batch) {
        ready.warnings = api::typical_range_warnings(ready.scenario, "/scenario");
    }
    return ready;
}

Outcome cancelled_outcome() {
    return problem_outcome(api::make_problem(
        api::ProblemCode::cancelled, "the analysis was stopped by its caller before it finished"));
}

namespace {

// The analyses write their status into the result document (api/*_json.cpp: "status" of the
// result, or of one of its parts); it is read once, here where the result is made.
ResultStatus status_of(const nlohmann::json& result) {
    if (!result.is_object()) return ResultStatus::ok;
    const auto failed = [](const nlohmann::json& object) {
        const auto status = object.find("status");
        return status != object.end() && status->is_string() && *status == "solver_failure";
    };
    if (failed(result)) return ResultStatus::solver_failure;
    for (const nlohmann::json& member : result) {
        if (member.is_object() && failed(member)) return ResultStatus::solver_failure;
    }
    return ResultStatus::ok;
}

}  // namespace

Outcome result_outcome(PreparedRequest& ready, nlohmann::json result) {
    Outcome outcome;
    outcome.status = status_of(result);
    outcome.body = {
        {"analysis", ready.analysis->name},
        {"options", std::move(ready.prepared.resolved_options)},
        {"result", std::move(result)},
    };
    // The subject echoed, so the answer can be rerun; a batch's items are in its options.
    if (ready.analysis->subject() != Subject::batch) {
        outcome.body[ready.mill ? "tandem" : "scenario"] =
            ready.mill ? api::resolved_tandem_json(*ready.mill, &ready.stand_bases)
                       : api::resolved_scenario_json(ready.scenario);
    }
    if (ready.base) outcome.body["base"] = api::scenario_base_json(*ready.base);
    if (ready.warnings.is_array() && !ready.warnings.empty())
        outcome.body["warnings"] = std::move(ready.warnings);
    return outcome;
}

namespace {

Outcome run_unguarded(PreparedRequest& ready, const core::Control& control) {
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

Outcome internal_outcome(std::string_view context, std::string_view what) {
    spdlog::error("internal error in {}: {}", context, what);
    return problem_outcome(
        api::make_problem(api::ProblemCode::internal,
                          "the request failed unexpectedly; the service log has the cause"));
}

Outcome evaluate(const nlohmann::json& request, std::span<const Analysis> offered,
                 const core::Control& control) {
    return run(guarded([&] { return prepare_request(request, offered); }), control);
}

std::variant<Outcome, PreparedRequest> prepare(const nlohmann::json& request) {
    return guarded([&] { return prepare_request(request, analyses()); });
}

std::variant<Outcome, PreparedRequest> prepare_text(std::string_view text) {
    return guarded([&]() -> std::variant<Outcome, PreparedRequest> {
        if (text.size() > max_request_bytes) {
            return problem_outcome(api::make_problem(
                api::ProblemCode::payload_too_large,
                api::concat("the request has ", std::to_string(text.size()),
                            " bytes; the limit is ", std::to_string(max_request_bytes))));
        }
        auto parsed = api::parse_json_text(text);
        if (auto* problem = std::get_if<api::Problem>(&parsed)) return problem_outcome(*problem);
        return prepare(std::get<nlohmann::json>(parsed));
    });
}

Outcome run(PreparedRequest ready, const core::Control& control) {
    return guarded([&] { return run_unguarded(ready, control); });
}

Outcome run(std::variant<Outcome, PreparedRequest> prepared, const core::Control& control) {
    if (auto* problem = std::get_if<Outcome>(&prepared)) return std::move(*problem);
    return run(std::move(std::get<PreparedRequest>(prepared)), control);
}

std::optional<Outcome> canonicalise_units(nlohmann::json& request) {
    return guarded([&]() -> std::optional<Outcome> {
        api::FieldErrors errors;
        api::canonicalise_request_units(request, "", errors);
        if (errors.empty()) return std::nullopt;
        return problem_outcome(errors.to_problem(
            api::ProblemCode::invalid_request,
            api::concat(std::to_string(errors.size()), " violation", errors.size() == 1 ? "" : "s",
                        " in the request's plant units")));
    });
}

std::optional<Outcome> check_envelope(const nlohmann::json& request) {
    return guarded([&]() -> std::optional<Outcome> {
        auto checked = check_envelope_of(request, analyses());
        if (auto* problem = std::get_if<Outcome>(&checked)) return std::move(*problem);
        return std::nullopt;
    });
}

Outcome evaluate_text(std::string_view text, const core::Control& control) {
    return run(prepare_text(text), control);
}

}  // namespace rollgap::service
