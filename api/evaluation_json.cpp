#include "api/option_names.h"
#include "api/evaluation_json.h"

#include <array>
#include <string_view>

#include "api/options_reader.h"
#include "api/result_json.h"
#include "api/result_table.h"
#include "api/stability_json.h"

namespace rollgap::api {
namespace {

constexpr std::array<std::string_view, 3> evaluation_members{critical_speed_name, amplitude_name,
                                                             "detail"};

struct EvaluationView {
    const core::Evaluation& evaluation;
    const EvaluationOptions& options;
};

const ResultTable<EvaluationView>& evaluation_table() {
    static const ResultTable<EvaluationView> table{
        "EvaluateResult",
        "Roll gap, stability, critical speed and amplitude at the scenario's speed. Without a steady bite there "
        "(roll_gap status not ok) the other three have status no_steady_state and null figures. With "
        "options.detail \"summary\" the distributions, amplitude windows and time series are left out.",
        {
            {"roll_gap", "The steady roll bite.", ref_schema("RollGapResult"),
             [](const EvaluationView& v) {
                 nlohmann::json bite = bite_result_json(v.evaluation.bite);
                 if (v.options.detail == Detail::summary) bite.erase("distribution");
                 return bite;
             }},
            {"stability", "The linearisation at the scenario's speed.",
             ref_schema("StabilitySummary"),
             [](const EvaluationView& v) {
                 return speed_stability_summary_json(v.evaluation.stability);
             }},
            {"critical_speed", "The critical-speed search.", ref_schema("CriticalSpeedSummary"),
             [](const EvaluationView& v) {
                 return critical_speed_summary_json(v.evaluation.critical);
             }},
            {"amplitude", "The vibration at the scenario's speed.", ref_schema("AmplitudePoint"),
             [](const EvaluationView& v) {
                 return amplitude_result_json(v.evaluation.amplitude,
                                              v.options.amplitude.time_series, v.options.detail);
             }},
        }};
    return table;
}

}  // namespace

EvaluationOptions evaluation_options_from_json(const nlohmann::json& options,
                                               const std::string& pointer, FieldErrors& errors) {
    EvaluationOptions parsed;
    const OptionsReader reader(options, pointer, evaluation_members, errors);
    if (!reader.is_object()) return parsed;
    if (reader.given(critical_speed_name)) {
        parsed.critical_speed = critical_speed_options_from_json(
            *reader.find(critical_speed_name), reader.at(critical_speed_name), errors);
    }
    if (reader.given(amplitude_name)) {
        parsed.amplitude =
            amplitude_options_from_json(*reader.find(amplitude_name), reader.at(amplitude_name),
                                        AmplitudeMembers::single_run, 0.0, errors)
                .run;
    }
    read_detail(reader, parsed.detail);
    return parsed;
}

nlohmann::json evaluation_options_json(const EvaluationOptions& options) {
    return {
        {critical_speed_name, critical_speed_options_json(options.critical_speed)},
        {amplitude_name,
         amplitude_options_json({{}, options.amplitude}, AmplitudeMembers::single_run)},
        {"detail", detail_json(options.detail)},
    };
}

nlohmann::json evaluation_result_json(const core::Evaluation& evaluation,
                                      const EvaluationOptions& options, double scenario_speed) {
    core::SpeedStability stability = evaluation.stability;
    core::AmplitudeResult amplitude = evaluation.amplitude;
    core::CriticalSpeedResult critical = evaluation.critical;
    if (evaluation.bite.status != core::BiteStatus::ok) {
        // core stops after the critical-speed search: say why the rest is missing, consistently.
        stability.speed = scenario_speed;
        stability.steady_status = evaluation.bite.status;
        amplitude.speed = scenario_speed;
        amplitude.steady_status = evaluation.bite.status;
        amplitude.status = core::AmplitudeStatus::no_steady_state;
        amplitude.message =
            "no steady state at the scenario's speed: the bite skids or loses contact";
    }
    core::Evaluation completed = evaluation;
    completed.stability = stability;
    completed.amplitude = amplitude;
    completed.critical = critical;
    return evaluation_table().write({completed, options});
}

std::vector<ResultSchema> evaluation_result_schemas() {
    return {result_schema(evaluation_table())};
}

}  // namespace rollgap::api
