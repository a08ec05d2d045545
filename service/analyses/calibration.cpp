#include "service/analyses/calibration.h"

#include <memory>

#include "api/calibration_json.h"
#include "core/calibration_observables.h"

namespace rollgap::service {

PreparedAnalysis prepare_calibration(const core::Scenario& scenario, const nlohmann::json& options,
                                     const std::string& options_pointer, api::FieldErrors& errors) {
    const bool scenario_valid = errors.empty();  // analysis.h: only the scenario was read so far
    // Up to 200 observation conditions: shared with the run, not copied into it.
    auto plan = std::make_shared<const api::CalibrationPlan>(api::calibration_plan_from_json(
        options, options_pointer, scenario_valid ? &scenario : nullptr, errors));
    return {
        plan->resolved_options,
        [plan](const core::Control& control) {
            const core::ScenarioCalibrationResult result =
                core::calibrate_scenario(plan->setup, control);
            if (result.fit.status == core::CalibrationStatus::cancelled) throw AnalysisCancelled{};
            throw_if_cancelled(control);
            return api::calibration_result_json(*plan, result);
        },
    };
}

}  // namespace rollgap::service
