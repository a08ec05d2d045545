#pragma once
// What an analysis is to the facade: a name and a function that reads its options and returns
// the computation to run. Reading is separate from running so that every violation of the
// scenario and of the options is reported together, before any physics runs, and so that a
// server can queue the computation with a deadline.

#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "core/scenario.h"

namespace rollgap::service {

struct PreparedAnalysis {
    nlohmann::json resolved_options;       // the options as applied, echoed with the result
    std::function<nlohmann::json()> run;   // computes the "result" member; may take a while
};

// Reads `options` strictly (violations under `options_pointer`) and captures what `run` needs.
// Must not compute: `scenario` may be invalid when errors were recorded.
using PrepareAnalysis = PreparedAnalysis (*)(const core::Scenario& scenario, const nlohmann::json& options,
                                             const std::string& options_pointer, api::FieldErrors& errors);

struct Analysis {
    std::string_view name;     // the request's "analysis"
    std::string_view summary;  // one line for --help and the documentation
    PrepareAnalysis prepare;
};

}  // namespace rollgap::service
