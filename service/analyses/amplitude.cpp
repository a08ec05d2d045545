#include "service/analyses/amplitude.h"

#include <vector>

#include "api/amplitude_json.h"
#include "core/amplitude.h"
#include "core/sweep.h"

namespace rollgap::service {

PreparedAnalysis prepare_amplitude(const core::Scenario& scenario, const nlohmann::json& options,
                                   const std::string& options_pointer, api::FieldErrors& errors) {
    const api::AmplitudeOptions parsed = api::amplitude_options_from_json(
        options, options_pointer, api::AmplitudeMembers::analysis, scenario.rolls.speed, errors);
    return {
        api::amplitude_options_json(parsed, api::AmplitudeMembers::analysis),
        [scenario, parsed](const core::Control& control) {
            std::vector<core::Scenario> runs;
            for (const double speed : parsed.speeds) {
                core::Scenario at_speed = scenario;
                at_speed.rolls.speed = speed;
                runs.push_back(at_speed);
            }
            // One speed keeps core's fine-grained progress; several run in parallel, each
            // result in its own slot (independent of the thread count).
            const std::vector<core::AmplitudeResult> results =
                runs.size() == 1 ? std::vector<core::AmplitudeResult>{core::vibration_amplitude(
                                       runs.front(), parsed.run, control)}
                                 : core::sweep_amplitude(runs, parsed.run, control);
            throw_if_cancelled(control);
            for (const core::AmplitudeResult& result : results) {
                if (result.status == core::AmplitudeStatus::cancelled) throw AnalysisCancelled{};
            }
            return api::amplitude_result_table().write({results, parsed.run.time_series});
        },
    };
}

}  // namespace rollgap::service
