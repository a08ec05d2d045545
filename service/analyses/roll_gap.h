#pragma once
// Analysis "roll_gap": the steady roll bite of the scenario (docs/model.md §7.1).

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_roll_gap(const core::Scenario& scenario, const nlohmann::json& options,
                                  const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
