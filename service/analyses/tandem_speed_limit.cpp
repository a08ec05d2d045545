#include "service/analyses/tandem_speed_limit.h"

#include <memory>
#include <vector>

#include "api/tandem_speed_limit_json.h"
#include "core/mill/mill_limit_sensitivity.h"
#include "core/mill/mill_speed_limit.h"

namespace rollgap::service {

PreparedAnalysis prepare_tandem_speed_limit(const core::Mill& mill, const nlohmann::json& options,
                                            const std::string& options_pointer,
                                            api::FieldErrors& errors) {
    // the per-stand lists are checked against a mill that was read without violations
    const core::Mill* valid = errors.empty() ? &mill : nullptr;
    auto parsed = std::make_shared<const api::TandemSpeedLimitOptions>(
        api::tandem_speed_limit_options_from_json(options, options_pointer, valid, errors));
    return {
        api::tandem_speed_limit_options_json(*parsed),
        [mill, parsed](const core::Control& control) {
            api::TandemSpeedLimitReport report;
            report.limits = parsed->limits;
            report.posteriors = parsed->posteriors;
            report.result = core::mill_speed_limit(mill, parsed->limits, parsed->search, control);
            if (report.result.window.status == core::SpeedLimitStatus::cancelled)
                throw AnalysisCancelled{};
            throw_if_cancelled(control);
            if (parsed->what_to_change) {
                // docs/model.md §13.6: the margin differenced over a hundredth of each typical
                // step (a nominal-delay root's margin is curved over a tenth)
                api::MillWhatToChange& what = report.what_to_change.emplace();
                what.changes = parsed->changes;
                what.mill = mill;
                what.chatter_margin = parsed->limits.chatter_margin;
                std::vector<core::MillNumber> numbers;
                for (const api::MillChangeField& c : parsed->changes)
                    numbers.push_back({c.shift, 0.01 * c.step});
                what.sensitivity = core::mill_binding_sensitivity(mill, parsed->limits,
                                                                  report.result, numbers, control);
                throw_if_cancelled(control);
            }
            return api::tandem_speed_limit_result_json(report);
        },
    };
}

}  // namespace rollgap::service
