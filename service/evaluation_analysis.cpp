#include "service/evaluation_analysis.h"

#include "api/evaluation_json.h"
#include "core/evaluation.h"
#include "core/parallel_for.h"

namespace rollgap::service {

PreparedAnalysis prepare_evaluation(const core::Scenario& scenario, const nlohmann::json& options,
                                    const std::string& options_pointer, api::FieldErrors& errors) {
    api::EvaluationOptions parsed = api::evaluation_options_from_json(options, options_pointer, errors);
    parsed.critical_speed.threads = core::default_thread_count();  // the scan speeds in parallel
    return {
        api::evaluation_options_json(parsed),
        [scenario, parsed](const core::Control& control) {
            const core::Evaluation evaluation =
                core::evaluate_scenario(scenario, parsed.critical_speed, parsed.amplitude, control);
            if (evaluation.critical.status == core::CriticalSpeedStatus::cancelled ||
                evaluation.amplitude.status == core::AmplitudeStatus::cancelled) {
                throw AnalysisCancelled{};
            }
            throw_if_cancelled(control);
            return api::evaluation_result_json(evaluation, parsed, scenario.rolls.speed);
        },
    };
}

}  // namespace rollgap::service
