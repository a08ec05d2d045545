#pragma once
// Rules that involve more than one scenario field (a field's own bounds are in the schema):
// tension below the flow stress, a sinusoidal tension that never goes slack or yields, a small
// bite angle, Rayleigh frequencies in order.

#include <string>

#include "api/field_errors.h"
#include "core/scenario.h"

namespace rollgap::api {

// Checks `scenario` (already read field by field) and records violations under `pointer`.
// Rules whose inputs already failed their own bounds are skipped: one mistake, one error.
void check_scenario_consistency(const core::Scenario& scenario, const std::string& pointer,
                                FieldErrors& errors);

}  // namespace rollgap::api
