#pragma once
// Requests through the facade whose options must be refused: the test names the field (JSON
// pointer) and, where it matters, the bound and unit the problem details must carry.

#include <doctest/doctest.h>

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"

namespace rollgap::test {

// The field error at `pointer` in a problem, or null.
inline nlohmann::json error_at(const service::Outcome& outcome, const std::string& pointer) {
    for (const nlohmann::json& error : outcome.body.value("errors", nlohmann::json::array())) {
        if (error["pointer"] == pointer) return error;
    }
    return nullptr;
}

// Runs the analysis, checks it was refused as invalid options (422) and returns the field error
// at `pointer`.
inline nlohmann::json refused_options(const std::string& analysis, const nlohmann::json& options,
                                      const std::string& pointer,
                                      const nlohmann::json& scenario = nlohmann::json::object()) {
    CAPTURE(options.dump());
    const service::Outcome outcome =
        service::evaluate({{"analysis", analysis}, {"scenario", scenario}, {"options", options}});
    REQUIRE_FALSE(outcome.ok());
    CHECK(outcome.problem == api::ProblemCode::invalid_options);
    CHECK(outcome.http_status == 422);
    const nlohmann::json error = error_at(outcome, pointer);
    REQUIRE_MESSAGE(error.is_object(), outcome.body.dump());
    return error;
}

// As refused_options, and the error names this bound and unit (when given).
inline void check_refused_options(const std::string& analysis, const nlohmann::json& options,
                                  const std::string& pointer,
                                  const std::optional<std::string>& bound,
                                  const std::optional<std::string>& unit,
                                  const nlohmann::json& scenario = nlohmann::json::object()) {
    const nlohmann::json error = refused_options(analysis, options, pointer, scenario);
    if (bound) CHECK(error.value("bound", "") == *bound);
    if (unit) CHECK(error.value("unit", "") == *unit);
}

}  // namespace rollgap::test
