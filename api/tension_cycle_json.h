#pragma once
// Options and results of the back-tension cycle analysis (docs/model.md §7.2, the paper's Figs.
// 14-15): the coupled model runs with the scenario's back tension as a sinusoid (its mean
// stress_MPa, amplitude_MPa and frequency_Hz, whatever its mode) and the roll bite is resolved
// at phases T of the last cycle, s_b = mean + amplitude sin(2 pi T).
//
// Options (defaults from core::TensionCycleOptions):
//   cycles              2                    [1, 20] whole cycles run; the first ones let the
//                                            start-up transient pass. cycles / frequency is at
//                                            most max_simulated_time_s.
//   phases              [0.25, 0.5, 0.75]    1 to max_phases distinct values in [0, 1)
//   relative_tolerance  1e-6                 [1e-9, 1e-3], of the time integration

#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/result_table.h"
#include "core/scenario.h"
#include "core/tension_cycle.h"

namespace rollgap::api {

inline constexpr int max_phases = 32;
// Simulated time of one run (also the bound of a sweep's total simulated time, sweep_json.h).
inline constexpr double max_simulated_time_s = 2000.0;

// `valid_scenario` is the scenario when it passed validation, else nullptr: rules that combine
// options with the scenario (the simulated time, the sinusoid's limits) need it.
core::TensionCycleOptions tension_cycle_options_from_json(const nlohmann::json& options,
                                                          const std::string& pointer,
                                                          const core::Scenario* valid_scenario,
                                                          FieldErrors& errors);
// Phases in ascending order, as they are run.
nlohmann::json tension_cycle_options_json(const core::TensionCycleOptions& options);

// The scenario rules for a sinusoidal back tension (never slack, below the flow stress), checked
// as if /scenario/tension/back/mode were "sinusoid": the analysis runs it so. Violations are
// recorded under `scenario_pointer` + the field's path.
void check_tension_cycle_scenario(const core::Scenario& scenario,
                                  const std::string& scenario_pointer, FieldErrors& errors);

// {"status", "message", "steady_status", "frequency_Hz", "phases": [{"phase", "time_s",
// "back_tension_MPa", "gap_um", "inlet_film_um", "roll_gap": <the roll_gap result>}]}.
// "status" is "ok", "no_steady_state" or what ended the run early (contact_lost, skidding,
// slack_strip, solver_failure): then only the phases reached are listed.
nlohmann::json tension_cycle_result_json(const core::TensionCycleResult& result);

// The tables that write it (result_table.h) and their OpenAPI components.
const ResultTable<core::PhaseDistribution>& tension_phase_table();
const ResultTable<core::TensionCycleResult>& tension_cycle_result_table();
std::vector<ResultSchema> tension_cycle_result_schemas();

}  // namespace rollgap::api
