#pragma once
// The facade: one request in, one outcome out. The CLI, the tests and the HTTP server all go
// through here, so they validate, compute and report errors identically.

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <variant>

#include <nlohmann/json.hpp>

#include "api/problem.h"
#include "api/request_json.h"
#include "core/control.h"
#include "api/tandem_json.h"
#include "core/mill/mill.h"
#include "service/analyses/analysis.h"

namespace rollgap::service {

// Larger requests are refused before parsing. Scenarios are ~2 kB; sweeps list at most
// thousands of values.
inline constexpr std::size_t max_request_bytes = 1024 * 1024;

// How a computed answer came out, typed, so that callers (the metrics) need not read its JSON.
// `solver_failure`: the result, or one of its parts (a stability analysis's steady state),
// reports that its solver did not converge; the answer is still a 200 with that status.
enum class ResultStatus { ok, solver_failure };

struct Outcome {
    int http_status = 200;
    nlohmann::json body;                      // the result document, or the problem details
    std::optional<api::ProblemCode> problem;  // set iff `body` is a problem
    ResultStatus status = ResultStatus::ok;   // of a result; a problem leaves it ok

    bool ok() const { return !problem.has_value(); }
    std::string_view media_type() const;  // application/json or application/problem+json
};

Outcome problem_outcome(const api::Problem& problem);

// {"analysis": "roll_gap", "scenario": {...merge patch...}, "options": {...}} →
// {"analysis", "scenario": <resolved>, "options": <resolved>, "result": {...}} or a problem.
// Never throws: an exception inside an analysis becomes the problem `internal` (and is logged).
//
// `control` reaches every core computation of the analysis:
// - control.cancelled() is polled between units of work (scan speeds, sweep points, output
//   times of a time integration), from the calling thread and from worker threads at once, so
//   it must be thread-safe and cheap (an atomic flag, a clock read). Once it returns true the
//   analysis stops within one unit of work and evaluate() returns the problem `cancelled`
//   (409). The facade cannot know why: a caller whose reason is a deadline replaces it with
//   `deadline_exceeded` (504), e.g.
//       Outcome outcome = evaluate(request, control);
//       if (outcome.problem == api::ProblemCode::cancelled && deadline_passed())
//           outcome = problem_outcome(api::make_problem(api::ProblemCode::deadline_exceeded,
//           "..."));
//   Validation problems are returned as usual whatever the Control says; a Control that is
//   already cancelled when the request is valid gives `cancelled` without computing.
// - control.progress(fraction) reports 0..1 as core computes; it too may be called from
//   several threads at once, not necessarily in increasing order (keep the largest). Not every
//   analysis reports (roll_gap is a single fast solve).
// The default Control never cancels and reports nowhere (the CLI).
Outcome evaluate(const nlohmann::json& request, const core::Control& control = {});

// The same against another table of analyses (tests: an analysis that throws).
Outcome evaluate(const nlohmann::json& request, std::span<const Analysis> offered,
                 const core::Control& control = {});

// Only the envelope: a JSON object of bounded depth with the envelope's fields, naming an
// analysis that is offered. What a job submission checks before it asks the store for a
// "base"; prepare() checks the rest once "base" is resolved.
std::optional<Outcome> check_envelope(const nlohmann::json& request);

// The same from request text: size limit, then JSON syntax (invalid_json), then evaluate().
Outcome evaluate_text(std::string_view text, const core::Control& control = {});

// A valid request, ready to compute.
struct PreparedRequest {
    const Analysis* analysis = nullptr;
    std::optional<api::ScenarioBase> base;  // the stored scenario it was resolved onto, echoed
    core::Scenario scenario;                // a stand's analysis: the scenario
    std::optional<core::Mill> mill;         // a mill's analysis (Subject::mill): the mill, echoed
    api::StandBases stand_bases;            // its stands' stored bases, echoed in each stand
    PreparedAnalysis prepared;
    // Values outside their field's typical plant range, echoed as the answer's `warnings`
    // (api/plant_units.h); an empty array when there are none.
    nlohmann::json warnings = nlohmann::json::array();
};

// evaluate() in its two steps, for callers that check a request in one place and compute it in
// another: the HTTP server prepares on its connection thread (a cheap 422 never waits behind
// computations for a worker) and hands the prepared request to a worker, so the request is
// prepared once; the CLI uses the same two steps. evaluate(request, control) is exactly
// run(prepare(request), control). Neither throws: an exception becomes the problem `internal`.
//
// prepare: everything evaluate() checks before it computes (envelope, analysis, scenario,
// options), never a computation; the problem of an invalid request, or the prepared request.
std::variant<Outcome, PreparedRequest> prepare(const nlohmann::json& request);
// Rewrites every scenario and tandem document of `request` to canonical keys and units (plant
// units, api/plant_units.h), in place; a 422 when a member is given twice or not as a number.
// The HTTP layer calls it before it merges a stored base; prepare() does it itself too.
std::optional<Outcome> canonicalise_units(nlohmann::json& request);
// The same from request text: size limit, then JSON syntax (invalid_json), then prepare().
std::variant<Outcome, PreparedRequest> prepare_text(std::string_view text);
// run: computes a prepared request under `control` (as evaluate() documents it).
Outcome run(PreparedRequest ready, const core::Control& control = {});
// Either step's result handed to run: the problem as it is, or the prepared request computed.
Outcome run(std::variant<Outcome, PreparedRequest> prepared, const core::Control& control = {});

// The parts of the steps, for facades that run a request in parts (service/chunked.h) and
// must answer exactly as evaluate() does.
// Validation as evaluate() does it: the problem of an invalid request, or the prepared request.
std::variant<Outcome, PreparedRequest> prepare_request(const nlohmann::json& request,
                                                       std::span<const Analysis> offered);
// The answer with `result` as its "result" member (moves the resolved options out of `ready`),
// its ResultStatus read from `result` as the analysis wrote it.
Outcome result_outcome(PreparedRequest& ready, nlohmann::json result);
// The problem `cancelled`, as evaluate() reports a stopped analysis.
Outcome cancelled_outcome();

// The one exception guard of the service: `work()`, or, when an exception escapes it, the problem
// `internal` (the exception logged with `context`, e.g. "request 7f3a"). `work` returns an
// Outcome or anything made from one (std::optional<Outcome>, the variant prepare() returns).
// The facade, the HTTP handlers and the workers all answer an exception through it.
Outcome internal_outcome(std::string_view context, std::string_view what);
template <class Work>
auto guarded(Work&& work, std::string_view context = "a request") -> decltype(work()) {
    try {
        return std::forward<Work>(work)();
    } catch (const std::exception& error) {
        return internal_outcome(context, error.what());
    } catch (...) {
        return internal_outcome(context, "a non-standard exception");
    }
}

}  // namespace rollgap::service
