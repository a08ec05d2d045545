#include "service/analyses/stability.h"

#include "api/stability_json.h"
#include "core/stand_structure.h"
#include "core/stability.h"

namespace rollgap::service {

PreparedAnalysis prepare_stability(const core::Scenario& scenario, const nlohmann::json& options,
                                   const std::string& options_pointer, api::FieldErrors& errors) {
    api::StabilityOptions parsed =
        api::stability_options_from_json(options, options_pointer, errors);
    return {
        api::stability_options_json(parsed),
        [scenario, parsed](const core::Control& control) {
            api::StabilityReport report{core::stability_at(scenario), {}, {}, parsed.detail};
            const double k4 = report.at_speed.strip_stiffness;
            if (report.at_speed.steady_status == core::BiteStatus::ok && k4 > 0.0) {
                core::ModalAnalysis modal =
                    core::modal_analysis(core::structure_matrices(scenario.structure), k4);
                if (modal.ok) report.modal = std::move(modal);
            }
            if (parsed.critical_speed) {
                // The scan speeds are independent: spread over the Control's executor and
                // budget (the result does not depend on it).
                // "summary" reports no scan: the search may stop at the first crossing.
                core::CriticalSpeedOptions search = parsed.search;
                search.stop_at_crossing = parsed.detail == api::Detail::summary;
                report.critical = core::critical_speed(scenario, search, control);
                if (report.critical->status == core::CriticalSpeedStatus::cancelled)
                    throw AnalysisCancelled{};
                throw_if_cancelled(control);
            }
            return api::stability_result_json(report);
        },
    };
}

}  // namespace rollgap::service
