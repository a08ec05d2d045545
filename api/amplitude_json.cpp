#include "api/amplitude_json.h"

#include <array>
#include <span>
#include <string_view>

#include "api/json_pointer.h"
#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/scenario_schema.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::string_view speeds_name = "speeds_m_per_s";
constexpr std::string_view window_name = "window_s";
constexpr std::string_view excitation_amplitude_name = "excitation_amplitude_MPa";
constexpr std::string_view excitation_frequency_name = "excitation_frequency_Hz";
constexpr std::string_view tolerance_name = "relative_tolerance";
constexpr std::string_view time_series_name = "time_series";
constexpr std::string_view time_series_points_name = "time_series_points";

constexpr std::array<std::string_view, 7> analysis_members{
    speeds_name, window_name, excitation_amplitude_name, excitation_frequency_name,
    tolerance_name, time_series_name, time_series_points_name};

std::span<const std::string_view> known_members(AmplitudeMembers members) {
    const std::span<const std::string_view> all(analysis_members);
    switch (members) {
        case AmplitudeMembers::analysis: return all;
        case AmplitudeMembers::single_run: return all.subspan(1);
        case AmplitudeMembers::sweep_point: return all.subspan(1, 4);
    }
    return all;
}

void read_speeds(const OptionsReader& reader, std::vector<double>& speeds) {
    const nlohmann::json* value = reader.find(speeds_name);
    if (value == nullptr) return;
    const std::string pointer = reader.at(speeds_name);
    if (!value->is_array()) {
        reader.errors().add({pointer, concat("must be an array of speeds, got ", json_type_name(*value)),
                             std::nullopt, std::nullopt});
        return;
    }
    const std::string count_bound = concat("1 to ", std::to_string(max_amplitude_speeds), " speeds");
    if (value->empty() || value->size() > static_cast<std::size_t>(max_amplitude_speeds)) {
        reader.errors().add({pointer,
                             concat("has ", std::to_string(value->size()), " speeds; give ", count_bound,
                                    " (each is a run of window_s simulated seconds)"),
                             count_bound, std::nullopt});
        return;
    }
    // A speed here is what /scenario/rolls/speed_m_per_s could be.
    const ScenarioField& speed_field = *find_scenario_field("/rolls/speed_m_per_s");
    std::vector<double> parsed;
    bool valid = true;
    for (std::size_t i = 0; i < value->size(); ++i) {
        const auto speed = read_number((*value)[i], append_pointer(pointer, std::to_string(i)), speed_field.range,
                                       speed_field.unit, reader.errors());
        if (speed) {
            parsed.push_back(to_si(*speed, speed_field.unit));
        } else {
            valid = false;
        }
    }
    if (valid) speeds = std::move(parsed);
}

bool figures_known(const core::AmplitudeResult& result) {
    if (result.status == core::AmplitudeStatus::no_steady_state || result.windows.empty()) return false;
    // As core: the amplitudes come from the last two complete 10 % windows.
    int complete = 0;
    for (const core::AmplitudeWindow& window : result.windows) {
        if (window.end <= result.end_time * (1.0 + 1e-9)) ++complete;
    }
    return complete >= 2;
}

bool ran(const core::AmplitudeResult& result) { return result.status != core::AmplitudeStatus::no_steady_state; }

}  // namespace

AmplitudeOptions amplitude_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                             AmplitudeMembers members, double scenario_speed, FieldErrors& errors) {
    AmplitudeOptions parsed;
    parsed.speeds = {scenario_speed};
    const OptionsReader reader(options, pointer, known_members(members), errors);
    if (members == AmplitudeMembers::analysis) read_speeds(reader, parsed.speeds);
    core::AmplitudeOptions& run = parsed.run;
    reader.number(window_name, units::second, open_closed(0.0, 20.0), run.window);
    reader.number(excitation_amplitude_name, units::megapascal, closed(0.0, 100.0), run.excitation_amplitude);
    reader.number(excitation_frequency_name, units::hertz, closed(0.0, 2000.0), run.excitation_frequency_Hz);
    reader.number(tolerance_name, units::one, closed(1e-9, 1e-3), run.relative_tolerance);
    if (members != AmplitudeMembers::sweep_point) {
        reader.boolean(time_series_name, run.time_series);
        reader.integer(time_series_points_name, closed(2.0, max_time_series_points), run.time_series_points);
    }
    return parsed;
}

