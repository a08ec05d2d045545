#include "service/map_analysis.h"

#include <memory>

#include "api/map_json.h"
#include "core/map.h"

namespace rollgap::service {

PreparedAnalysis prepare_map(const core::Scenario& scenario, const nlohmann::json& options,
                             const std::string& options_pointer, api::FieldErrors& errors) {
    const bool scenario_valid = errors.empty();  // analysis.h: only the scenario was read so far
    // Up to 2500 scenarios: shared with the run, not copied into it.
    auto plan = std::make_shared<const api::MapPlan>(api::map_plan_from_json(
        options, options_pointer, scenario_valid ? &scenario : nullptr, errors));
    return {
        plan->resolved_options,
        [plan](const core::Control& control) {
            const auto rows = static_cast<int>(plan->axes[0].values.size());
            const auto columns = static_cast<int>(plan->axes[1].values.size());
            const core::StabilityMap map =
                core::stability_map(plan->cells, rows, columns, plan->critical_speed, control);
            throw_if_cancelled(control);
            for (const auto& cell : map.cells) {
                if (cell.status == core::CriticalSpeedStatus::cancelled) throw AnalysisCancelled{};
            }
            return api::map_json(*plan, map);
        },
    };
}

}  // namespace rollgap::service
