#pragma once
// Rules that involve more than one scenario field (a field's own bounds are in the schema):
// tension below the flow stress, a sinusoidal tension that never goes slack or yields, a small
// bite angle, Rayleigh frequencies in order.

#include <span>
#include <string>

#include "api/field_errors.h"
#include "api/plant_units.h"
#include "core/scenario.h"

namespace rollgap::api {

// Checks `scenario` (already read field by field) and records violations under `pointer`.
// Rules whose inputs already failed their own bounds are skipped: one mistake, one error. A
// violation of a field the client gave in another unit (`given_as`: a tension as a force) is
// reported at the member given, with the bound in its unit.
void check_scenario_consistency(const core::Scenario& scenario, const std::string& pointer,
                                FieldErrors& errors, std::span<const GivenAs> given_as = {});

}  // namespace rollgap::api
