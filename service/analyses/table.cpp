#include "service/analyses/table.h"

#include <algorithm>
#include <array>
#include <string_view>
#include <vector>

#include "api/amplitude_json.h"
#include "api/calibration_json.h"
#include "api/csv.h"
#include "api/evaluation_json.h"
#include "api/field_errors.h"
#include "api/map_json.h"
#include "api/result_json.h"
#include "api/speed_limit_json.h"
#include "api/batch_json.h"
#include "api/stability_json.h"
#include "api/sweep_json.h"
#include "api/tandem_result_json.h"
#include "api/tandem_map_json.h"
#include "api/tandem_speed_limit_json.h"
#include "api/tandem_sweep_json.h"
#include "api/tension_cycle_json.h"
#include "api/name_suggestion.h"
#include "api/text.h"

#include "service/analyses/amplitude.h"
#include "service/analyses/calibration.h"
#include "service/analyses/evaluation.h"
#include "service/analyses/map.h"
#include "service/analyses/roll_gap.h"
#include "service/analyses/speed_limit.h"
#include "service/analyses/batch.h"
#include "service/analyses/stability.h"
#include "service/analyses/sweep.h"
#include "service/analyses/tandem.h"
#include "service/analyses/tandem_map.h"
#include "service/analyses/tandem_speed_limit.h"
#include "service/analyses/tandem_sweep.h"
#include "service/analyses/tension_cycle.h"

