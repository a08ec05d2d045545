#include "api/amplitude_json.h"

#include <array>
#include <span>
#include <string_view>

#include "api/json_pointer.h"
#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/result_table.h"
#include "api/scenario_schema.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::string_view speeds_name = "speeds_m_per_s";

constexpr std::array<std::string_view, 7> analysis_members{
    speeds_name,
    option_name(OptionId::window),
    option_name(OptionId::excitation_amplitude),
    option_name(OptionId::excitation_frequency),
    option_name(OptionId::integration_tolerance),
    option_name(OptionId::time_series),
    option_name(OptionId::time_series_points)};

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
        reader.errors().add({pointer,
                             concat("must be an array of speeds, got ", json_type_name(*value)),
                             std::nullopt, std::nullopt});
        return;
    }
    const std::string count_bound =
        concat("1 to ", std::to_string(max_amplitude_speeds), " speeds");
    if (value->empty() || value->size() > static_cast<std::size_t>(max_amplitude_speeds)) {
        reader.errors().add({pointer,
                             concat("has ", std::to_string(value->size()), " speeds; give ",
                                    count_bound, " (each is a run of window_s simulated seconds)"),
                             count_bound, std::nullopt});
        return;
    }
    // A speed here is what /scenario/rolls/speed_m_per_s could be.
    const ScenarioField& speed_field = *find_scenario_field("/rolls/speed_m_per_s");
    std::vector<double> parsed;
    bool valid = true;
    for (std::size_t i = 0; i < value->size(); ++i) {
        const auto speed = read_number((*value)[i], append_pointer(pointer, std::to_string(i)),
                                       speed_field.range, speed_field.unit, reader.errors());
        if (speed) {
            parsed.push_back(to_si(*speed, speed_field.unit));
        } else {
            valid = false;
        }
    }
    if (valid) speeds = std::move(parsed);
}

bool figures_known(const core::AmplitudeResult& result) {
    if (result.status == core::AmplitudeStatus::no_steady_state || result.windows.empty())
        return false;
    // As core: the amplitudes come from the last two complete 10 % windows.
    int complete = 0;
    for (const core::AmplitudeWindow& window : result.windows) {
        if (window.end <= result.end_time * (1.0 + 1e-9)) ++complete;
    }
    return complete >= 2;
}

bool ran(const core::AmplitudeResult& result) {
    return result.status != core::AmplitudeStatus::no_steady_state;
}

}  // namespace

AmplitudeOptions amplitude_options_from_json(const nlohmann::json& options,
                                             const std::string& pointer, AmplitudeMembers members,
                                             double scenario_speed, FieldErrors& errors) {
    AmplitudeOptions parsed;
    parsed.speeds = {scenario_speed};
    const OptionsReader reader(options, pointer, known_members(members), errors);
    if (members == AmplitudeMembers::analysis) read_speeds(reader, parsed.speeds);
    core::AmplitudeOptions& run = parsed.run;
    reader.read(OptionId::window, run.window);
    reader.read(OptionId::excitation_amplitude, run.excitation_amplitude);
    reader.read(OptionId::excitation_frequency, run.excitation_frequency_Hz);
    reader.read(OptionId::integration_tolerance, run.relative_tolerance);
    if (members != AmplitudeMembers::sweep_point) {
        reader.read(OptionId::time_series, run.time_series);
        reader.read(OptionId::time_series_points, run.time_series_points);
    }
    return parsed;
}

nlohmann::json amplitude_options_json(const AmplitudeOptions& options, AmplitudeMembers members) {
    const core::AmplitudeOptions& run = options.run;
    nlohmann::json document = nlohmann::json::object();
    if (members == AmplitudeMembers::analysis)
        document[speeds_name] = quantities_json(options.speeds, units::metre_per_second);
    put_option(document, OptionId::window, run.window);
    put_option(document, OptionId::excitation_amplitude, run.excitation_amplitude);
    put_option(document, OptionId::excitation_frequency, run.excitation_frequency_Hz);
    put_option(document, OptionId::integration_tolerance, run.relative_tolerance);
    if (members != AmplitudeMembers::sweep_point) {
        put_option(document, OptionId::time_series, run.time_series);
        put_option(document, OptionId::time_series_points, run.time_series_points);
    }
    return document;
}

