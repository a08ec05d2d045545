#include "api/evaluation_json.h"

#include <array>
#include <string_view>

#include "api/options_reader.h"
#include "api/result_json.h"
#include "api/stability_json.h"

namespace rollgap::api {
namespace {

constexpr std::string_view critical_speed_name = "critical_speed";
constexpr std::string_view amplitude_name = "amplitude";
constexpr std::array<std::string_view, 2> members{critical_speed_name, amplitude_name};

}  // namespace

EvaluationOptions evaluation_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                               FieldErrors& errors) {
    EvaluationOptions parsed;
    const OptionsReader reader(options, pointer, members, errors);
    if (!reader.is_object()) return parsed;
    if (const nlohmann::json* search = reader.find(critical_speed_name)) {
        parsed.critical_speed = critical_speed_options_from_json(*search, reader.at(critical_speed_name), errors);
    }
    if (const nlohmann::json* run = reader.find(amplitude_name)) {
        parsed.amplitude =
            amplitude_options_from_json(*run, reader.at(amplitude_name), AmplitudeMembers::single_run, 0.0, errors).run;
    }
    return parsed;
}

nlohmann::json evaluation_options_json(const EvaluationOptions& options) {
    return {
        {critical_speed_name, critical_speed_options_json(options.critical_speed)},
        {amplitude_name, amplitude_options_json({{}, options.amplitude}, AmplitudeMembers::single_run)},
    };
}

nlohmann::json evaluation_result_json(const core::Evaluation& evaluation, const EvaluationOptions& options,
                                      double scenario_speed) {
    core::SpeedStability stability = evaluation.stability;
    core::AmplitudeResult amplitude = evaluation.amplitude;
    core::CriticalSpeedResult critical = evaluation.critical;
    if (evaluation.roll_gap.status != core::BiteStatus::ok) {
        // core stops after the critical-speed search: say why the rest is missing, consistently.
        stability.speed = scenario_speed;
        stability.steady_status = evaluation.roll_gap.status;
        amplitude.speed = scenario_speed;
        amplitude.steady_status = evaluation.roll_gap.status;
        amplitude.status = core::AmplitudeStatus::no_steady_state;
        amplitude.message = "no steady state at the scenario's speed: the bite skids or loses contact";
    }
    return {
        {"roll_gap", bite_result_json(evaluation.roll_gap)},
        {"stability", speed_stability_summary_json(stability)},
        {"critical_speed", critical_speed_summary_json(critical)},
        {"amplitude", amplitude_result_json(amplitude, options.amplitude.time_series)},
    };
}

}  // namespace rollgap::api
