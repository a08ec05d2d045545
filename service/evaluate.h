#pragma once
// The facade: one request in, one outcome out. The CLI, the tests and the HTTP server all go
// through here, so they validate, compute and report errors identically.

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "api/problem.h"
#include "api/request_json.h"
#include "core/control.h"
#include "service/analyses/analysis.h"

namespace rollgap::service {

// Larger requests are refused before parsing. Scenarios are ~2 kB; sweeps list at most
// thousands of values.
inline constexpr std::size_t max_request_bytes = 1024 * 1024;

struct Outcome {
    int http_status = 200;
    nlohmann::json body;                      // the result document, or the problem details
    std::optional<api::ProblemCode> problem;  // set iff `body` is a problem

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

// What evaluate() checks before it computes, without computing: the problem of an invalid
// request, or nothing when evaluate() would compute. The HTTP server validates on its
// connection threads, so that a cheap 422 never waits behind computations for a worker.
std::optional<Outcome> validate(const nlohmann::json& request);

// Only the envelope: a JSON object of bounded depth with the envelope's fields, naming an
// analysis that is offered. What a job needs at submission; its scenario and options are
// checked when it runs and a violation fails the job.
std::optional<Outcome> check_envelope(const nlohmann::json& request);

// The same from request text: size limit, then JSON syntax (invalid_json), then evaluate().
Outcome evaluate_text(std::string_view text, const core::Control& control = {});

// The steps of evaluate(), for facades that run a request in parts (service/chunked.h) and
// must answer exactly as evaluate() does.
// A valid request, ready to compute.
struct PreparedRequest {
    const Analysis* analysis = nullptr;
    std::optional<api::ScenarioBase> base;  // the stored scenario it was resolved onto, echoed
    core::Scenario scenario;
    PreparedAnalysis prepared;
};
// Validation as evaluate() does it: the problem of an invalid request, or the prepared request.
std::variant<Outcome, PreparedRequest> prepare_request(const nlohmann::json& request,
                                                       std::span<const Analysis> offered);
// The answer with `result` as its "result" member (moves the resolved options out of `ready`).
Outcome result_outcome(PreparedRequest& ready, nlohmann::json result);
// The problem `cancelled`, as evaluate() reports a stopped analysis.
Outcome cancelled_outcome();
// `compute()`, with an escaping exception turned into the problem `internal` (and logged).
Outcome guarded(const std::function<Outcome()>& compute);

}  // namespace rollgap::service
