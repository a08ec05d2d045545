#include "service/analyses/map.h"

#include <memory>
#include <span>

#include "api/map_json.h"
#include "core/sweep.h"

namespace rollgap::service {

PreparedAnalysis prepare_map(const core::Scenario& scenario, const nlohmann::json& options,
                             const std::string& options_pointer, api::FieldErrors& errors) {
    const bool scenario_valid = errors.empty();  // analysis.h: only the scenario was read so far
    // Up to 2500 scenarios: shared with the run, not copied into it.
    auto plan = std::make_shared<const api::MapPlan>(api::map_plan_from_json(
        options, options_pointer, scenario_valid ? &scenario : nullptr, errors));
    PointwiseRun cells{
        static_cast<std::int64_t>(plan->cells.size()),
        [plan](std::int64_t begin, std::int64_t end, const core::Control& control) {
            const auto first = static_cast<std::size_t>(begin);
            const auto slice =
                std::span(plan->cells).subspan(first, static_cast<std::size_t>(end - begin));
            // The cells of core::stability_map, without its neighbour comparison: the cells of
            // other chunks are not here, the assembly compares them (api/map_json.h).
            const auto results = core::sweep_critical_speed(slice, plan->critical_speed, control,
                                                            /*keep_scan=*/false);
            throw_if_cancelled(control, results);
            return api::map_cells_json(*plan, results, first);
        },
        [plan](nlohmann::json documents) {
            return api::map_result_json(*plan, std::move(documents));
        },
    };
    return pointwise_analysis(plan->resolved_options, std::move(cells));
}

}  // namespace rollgap::service
