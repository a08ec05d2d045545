#pragma once
// The facade: one request in, one outcome out. The CLI, the tests and the HTTP server all go
// through here, so they validate, compute and report errors identically.

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/problem.h"
#include "service/analysis.h"

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
Outcome evaluate(const nlohmann::json& request);

// The same against another table of analyses (tests: an analysis that throws).
Outcome evaluate(const nlohmann::json& request, std::span<const Analysis> offered);

// The same from request text: size limit, then JSON syntax (invalid_json), then evaluate().
Outcome evaluate_text(std::string_view text);

}  // namespace rollgap::service
