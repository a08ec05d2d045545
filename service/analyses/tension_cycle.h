#pragma once
// Analysis "tension_cycle": roll-bite distributions at phases of a sinusoidal back-tension
// cycle, from the coupled model run over whole cycles (docs/model.md §7.2, the paper's Figs.
// 14-15).

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_tension_cycle(const core::Scenario& scenario,
                                       const nlohmann::json& options,
                                       const std::string& options_pointer,
                                       api::FieldErrors& errors);

}  // namespace rollgap::service
