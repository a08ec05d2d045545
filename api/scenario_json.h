#pragma once
// The scenario document: engineering units in every field name (scenario_schema.h), read
// strictly into core::Scenario (SI) and written back for echoing.

#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "core/scenario.h"

namespace rollgap::api {

// core::Scenario{} in the document's units: the defaults live in core only.
nlohmann::json default_scenario_json();

// The complete document of a scenario; every result echoes it, so a result can be rerun.
nlohmann::json resolved_scenario_json(const core::Scenario& scenario);

// Strict read of a scenario document. Missing members keep core's defaults; unknown members,
// wrong types, non-finite numbers, values out of bounds and inconsistent combinations are
// recorded in `errors` under `pointer` (e.g. "/scenario"). The returned scenario is meaningful
// only if no error was recorded.
core::Scenario scenario_from_json(const nlohmann::json& document, const std::string& pointer,
                                  FieldErrors& errors);

// What a request's "scenario" means: an RFC 7396 merge patch onto the default document,
// then read strictly. `null` for a member restores its default.
core::Scenario scenario_from_patch(const nlohmann::json& patch, const std::string& pointer,
                                   FieldErrors& errors);

}  // namespace rollgap::api
