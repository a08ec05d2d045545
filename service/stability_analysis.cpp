#include "service/stability_analysis.h"

#include "api/stability_json.h"
#include "core/mill_structure.h"
#include "core/stability.h"

namespace rollgap::service {

PreparedAnalysis prepare_stability(const core::Scenario& scenario, const nlohmann::json& options,
                                   const std::string& options_pointer, api::FieldErrors& errors) {
    api::StabilityOptions parsed = api::stability_options_from_json(options, options_pointer, errors);
    return {
        api::stability_options_json(parsed),
        [scenario, parsed](const core::Control& control) {
            const core::SpeedStability at_speed = core::stability_at(scenario);
            nlohmann::json body = api::speed_stability_json(at_speed);
            const double k4 = at_speed.strip_stiffness;
            nlohmann::json structure = nullptr;
            if (at_speed.steady_status == core::BiteStatus::ok && k4 > 0.0) {
                const core::ModalAnalysis modal = core::modal_analysis(core::mill_matrices(scenario.mill), k4);
                if (modal.ok) structure = api::structure_modes_json(modal, k4);
            }
            body["structure"] = std::move(structure);
            body["critical_speed"] = nullptr;
            if (parsed.critical_speed) {
                // The scan speeds are independent: spread over the caller's thread budget (the
                // result does not depend on it).
                core::CriticalSpeedOptions search = parsed.search;
                search.threads = control.thread_budget();
                const core::CriticalSpeedResult critical = core::critical_speed(scenario, search, control);
                if (critical.status == core::CriticalSpeedStatus::cancelled) throw AnalysisCancelled{};
                throw_if_cancelled(control);
                body["critical_speed"] = api::critical_speed_json(critical);
            }
            return body;
        },
    };
}

}  // namespace rollgap::service
