#pragma once
// The request envelope: {"analysis": "roll_gap", "scenario": {...merge patch...}, "options":
// {...}}. Only its shape is checked here; the analysis name, scenario and options are read by the
// service once it knows which analysis runs.

#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"

namespace rollgap::api {

struct AnalysisRequest {
    std::string analysis;
    nlohmann::json scenario_patch = nlohmann::json::object();  // absent or null: the default
    nlohmann::json options = nlohmann::json::object();         // absent or null: the defaults
};

// Violations are recorded under the root pointer ("/analysis", "/extra_field", ...).
AnalysisRequest analysis_request_from_json(const nlohmann::json& request, FieldErrors& errors);

}  // namespace rollgap::api