nlohmann::json amplitude_options_json(const AmplitudeOptions& options, AmplitudeMembers members) {
    const core::AmplitudeOptions& run = options.run;
    nlohmann::json document = nlohmann::json::object();
    if (members == AmplitudeMembers::analysis) document[speeds_name] = quantities_json(options.speeds, units::metre_per_second);
    document[window_name] = from_si(run.window, units::second);
    document[excitation_amplitude_name] = from_si(run.excitation_amplitude, units::megapascal);
    document[excitation_frequency_name] = from_si(run.excitation_frequency_Hz, units::hertz);
    document[tolerance_name] = run.relative_tolerance;
    if (members != AmplitudeMembers::sweep_point) {
        document[time_series_name] = run.time_series;
        document[time_series_points_name] = run.time_series_points;
    }
    return document;
}

nlohmann::json amplitude_figures_json(const core::AmplitudeResult& result) {
    const bool known = figures_known(result);
    const auto figure = [known](double value_si, Unit unit) {
        return known ? quantity_json(value_si, unit) : nlohmann::json(nullptr);
    };
    return {
        {"status", core::to_string(result.status)},
        {"message", result.message != nullptr ? result.message : ""},
        {"excitation_frequency_Hz", ran(result) ? quantity_json(result.excitation_frequency_Hz, units::hertz) : nullptr},
        {"upper_roll_amplitude_um", figure(result.upper_roll, units::micrometre)},
        {"gap_amplitude_um", figure(result.gap, units::micrometre)},
        {"force_amplitude_kN", figure(result.force, units::kilonewton)},
        {"settled", known ? nlohmann::json(result.settled) : nlohmann::json(nullptr)},
        {"growth_rate_per_s", figure(result.growth_rate, units::per_second)},
        {"end_time_s", ran(result) ? quantity_json(result.end_time, units::second) : nullptr},
    };
}

nlohmann::json amplitude_result_json(const core::AmplitudeResult& result, bool with_time_series) {
    nlohmann::json body = amplitude_figures_json(result);
    body["speed_m_per_s"] = quantity_json(result.speed, units::metre_per_second);
    body["steady_status"] = core::to_string(result.steady_status);
    body["end_status"] = ran(result) ? nlohmann::json(core::to_string(result.end_status)) : nlohmann::json(nullptr);
    body["least_damped_growth_rate_per_s"] =
        ran(result) ? quantity_json(result.least_damped_growth_rate, units::per_second) : nullptr;
    nlohmann::json windows = nlohmann::json::array();
    for (const core::AmplitudeWindow& window : result.windows) {
        const bool sampled = window.start < result.end_time;  // a limit may end the run before it
        windows.push_back({
            {"start_s", quantity_json(window.start, units::second)},
            {"end_s", quantity_json(window.end, units::second)},
            {"upper_roll_amplitude_um", sampled ? quantity_json(window.upper_roll, units::micrometre) : nullptr},
        });
    }
    body["windows"] = std::move(windows);
    if (with_time_series) {
        body["time_series"] = {
            {"t_s", quantities_json(result.t, units::second)},
            {"x3_um", quantities_json(result.x3, units::micrometre)},
            {"gap_um", quantities_json(result.g, units::micrometre)},
            {"force_kN", quantities_json(result.dP, units::kilonewton)},
        };
    }
    return body;
}

}  // namespace rollgap::api
