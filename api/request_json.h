#pragma once
// The request envelope: {"analysis": "roll_gap", "base": "stand-3", "scenario": {...merge
// patch...}, "options": {...}}, or for a mill {"analysis": "tandem", "tandem": {...}, ...}. Only
// its shape is checked here; the analysis name, scenario and options are read by the service once
// it knows which analysis runs.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"

namespace rollgap::api {

// The names of stored scenarios (PUT /v1/scenarios/{name}, a request's "base").
inline constexpr std::string_view stored_scenario_name_pattern =
    "^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$";
// The built-in default (GET /v1/scenarios/default): never stored, never a base.
inline constexpr std::string_view reserved_scenario_name = "default";
bool is_stored_scenario_name(std::string_view name);

// The stored scenario a request's patch was merged onto, echoed in its result.
struct ScenarioBase {
    std::string name;
    std::int64_t version = 0;
};

struct AnalysisRequest {
    std::string analysis;
    nlohmann::json scenario_patch = nlohmann::json::object();  // absent or null: the default
    nlohmann::json options = nlohmann::json::object();         // absent or null: the defaults
    // "tandem": the mill's merge patch (docs/model.md §12.8), for the analyses of a mill; set
    // iff the request has a non-null "tandem".
    std::optional<nlohmann::json> tandem_patch;
    // "base": "<name>" as a client sends it: only the service, which has the store, can resolve
    // it (it then rewrites the request to the resolved form below).
    std::optional<std::string> unresolved_base;
    // "base": {"name", "version"}: the scenario patch was already merged onto that stored
    // scenario (a resolved request, e.g. a job's stored request, is self-contained).
    std::optional<ScenarioBase> base;
};

// Violations are recorded under the root pointer ("/analysis", "/extra_field", ...).
AnalysisRequest analysis_request_from_json(const nlohmann::json& request, FieldErrors& errors);

// {"name": ..., "version": ...}: the resolved form of "base", as echoed in results.
nlohmann::json scenario_base_json(const ScenarioBase& base);
// The resolved {"name", "version"} form (an object) at `pointer`: nullopt when incomplete.
std::optional<ScenarioBase> read_resolved_base(const nlohmann::json& base,
                                               const std::string& pointer, FieldErrors& errors);

// The violation of a name that is not a stored scenario's name (pattern or `default`), at
// `pointer`; nothing if it is one.
std::optional<FieldError> stored_scenario_name_error(std::string_view name,
                                                     const std::string& pointer);

}  // namespace rollgap::api
