#pragma once
// Analysis "calibrate": fit scenario fields to plant observations by weighted nonlinear least
// squares (docs/model.md §11).

#include "service/analyses/analysis.h"

namespace rollgap::service {

// The Jacobian's columns spread over the caller's thread budget (core::Control::threads); the
// result does not depend on it. Progress goes up by iterations of the fit.
PreparedAnalysis prepare_calibration(const core::Scenario& scenario, const nlohmann::json& options,
                                     const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
