#include "service/analyses/tandem_map.h"

#include <memory>

#include "api/tandem_map_json.h"

namespace rollgap::service {

PreparedAnalysis prepare_tandem_map(const core::Mill& mill, const nlohmann::json& options,
                                    const std::string& options_pointer, api::FieldErrors& errors) {
    const bool mill_valid = errors.empty();  // analysis.h: only the mill was read so far
    // Up to 400 mills: shared with the run, not copied into it.
    auto plan = std::make_shared<const api::TandemMapPlan>(api::tandem_map_plan_from_json(
        options, options_pointer, mill_valid ? &mill : nullptr, errors));
    PointwiseRun cells{
        static_cast<std::int64_t>(plan->cells.size()),
        [plan](std::int64_t begin, std::int64_t end, const core::Control& control) {
            nlohmann::json documents =
                api::tandem_map_cells_json(*plan, static_cast<std::size_t>(begin),
                                           static_cast<std::size_t>(end - begin), control);
            // A cell stopped half-way is never returned as computed.
            throw_if_cancelled(control);
            return documents;
        },
        [plan](nlohmann::json documents) {
            return api::tandem_map_result_json(*plan, std::move(documents));
        },
    };
    return pointwise_analysis(plan->resolved_options, std::move(cells));
}

}  // namespace rollgap::service
