#include "service/analyses/tandem.h"

#include "api/stability_json.h"
#include "api/tandem_result_json.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_stability.h"

namespace rollgap::service {

PreparedAnalysis prepare_tandem(const core::Mill& mill, const nlohmann::json& options,
                                const std::string& options_pointer, api::FieldErrors& errors) {
    // The stability analysis' options: the same search over mill speeds (the last stand's roll
    // speed), critical_speed and detail.
    api::StabilityOptions parsed =
        api::stability_options_from_json(options, options_pointer, errors);
    return {
        api::stability_options_json(parsed),
        [mill, parsed](const core::Control& control) {
            api::TandemReport report;
            report.mill = mill;
            report.detail = parsed.detail;
            report.at_speed = core::mill_stability_at(mill);
            throw_if_cancelled(control);
            report.rightmost = core::describe_rightmost_root(mill, report.at_speed);
            throw_if_cancelled(control);
            if (parsed.critical_speed) {
                report.critical = core::mill_critical_speeds(mill, parsed.search, control);
                throw_if_cancelled(control);
            }
            return api::tandem_result_json(report);
        },
    };
}

}  // namespace rollgap::service
