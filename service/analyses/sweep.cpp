#include "service/analyses/sweep.h"

#include <memory>
#include <span>

#include "api/sweep_json.h"
#include "core/sweep.h"

namespace rollgap::service {

PreparedAnalysis prepare_sweep(const core::Scenario& scenario, const nlohmann::json& options,
                               const std::string& options_pointer, api::FieldErrors& errors) {
    const bool scenario_valid = errors.empty();  // analysis.h: only the scenario was read so far
    // Up to 1000 scenarios: shared with the run, not copied into it.
    auto plan = std::make_shared<const api::SweepPlan>(api::sweep_plan_from_json(
        options, options_pointer, scenario_valid ? &scenario : nullptr, errors));
    PointwiseRun points{
        static_cast<std::int64_t>(plan->scenarios.size()),
        [plan](std::int64_t begin, std::int64_t end, const core::Control& control) {
            const auto first = static_cast<std::size_t>(begin);
            const auto slice =
                std::span(plan->scenarios).subspan(first, static_cast<std::size_t>(end - begin));
            // The points run in parallel on the Control's executor and budget; the results do
            // not depend on it.
            if (plan->quantity == api::SweepQuantity::critical_speed) {
                // A sweep point reports no scan: each search may stop at its first crossing.
                const auto results = core::sweep_critical_speed(slice, plan->critical_speed,
                                                                control, /*keep_scan=*/false);
                throw_if_cancelled(control, results);
                return api::sweep_critical_speed_points_json(*plan, results, first);
            }
            const auto results = core::sweep_amplitude(slice, plan->amplitude, control);
            throw_if_cancelled(control, results);
            return api::sweep_amplitude_points_json(*plan, results, first);
        },
        [plan](nlohmann::json documents) {
            return api::sweep_result_json(*plan, std::move(documents));
        },
    };
    return pointwise_analysis(plan->resolved_options, std::move(points));
}

}  // namespace rollgap::service
