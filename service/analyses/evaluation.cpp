#include "service/analyses/evaluation.h"

#include "api/evaluation_json.h"
#include "core/evaluation.h"

namespace rollgap::service {

PreparedAnalysis prepare_evaluation(const core::Scenario& scenario, const nlohmann::json& options,
                                    const std::string& options_pointer, api::FieldErrors& errors) {
    api::EvaluationOptions parsed =
        api::evaluation_options_from_json(options, options_pointer, errors);
    return {
        api::evaluation_options_json(parsed),
        [scenario, parsed](const core::Control& control) {
            // The scan speeds run in parallel on the Control's executor and budget. The result
            // gives the search's summary, no scan: it may stop at the first crossing.
            core::CriticalSpeedOptions search = parsed.critical_speed;
            search.stop_at_crossing = true;
            const core::Evaluation evaluation =
                core::evaluate_scenario(scenario, search, parsed.amplitude, control);
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