namespace {

using core::AmplitudeResult;

// A figure of the last windows: null unless two 10 % windows completed.
Member<AmplitudeResult> figure_member(std::string_view name, std::string_view description,
                                      double AmplitudeResult::*member, Unit unit) {
    return {name, description, number_schema(unit), [member, unit](const AmplitudeResult& result) {
                return figures_known(result) ? quantity_json(result.*member, unit)
                                             : nlohmann::json(nullptr);
            }};
}

nlohmann::json dynamics_status_schema(bool nullable) {
    return enum_schema({"ok", "contact_lost", "skidding", "slack_strip", "solver_failure"},
                       nullable);
}

}  // namespace

const ResultTable<AmplitudeWindowView>& amplitude_window_table() {
    using Window = AmplitudeWindowView;
    static const ResultTable<Window> table{
        "AmplitudeWindow",
        "One of the ten 10 % windows of the run.",
        {
            {"start_s", "Start of the window.", number_schema(units::second),
             [](const Window& w) { return quantity_json(w.window.start, units::second); }},
            {"end_s", "End of the window.", number_schema(units::second),
             [](const Window& w) { return quantity_json(w.window.end, units::second); }},
            {"upper_roll_amplitude_um",
             "Half peak-to-peak displacement of the upper work roll (m3) in the window; null if a limit ended the "
             "run before it.",
             number_schema(units::micrometre),
             [](const Window& w) {
                 // A limit may end the run before the window.
                 return w.window.start < w.end_time
                            ? quantity_json(w.window.upper_roll, units::micrometre)
                            : nlohmann::json(nullptr);
             }},
        }};
    return table;
}

namespace {

Member<AmplitudeResult> series_member(std::string_view name, std::string_view description,
                                      std::vector<double> AmplitudeResult::*member, Unit unit) {
    return {name, description, array_schema(number_schema(unit)),
            [member, unit](const AmplitudeResult& result) {
                return quantities_json(result.*member, unit);
            }};
}

}  // namespace

std::vector<Member<core::AmplitudeResult>> amplitude_figure_members(
    std::string_view frequency_name) {
    return {
        {"status",
         "`settled`: the last two 10 % windows agree within 1 %. `growing` / `decaying`: they do not. "
         "`limit_reached`: the vibration slackened the strip, opened the gap or made the rolls skid (the figures "
         "are those of the window it happened in). `no_steady_state`: no steady bite to vibrate about. "
         "`solver_failure`: the integration failed.",
         enum_schema({"settled", "growing", "decaying", "limit_reached", "no_steady_state",
                      "solver_failure"}),
         [](const AmplitudeResult& r) { return nlohmann::json(core::to_string(r.status)); }},
        {"message", "Why, for humans; empty when settled.", string_schema(),
         [](const AmplitudeResult& r) {
             return nlohmann::json(r.message != nullptr ? r.message : "");
         }},
        {frequency_name, "The excitation frequency (the least-damped mode's unless given).",
         number_schema(units::hertz),
         [](const AmplitudeResult& r) {
             return ran(r) ? quantity_json(r.excitation_frequency_Hz, units::hertz)
                           : nlohmann::json(nullptr);
         }},
        figure_member("upper_roll_amplitude_um",
                      "Half peak-to-peak displacement of the upper work roll (m3).",
                      &AmplitudeResult::upper_roll, units::micrometre),
        figure_member("gap_amplitude_um",
                      "Half peak-to-peak change of the work-roll gap (m3 − m4).",
                      &AmplitudeResult::gap, units::micrometre),
        figure_member("force_amplitude_kN", "Half peak-to-peak change of the roll force.",
                      &AmplitudeResult::force, units::kilonewton),
        {"settled", "Whether the last two 10 % windows agree within 1 %.", boolean_schema(true),
         [](const AmplitudeResult& r) {
             return figures_known(r) ? nlohmann::json(r.settled) : nlohmann::json(nullptr);
         }},
        figure_member("growth_rate_per_s",
                      "Growth rate of the amplitude from the last two 10 % windows.",
                      &AmplitudeResult::growth_rate, units::per_second),
        {"end_time_s", "Simulated time: the window unless a limit ended the run.",
         number_schema(units::second),
         [](const AmplitudeResult& r) {
             return ran(r) ? quantity_json(r.end_time, units::second) : nlohmann::json(nullptr);
         }},
    };
}

