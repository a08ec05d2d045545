#pragma once
// Analysis "sweep": the critical speed or the vibration amplitude over the values of one
// numeric scenario field, in parallel (docs/model.md §7.5).

#include "service/analyses/analysis.h"

namespace rollgap::service {

// On the caller's thread budget (core::Control::threads; by default every hardware thread); the
// result is the same for any count (tests check it).
PreparedAnalysis prepare_sweep(const core::Scenario& scenario, const nlohmann::json& options,
                               const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
