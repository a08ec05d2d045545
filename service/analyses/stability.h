#pragma once
// Analysis "stability": the eigenvalues of the coupled model linearised at the scenario's speed,
// the modes of the stack, and the critical speed over a speed range (docs/model.md §7.3).

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_stability(const core::Scenario& scenario, const nlohmann::json& options,
                                   const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