const ResultTable<core::AmplitudeResult>& time_series_table() {
    static const ResultTable<AmplitudeResult> table{
        "AmplitudeTimeSeries",
        "The run, decimated to options.time_series_points samples, columnar (arrays of equal length).",
        {
            series_member("time_s", "Simulated time.", &AmplitudeResult::t, units::second),
            series_member(
                "upper_work_roll_displacement_um",
                "Displacement of the upper work roll (m3, x3) from its steady position, upward positive.",
                &AmplitudeResult::x3, units::micrometre),
            series_member(
                "work_roll_gap_change_um",
                "Change of the gap between the work rolls (x3 − x4) from its steady value.",
                &AmplitudeResult::g, units::micrometre),
            series_member("roll_force_change_kN", "Change of the roll force from its steady value.",
                          &AmplitudeResult::force_change, units::kilonewton),
        }};
    return table;
}

const ResultTable<AmplitudeView>& amplitude_point_table() {
    static const ResultTable<AmplitudeView> table{
        "AmplitudePoint",
        "The vibration at one speed. Amplitudes are half peak-to-peak over the last complete 10 % window; they, "
        "`settled` and the growth rate are null when fewer than two 10 % windows completed or there is no steady "
        "state.",
        [] {
            std::vector<Member<AmplitudeView>> members = lift<AmplitudeView>(
                amplitude_figure_members("excitation_frequency_Hz"),
                [](const AmplitudeView& v) -> const AmplitudeResult& { return v.result; });
            const std::vector<Member<AmplitudeView>> more{
                {"speed_m_per_s", "The roll speed.", number_schema(units::metre_per_second),
                 [](const AmplitudeView& v) {
                     return quantity_json(v.result.speed, units::metre_per_second);
                 }},
                {"steady_status", "The status of the steady bite at this speed.",
                 enum_schema({"ok", "skidding", "contact_lost", "solver_failure"}),
                 [](const AmplitudeView& v) {
                     return nlohmann::json(core::to_string(v.result.steady_status));
                 }},
                {"end_status",
                 "What ended the run (`ok`: the window did); null without a steady state.",
                 dynamics_status_schema(true),
                 [](const AmplitudeView& v) {
                     return ran(v.result) ? nlohmann::json(core::to_string(v.result.end_status))
                                          : nlohmann::json(nullptr);
                 }},
                {"least_damped_growth_rate_per_s",
                 "Real part of the least-damped eigenvalue at this speed.",
                 number_schema(units::per_second),
                 [](const AmplitudeView& v) {
                     return ran(v.result) ? quantity_json(v.result.least_damped_growth_rate,
                                                          units::per_second)
                                          : nlohmann::json(nullptr);
                 }},
                {"windows", "The ten 10 % windows (options.detail \"full\" only).",
                 array_schema(ref_schema("AmplitudeWindow")),
                 [](const AmplitudeView& v) {
                     if (v.detail == Detail::summary) return absent();
                     nlohmann::json windows = nlohmann::json::array();
                     for (const core::AmplitudeWindow& window : v.result.windows) {
                         windows.push_back(
                             amplitude_window_table().write({window, v.result.end_time}));
                     }
                     return windows;
                 },
                 true},
                {"time_series",
                 "Present when options.time_series is true (and detail is \"full\").",
                 ref_schema("AmplitudeTimeSeries"),
                 [](const AmplitudeView& v) {
                     return v.time_series && v.detail == Detail::full
                                ? time_series_table().write(v.result)
                                : absent();
                 },
                 true},
            };
            members.insert(members.end(), more.begin(), more.end());
            return members;
        }()};
    return table;
}

const ResultTable<AmplitudeRuns>& amplitude_result_table() {
    static const ResultTable<AmplitudeRuns> table{
        "AmplitudeResult",
        "The vibration amplitude under a back-tension excitation, per speed (docs/model.md §7.4).",
        {
            {"points", "One per speed of options.speeds_m_per_s, in that order.",
             array_schema(ref_schema("AmplitudePoint")),
             [](const AmplitudeRuns& runs) {
                 nlohmann::json points = nlohmann::json::array();
                 for (const AmplitudeResult& result : runs.results) {
                     points.push_back(
                         amplitude_point_table().write({result, runs.time_series, Detail::full}));
                 }
                 return points;
             }},
        }};
    return table;
}

std::vector<ResultSchema> amplitude_result_schemas() {
    return {result_schema(amplitude_window_table()), result_schema(time_series_table()),
            result_schema(amplitude_point_table()), result_schema(amplitude_result_table())};
}

nlohmann::json amplitude_result_json(const core::AmplitudeResult& result, bool with_time_series,
                                     Detail detail) {
    return amplitude_point_table().write({result, with_time_series, detail});
}

}  // namespace rollgap::api
