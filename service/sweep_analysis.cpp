#include "service/sweep_analysis.h"

#include <memory>

#include "api/sweep_json.h"
#include "core/sweep.h"

namespace rollgap::service {

PreparedAnalysis prepare_sweep(const core::Scenario& scenario, const nlohmann::json& options,
                               const std::string& options_pointer, api::FieldErrors& errors) {
    const bool scenario_valid = errors.empty();  // analysis.h: only the scenario was read so far
    // Up to 1000 scenarios: shared with the run, not copied into it.
    auto plan = std::make_shared<const api::SweepPlan>(api::sweep_plan_from_json(
        options, options_pointer, scenario_valid ? &scenario : nullptr, errors));
    return {
        plan->resolved_options,
        [plan](const core::Control& control) {
            // The points run in parallel on the Control's executor and budget; the results do
            // not depend on it.
            if (plan->quantity == api::SweepQuantity::critical_speed) {
                const auto results =
                    core::sweep_critical_speed(plan->scenarios, plan->critical_speed, control);
                throw_if_cancelled(control);
                for (const auto& result : results) {
                    if (result.status == core::CriticalSpeedStatus::cancelled)
                        throw AnalysisCancelled{};
                }
                return api::sweep_critical_speed_json(*plan, results);
            }
            const auto results = core::sweep_amplitude(plan->scenarios, plan->amplitude, control);
            throw_if_cancelled(control);
            for (const auto& result : results) {
                if (result.status == core::AmplitudeStatus::cancelled) throw AnalysisCancelled{};
            }
            return api::sweep_amplitude_json(*plan, results);
        },
    };
}

}  // namespace rollgap::service
