#pragma once
// Options and result of the analysis "calibrate" (docs/model.md §11): fit scenario fields to
// plant observations by weighted least squares.
//
// Options:
//   parameters      [{"field": "/strip/flow_stress_MPa",          the scenario field to fit
//                     "min": 300, "max": 500,                     optional, inside the field's own
//                                                                  bounds, in the field's unit
//                     "prior": {"value": 380,                     optional, in the field's unit
//                               "standard_uncertainty": 20}}]
//                   1 to max_calibration_parameters; the start is the request scenario's value
//   observations    [{"scenario": {...},   merge patch onto the request's scenario: the
//                                          conditions of the measurement (optional)
//                     "quantity": "roll_force_kN",   one of calibration_quantities below
//                     "value": 9100, "standard_uncertainty": 50,   in the quantity's unit
//                     "mode": {"index": 2} | {"near_frequency_Hz": 201}}]
//                                          natural_frequency_Hz and damping_ratio only: the
//                                          mode at the start values, then followed by shape
//                   1 to max_calibration_observations
//   max_iterations  30, [1, 100]
//   critical_speed  the search options of stability_json.h (relative_tolerance 1e-4)
//
// The work is bounded before anything runs: the fit evaluates all observations at most
// max_evaluations times (max_iterations × (parameters + 4) + 2 × parameters + 2), and each
// evaluation costs one critical-speed search per condition that needs one; the product may
// not exceed max_calibration_stability_evaluations.

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/result_table.h"
#include "api/scenario_schema.h"
#include "core/calibration_observables.h"
#include "core/scenario.h"

namespace rollgap::api {

inline constexpr int max_calibration_parameters = 12;
inline constexpr int max_calibration_observations = 200;
inline constexpr int max_calibration_iterations = 100;
// Linearisations of the coupled model over the whole fit (as a sweep's scan-point bound).
inline constexpr long max_calibration_stability_evaluations = 250'000;

struct CalibrationQuantity {
    std::string_view name;  // as in the request: "roll_force_kN"
    core::Observable observable;
    Unit unit;
    std::string_view title;  // what a label or a form calls it (the OpenAPI x-enum-descriptions)
};
const std::vector<CalibrationQuantity>& calibration_quantities();

// The continuous number field of the scenario a fit (or a posterior) names at `pointer`, or
// nullptr with the violation recorded (with the fields' list and a suggestion).
const ScenarioField* read_fitted_field(const nlohmann::json* value, const std::string& pointer,
                                       FieldErrors& errors);

struct CalibrationPlan {
    std::vector<const ScenarioField*> fields;  // one per parameter
    std::vector<std::string> quantity_names;   // one per observation
    std::vector<Unit> quantity_units;
    core::ScenarioCalibration setup;  // complete only for a valid request
    core::Scenario scenario;          // the request's (start values)
    long estimated_stability_evaluations = 0;
    nlohmann::json resolved_options;
};

// `valid_scenario` is the request's scenario if it passed validation, else nullptr (then the
// observation conditions and the start values are not checked).
CalibrationPlan calibration_plan_from_json(const nlohmann::json& options,
                                           const std::string& pointer,
                                           const core::Scenario* valid_scenario,
                                           FieldErrors& errors);

// The result document: status, iterations, parameters (value, standard error, bounds, prior),
// correlation, observations (predicted, normalised residual), chi-squared, degrees of freedom,
// warnings and the calibrated scenario as a merge patch onto the defaults.
nlohmann::json calibration_result_json(const CalibrationPlan& plan,
                                       const core::ScenarioCalibrationResult& result);

// The tables that write it (api/result_table.h): their OpenAPI components, and the scalar
// members of a parameter and of an observation (the CSV columns).
std::vector<ResultSchema> calibration_result_schemas();
std::vector<std::string> calibration_parameter_columns();
std::vector<std::string> calibration_observation_columns();

// RFC 7396 in reverse: the smallest merge patch that turns `from` into `to` (objects only;
// members of `from` missing in `to` become null).
nlohmann::json merge_patch_between(const nlohmann::json& from, const nlohmann::json& to);

}  // namespace rollgap::api
