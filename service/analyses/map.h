#pragma once
// Analysis "map": the critical speed, its frequency and chatter type over a grid of two numeric
// scenario fields, in parallel (docs/model.md, "Stability maps").

#include "service/analyses/analysis.h"

namespace rollgap::service {

// On the caller's thread budget (core::Control::threads); the result is the same for any count.
PreparedAnalysis prepare_map(const core::Scenario& scenario, const nlohmann::json& options,
                             const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
