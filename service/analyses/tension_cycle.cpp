#include "service/analyses/tension_cycle.h"

#include "api/tension_cycle_json.h"
#include "core/tension_cycle.h"

namespace rollgap::service {

PreparedAnalysis prepare_tension_cycle(const core::Scenario& scenario,
                                       const nlohmann::json& options,
                                       const std::string& options_pointer,
                                       api::FieldErrors& errors) {
    const bool scenario_valid = errors.empty();  // analysis.h: only the scenario was read so far
    if (scenario_valid) api::check_tension_cycle_scenario(scenario, "/scenario", errors);
    const core::TensionCycleOptions parsed = api::tension_cycle_options_from_json(
        options, options_pointer, scenario_valid ? &scenario : nullptr, errors);
    return {
        api::tension_cycle_options_json(parsed),
        [scenario, parsed](const core::Control& control) {
            const core::TensionCycleResult result = core::tension_cycle(scenario, parsed, control);
            if (result.status == core::DynamicsStatus::cancelled) throw AnalysisCancelled{};
            throw_if_cancelled(control);
            return api::tension_cycle_result_json(result);
        },
    };
}

}  // namespace rollgap::service
