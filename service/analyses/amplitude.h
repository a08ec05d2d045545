#pragma once
// Analysis "amplitude": the vibration amplitude of the nonlinear coupled model under a
// back-tension excitation, at one or more speeds (docs/model.md §7.4).

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_amplitude(const core::Scenario& scenario, const nlohmann::json& options,
                                   const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