namespace rollgap::service {
namespace {

using std::string_view_literals::operator""sv;

// The options schemas given defaults from core, and the option members whose defaults depend on
// the request, of each analysis.
constexpr std::array<OptionsDefaults, 1> roll_gap_defaults{{{"RollGapOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 1> tension_cycle_defaults{{{"TensionCycleOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 1> stability_defaults{{{"StabilityOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 1> amplitude_defaults{{{"AmplitudeOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 2> sweep_defaults{{
    {"SweepOptions", R"({"parameter": "/strip/reduction", "values": [0.3]})"},
    {"SweepAmplitudeOptions",
     R"({"parameter": "/rolls/speed_m_per_s", "values": [19], "quantity": "amplitude"})",
     "amplitude"},
}};
constexpr std::array<OptionsDefaults, 1> map_defaults{{
    {"MapOptions", R"({"parameters": [{"parameter": "/strip/reduction", "values": [0.15]},
                        {"parameter": "/strip/entry_thickness_mm", "values": [1.6]}]})"},
}};
constexpr std::array<OptionsDefaults, 1> speed_limit_defaults{{{"SpeedLimitOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 1> tandem_defaults{{{"TandemOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 1> tandem_sweep_defaults{{
    {"TandemSweepOptions", R"({"parameter": "/spans/length_m/0", "values": [5]})"},
}};
constexpr std::array<OptionsDefaults, 1> tandem_map_defaults{{
    {"TandemMapOptions", R"({"parameters": [{"parameter": "/spans/length_m/0", "values": [5]},
                               {"parameter": "/spans/tension_MPa/0", "values": [60]}]})"},
}};
constexpr std::array<OptionsDefaults, 1> tandem_speed_limit_defaults{
    {{"TandemSpeedLimitOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 1> evaluation_defaults{{{"EvaluateOptions", "{}"}}};
constexpr std::array<OptionsDefaults, 1> calibration_defaults{{
    {"CalibrateOptions",
     R"({"parameters": [{"field": "/strip/flow_stress_MPa"}],
         "observations": [{"quantity": "roll_force_kN", "value": 9000, "standard_uncertainty": 50}]})"},
}};

constexpr std::array<std::string_view, 0> no_names{};
constexpr std::array speeds_option{"speeds_m_per_s"sv};
constexpr std::array sweep_request_options{"parameter"sv, "values"sv, "range"sv,
                                           "speeds_m_per_s"sv};
constexpr std::array map_request_options{"parameters"sv};
constexpr std::array tandem_sweep_request_options{"parameter"sv, "values"sv, "range"sv};
constexpr std::array tandem_map_request_options{"parameters"sv};
constexpr std::array calibration_request_options{"parameters"sv, "observations"sv};
// one entry per stand of the request's mill
constexpr std::array tandem_speed_limit_request_options{"stands"sv};

// The result components a point of a pointwise analysis can be (api/sweep_json.h, map_json.h).
constexpr std::array sweep_points{"SweepCriticalSpeedPoint"sv, "SweepAmplitudePoint"sv};
constexpr std::array map_points{"MapCell"sv};
constexpr std::array tandem_sweep_points{"TandemSweepCriticalSpeedPoint"sv,
                                         "TandemSweepStabilityPoint"sv};
constexpr std::array tandem_map_points{"TandemMapCriticalSpeedCell"sv, "TandemMapStabilityCell"sv};
constexpr std::array batch_points{"BatchItem"sv};

const std::array table{
    Analysis{"roll_gap", "Roll gap",
             "steady roll-bite pressure, friction and film distributions (docs/model.md §7.1)",
             &prepare_roll_gap, "/v1/roll-gap", "RollGapResponse", "RollGapOptions",
             "RollGapResult", &api::bite_result_schemas, roll_gap_defaults, no_names,
             &api::roll_gap_csv_tables},
    Analysis{"tension_cycle", "Tension cycle",
             "distributions at phases of a sinusoidal back-tension cycle (docs/model.md §7.2)",
             &prepare_tension_cycle, "/v1/tension-cycle", "TensionCycleResponse",
             "TensionCycleOptions", "TensionCycleResult", &api::tension_cycle_result_schemas,
             tension_cycle_defaults, no_names, &api::tension_cycle_csv_tables},
    Analysis{
        "stability", "Stability",
        "eigenvalues and modes at the scenario's speed, critical chatter speed (docs/model.md §7.3)",
        &prepare_stability, "/v1/stability", "StabilityResponse", "StabilityOptions",
        "StabilityResult", &api::stability_result_schemas, stability_defaults, no_names,
        &api::stability_csv_tables},
    Analysis{"amplitude", "Amplitude",
             "vibration amplitude under a back-tension excitation, per speed (docs/model.md §7.4)",
             &prepare_amplitude, "/v1/amplitude", "AmplitudeResponse", "AmplitudeOptions",
             "AmplitudeResult", &api::amplitude_result_schemas, amplitude_defaults, speeds_option,
             &api::amplitude_csv_tables},
    Analysis{
        "sweep", "Sweep",
        "critical speed or amplitude over the values of one scenario field (docs/model.md §7.5)",
        &prepare_sweep, "/v1/sweeps", "SweepResponse", "SweepOptions", "SweepResult",
        &api::sweep_result_schemas, sweep_defaults, sweep_request_options, &api::sweep_csv_tables,
        sweep_points},
    Analysis{"map", "Map",
             "critical speed, frequency and chatter type over a grid of two scenario fields "
             "(docs/model.md, \"Stability maps\")",
             &prepare_map, "/v1/maps", "MapResponse", "MapOptions", "MapResult",
             &api::map_result_schemas, map_defaults, map_request_options, &api::map_csv_tables,
             map_points},
    Analysis{"evaluate",
             "Evaluation",
             "roll gap, stability, critical speed and amplitude of the scenario at once",
             &prepare_evaluation,
             "/v1/evaluate",
             "EvaluateResponse",
             "EvaluateOptions",
             "EvaluateResult",
             &api::evaluation_result_schemas,
             evaluation_defaults,
             speeds_option,
             nullptr,
             {},
             false},
    Analysis{
        "calibrate", "Calibration",
        "fit scenario fields to plant observations, weighted least squares (docs/model.md §11)",
        &prepare_calibration, "/v1/calibrate", "CalibrateResponse", "CalibrateOptions",
        "CalibrationResult", &api::calibration_result_schemas, calibration_defaults,
        calibration_request_options, &api::calibration_csv_tables},
    Analysis{"speed_limit", "Speed limit",
             "the speeds the stand may run at under the plant's limits (force, torque, power, "
             "skid, chatter with its uncertainty), the binding limit and the margins "
             "(docs/model.md §13)",
             &prepare_speed_limit, "/v1/speed-limit", "SpeedLimitResponse", "SpeedLimitOptions",
             "SpeedLimitResult", &api::speed_limit_result_schemas, speed_limit_defaults, no_names,
             &api::speed_limit_csv_tables},
    Analysis{"tandem",
             "Tandem mill",
             "a tandem mill at its speed: pass schedule, stability by stand and the three "
             "critical mill speeds (docs/model.md §12)",
             nullptr,
             "/v1/tandem",
             "TandemResponse",
             "TandemOptions",
             "TandemResult",
             &api::tandem_result_schemas,
             tandem_defaults,
             no_names,
             &api::tandem_csv_tables,
             {},
             true,
             &prepare_tandem},
    Analysis{"tandem_sweep", "Mill sweep",
             "a tandem mill's critical speeds or its stability over the values of one of its "
             "fields: a stand's field, a span length, a tension set point, the schedule "
             "(docs/model.md §12.10)",
             nullptr, "/v1/tandem/sweeps", "TandemSweepResponse", "TandemSweepOptions",
             "TandemSweepResult", &api::tandem_sweep_result_schemas, tandem_sweep_defaults,
             tandem_sweep_request_options, &api::tandem_sweep_csv_tables, tandem_sweep_points,
             false, &prepare_tandem_sweep},
    Analysis{"tandem_map", "Mill map",
             "a tandem mill's critical speeds or its stability over a grid of two numbers of its "
             "document (docs/model.md §12.10)",
             nullptr, "/v1/tandem/maps", "TandemMapResponse", "TandemMapOptions", "TandemMapResult",
             &api::tandem_map_result_schemas, tandem_map_defaults, tandem_map_request_options,
             &api::tandem_map_csv_tables, tandem_map_points, false, &prepare_tandem_map},
    Analysis{"tandem_speed_limit",
             "Mill speed limit",
             "the mill speeds a tandem mill may run at under the plant's limits per stand "
             "(force, torque, power, skid) and its chatter limit, the binding limit with its "
             "stand and the margins (docs/model.md §13.5)",
             nullptr,
             "/v1/tandem/speed-limit",
             "TandemSpeedLimitResponse",
             "TandemSpeedLimitOptions",
             "TandemSpeedLimitResult",
             &api::tandem_speed_limit_result_schemas,
             tandem_speed_limit_defaults,
             tandem_speed_limit_request_options,
             &api::tandem_speed_limit_csv_tables,
             {},
             true,
             &prepare_tandem_speed_limit},
    // Last: its items may be any row above that runs whole.
    Analysis{"batch",
             "Batch",
             "many requests of one analysis (typically a speed limit per coil) as one job: one "
             "headline row per item, an item's problem its own (docs/http-api.md, \"Batches\")",
             nullptr,
             "/v1/batches",
             "BatchResponse",
             "BatchOptions",
             "BatchResult",
             &api::batch_result_schemas,
             {},
             no_names,
             &api::batch_csv_tables,
             batch_points,
             false,
             nullptr,
             &prepare_batch},
};

}  // namespace

std::span<const Analysis> analyses() { return table; }

const Analysis* find_analysis(std::span<const Analysis> offered, std::string_view name) {
    const auto row = std::find_if(offered.begin(), offered.end(), [name](const Analysis& analysis) {
        return analysis.name == name;
    });
    return row == offered.end() ? nullptr : &*row;
}

api::Problem unknown_analysis_problem(std::span<const Analysis> offered, std::string_view name) {
    std::vector<std::string_view> names;
    for (const Analysis& row : offered) names.push_back(row.name);
    return api::make_problem(api::ProblemCode::unknown_analysis,
                             api::concat("no analysis named ", api::quoted_for_message(name)),
                             {{"/analysis",
                               api::concat("unknown analysis ", api::quoted_for_message(name),
                                           api::did_you_mean(name, names)),
                               api::choices_text(names), std::nullopt}});
}

}  // namespace rollgap::service
