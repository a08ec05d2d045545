#pragma once
// Options and results of a sweep (docs/model.md §7.5): one numeric scenario field over a list or a
// range of values, the critical speed or the vibration amplitude at each.
//
// Options:
//   parameter       required: the JSON pointer of a numeric field of the scenario, in the
//                   scenario's own names and units, e.g. "/lubricant/viscosity_Pa_s"
//   values          [v0, v1, ...], 1 to max_sweep_points values      } exactly one of
//   range           {"from", "to", "count"}, count in [2, 1000]      } values and range
//                   (from + (to − from)·i/(count − 1), i = 0..count − 1)
//   quantity        "critical_speed" (default) | "amplitude"
//   critical_speed  the search options of stability_json.h (quantity critical_speed only)
//   amplitude       the run options of amplitude_json.h, without speeds and time series
//                   (quantity amplitude only; the speed is the scenario's or the swept one)
//
// Every value is set into the request's scenario and read through the same validation as a
// scenario (field bounds and cross-field rules), so a value the scenario could not have is a
// problem at /options/values/<i> (or /options/range/from, /to, or /options/range for a point
// in between) with the field's bound and unit.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/options_reader.h"
#include "api/result_table.h"
#include "api/scenario_schema.h"
#include "core/amplitude.h"
#include "core/scenario.h"
#include "core/stability.h"

namespace rollgap::api {

inline constexpr int max_sweep_points = 1000;
// Work bounds of one sweep: simulated seconds over all values (amplitude), scan speeds over all
// values (critical speed; the default search is 119 speeds, 1000 values fit).
inline constexpr double max_sweep_simulated_time_s = 2000.0;
inline constexpr long max_sweep_scan_points = 250'000;

enum class SweepQuantity { critical_speed, amplitude };

struct SweepPlan {
    const ScenarioField* field = nullptr;   // the swept field
    std::vector<double> values;             // in the field's unit, as the client wrote them
    std::vector<core::Scenario> scenarios;  // one per value; filled only for a valid request
    SweepQuantity quantity = SweepQuantity::critical_speed;
    core::CriticalSpeedOptions critical_speed;
    core::AmplitudeOptions amplitude;
    nlohmann::json resolved_options;  // the echo
};

// `valid_scenario` is the request's scenario if it passed validation, else nullptr (then the
// values are not checked against it and no scenarios are built).
SweepPlan sweep_plan_from_json(const nlohmann::json& options, const std::string& pointer,
                               const core::Scenario* valid_scenario, FieldErrors& errors);

// One swept field with its values, read as a sweep reads them: the object {"parameter", "values"
// | "range"} at `pointer` (a map's axes). Values and scenarios are filled only for a valid
// request; `resolved` is the echo.
struct SweepAxis {
    const ScenarioField* field = nullptr;
    std::vector<double> values;             // in the field's unit
    std::vector<core::Scenario> scenarios;  // the request's scenario with this field at each value
    nlohmann::json resolved;
};
SweepAxis sweep_axis_from_json(const nlohmann::json& axis, const std::string& pointer,
                               const core::Scenario* valid_scenario, FieldErrors& errors);

// One sweep point before validation: the JSON value and where a violation of it is reported.
struct SweepPoint {
    nlohmann::json value;
    std::string pointer;
    std::optional<std::size_t> range_index;  // for a point inside a range: its index
};

// The points as the client gave them in `reader`'s "values" or "range" (1 to max_points), or
// nothing with the violation recorded; `echo_values` gets {"values"} or {"range"}. Shared by
// the sweeps of a stand and of a mill (api/tandem_sweep_json.h).
std::optional<std::vector<SweepPoint>> read_sweep_points(const OptionsReader& reader,
                                                         nlohmann::json& echo_values,
                                                         int max_points);

// The swept value's member in the points: "value_" and the unit in a name's spelling
// ("value_Pa_s", "value_per_MPa", "value_m_per_s"); dimensionless: "value".
std::string sweep_value_name(Unit unit);

// A point's schema: a point table's members and the swept value under its value_name.
nlohmann::json sweep_point_schema(nlohmann::json schema);

// Sets a numeric field to `value`, in the field's unit (already validated).
void set_scenario_field(core::Scenario& scenario, const ScenarioField& field, double value);

// The sweep's result as written: the points carry the swept value under value_name.
struct SweepOutput {
    std::string_view parameter;
    std::string_view unit;
    std::string value_name;
    std::string_view quantity;
    nlohmann::json points;
    nlohmann::json chatter_type_changes;  // absent() unless the points are critical speeds
};
const ResultTable<SweepOutput>& sweep_result_table();
std::vector<ResultSchema> sweep_result_schemas();
// The members of a point besides the value, in order (the CSV columns).
std::vector<std::string> sweep_point_columns(bool amplitude);

// {"parameter", "unit", "value_name", "quantity", "points": [{"value_<unit>", "status",
// "critical_speed_m_per_s", "frequency_Hz", "chatter_type", "chatter_band"}],
// "chatter_type_changes": [...]}: the critical speed and the frequency and chatter type of the mode
// that goes unstable there (null unless found; the mode also for unstable_at_lower_bound); the
// changes (api/chatter_json.h) name each pair of consecutive values whose crossing modes differ in
// type.
nlohmann::json sweep_critical_speed_json(const SweepPlan& plan,
                                         const std::vector<core::CriticalSpeedResult>& results);

// The same with amplitude points: {"value_<unit>", "status", "message", "frequency_Hz" (of the
// excitation), "upper_roll_amplitude_um", "gap_amplitude_um", "force_amplitude_kN", "settled",
// "growth_rate_per_s", "end_time_s"}.
nlohmann::json sweep_amplitude_json(const SweepPlan& plan,
                                    const std::vector<core::AmplitudeResult>& results);

// The two above in two steps, so that points computed apart (the chunks of a job, on any
// replica) assemble into exactly the document one run writes: both functions above are these
// two steps.
// The documents of the points first, first + 1, ... (one per result), as "points" lists them.
nlohmann::json sweep_critical_speed_points_json(
    const SweepPlan& plan, const std::vector<core::CriticalSpeedResult>& results,
    std::size_t first);
nlohmann::json sweep_amplitude_points_json(const SweepPlan& plan,
                                           const std::vector<core::AmplitudeResult>& results,
                                           std::size_t first);
// The result from all points' documents in order (one per value); chatter_type_changes
// (quantity critical_speed) from the documents' chatter types.
nlohmann::json sweep_result_json(const SweepPlan& plan, nlohmann::json points);

}  // namespace rollgap::api
