#pragma once
// Analysis "evaluate": everything about the scenario at once — the roll gap, the stability at
// its speed, the critical speed and the vibration amplitude at its speed. What the HTTP service
// answers by default.

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_evaluation(const core::Scenario& scenario, const nlohmann::json& options,
                                    const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
