#pragma once
// Options of the roll_gap analysis: {"distributions": true}.

#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "core/roll_bite.h"

namespace rollgap::api {

// Strict read; a missing member keeps its default, violations go to `errors` under `pointer`.
core::BiteOptions bite_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                         FieldErrors& errors);

// The options as applied, echoed with the result.
nlohmann::json bite_options_json(const core::BiteOptions& options);

}  // namespace rollgap::api
