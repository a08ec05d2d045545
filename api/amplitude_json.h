#pragma once
// Options and results of the vibration-amplitude analysis (docs/model.md §7.4): the analysis
// "amplitude", and the "amplitude" member of the options of "sweep" and "evaluate".
//
// Options (units in the names; defaults from core::AmplitudeOptions):
//   speeds_m_per_s             [scenario speed]  1 to max_amplitude_speeds speeds in [0.01, 100]
//                                                (analysis "amplitude" only)
//   window_s                   2      (0, 20], simulated time per speed
//   excitation_amplitude_MPa   1      [0, 100], added to the back tension the bite sees
//   excitation_frequency_Hz    0      [0, 2000]; 0: the least-damped eigenfrequency at each speed
//   relative_tolerance         1e-6   [1e-9, 1e-3], of the time integration
//   time_series                false  (not in sweeps) return the decimated x3, gap and force
//   time_series_points         2000   [2, 20000] (not in sweeps)

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/result_table.h"
#include "api/stability_json.h"
#include "core/amplitude.h"
#include "core/scenario.h"

namespace rollgap::api {

inline constexpr int max_amplitude_speeds = 64;
inline constexpr int max_time_series_points = 20000;

// Which members an amplitude options object has.
enum class AmplitudeMembers {
    analysis,     // everything, speeds_m_per_s included
    single_run,   // no speeds (evaluate: the scenario's speed)
    sweep_point,  // no speeds, no time series (a sweep reports figures per value)
};

struct AmplitudeOptions {
    std::vector<double> speeds;  // m/s; the scenario's speed unless given
    core::AmplitudeOptions run;
};

// `scenario_speed` (m/s) is the default of speeds_m_per_s.
AmplitudeOptions amplitude_options_from_json(const nlohmann::json& options,
                                             const std::string& pointer, AmplitudeMembers members,
                                             double scenario_speed, FieldErrors& errors);
nlohmann::json amplitude_options_json(const AmplitudeOptions& options, AmplitudeMembers members);

// One speed: {"speed_m_per_s", "status", "message", "steady_status", "end_status",
// "excitation_frequency_Hz", "upper_roll_amplitude_um", "gap_amplitude_um", "force_amplitude_kN",
// "settled", "growth_rate_per_s", "least_damped_growth_rate_per_s", "end_time_s",
// "windows": [{"start_s", "end_s", "upper_roll_amplitude_um"}] (detail full),
// "time_series": {"time_s", "upper_work_roll_displacement_um", "work_roll_gap_change_um",
// "roll_force_change_kN"} (only if asked for, detail full)}.
// Amplitudes are half peak-to-peak over the last complete 10 % window; they, "settled" and the
// growth rate are null when fewer than two 10 % windows completed (a physical limit ended the
// run early) or there is no steady state.
nlohmann::json amplitude_result_json(const core::AmplitudeResult& result, bool with_time_series,
                                     Detail detail = Detail::full);

struct AmplitudeView {
    const core::AmplitudeResult& result;
    bool time_series;
    Detail detail;
};

// The amplitude analysis' result: {"points": [one per speed]}.
struct AmplitudeRuns {
    const std::vector<core::AmplitudeResult>& results;
    bool time_series;
};

// The figures alone (the head of a point; a sweep point, with the excitation frequency under
// `frequency_name`): status, message, the frequency, the three amplitudes, settled,
// growth_rate_per_s, end_time_s.
std::vector<Member<core::AmplitudeResult>> amplitude_figure_members(
    std::string_view frequency_name);

struct AmplitudeWindowView {
    const core::AmplitudeWindow& window;
    double end_time;  // of the run: a window after it was not sampled
};

// The tables that write them (result_table.h) and their OpenAPI components.
const ResultTable<AmplitudeWindowView>& amplitude_window_table();
const ResultTable<core::AmplitudeResult>& time_series_table();
const ResultTable<AmplitudeView>& amplitude_point_table();
const ResultTable<AmplitudeRuns>& amplitude_result_table();
std::vector<ResultSchema> amplitude_result_schemas();

}  // namespace rollgap::api
