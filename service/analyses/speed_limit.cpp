#include "service/analyses/speed_limit.h"

#include <memory>
#include <optional>
#include <utility>
#include <vector>
#include <vector>

#include "api/speed_limit_json.h"
#include "core/limit_sensitivity.h"
#include "core/limit_sensitivity.h"
#include "core/propagation.h"
#include "core/speed_limit.h"
#include "core/stability.h"

namespace rollgap::service {

PreparedAnalysis prepare_speed_limit(const core::Scenario& scenario, const nlohmann::json& options,
                                     const std::string& options_pointer, api::FieldErrors& errors) {
    const bool scenario_valid = errors.empty();
    auto parsed = std::make_shared<const api::SpeedLimitOptions>(api::speed_limit_options_from_json(
        options, options_pointer, scenario_valid ? &scenario : nullptr, errors));
    return {
        api::speed_limit_options_json(*parsed),
        [scenario, parsed](const core::Control& control) {
            api::SpeedLimitReport report;
            report.limits = parsed->limits;
            if (parsed->posterior && parsed->limits.chatter) {
                // The critical speed at the posterior's points, searched as the chatter limit
                // searches it (docs/model.md §13.2): the differences run side by side, each
                // search on one thread.
                const api::Posterior& posterior = *parsed->posterior;
                core::CriticalSpeedOptions search = parsed->search;
                search.stop_at_crossing = true;
                const core::Figure critical =
                    [&](const Eigen::VectorXd& x) -> std::optional<double> {
                    const core::CriticalSpeedResult r =
                        core::critical_speed(posterior.at(scenario, x), search);
                    if (r.status != core::CriticalSpeedStatus::found) return std::nullopt;
                    return r.critical_speed;
                };
                // filled in place: a moved optional<Propagated> trips GCC 12's
                // -Wmaybe-uninitialized
                api::SpeedLimitUncertainty& uncertainty = report.uncertainty.emplace();
                uncertainty.posterior = &posterior;
                uncertainty.confidence = parsed->limits.confidence;
                uncertainty.seed = parsed->seed;
                uncertainty.linear = core::propagate_linear(critical, posterior.mean,
                                                            posterior.covariance(), control);
                throw_if_cancelled(control);
                if (parsed->samples > 0) {
                    uncertainty.sampled.emplace(core::propagate_sampled(
                        critical, posterior.mean, posterior.covariance(), parsed->samples,
                        static_cast<std::uint64_t>(parsed->seed), control));
                    throw_if_cancelled(control);
                }
                if (uncertainty.linear.ok)
                    report.limits.chatter_sigma = uncertainty.linear.standard_deviation;
            }
            report.result = core::speed_limit(scenario, report.limits, parsed->search, control);
            if (report.result.status == core::SpeedLimitStatus::cancelled)
                throw AnalysisCancelled{};
            throw_if_cancelled(control);
            if (parsed->what_to_change) {
                // docs/model.md §13.4: the margin differenced over a tenth of each typical step
                api::WhatToChange& what = report.what_to_change.emplace();
                what.changes = parsed->changes;
                what.scenario = scenario;
                std::vector<core::ScenarioNumber> numbers;
                for (const api::ChangeField& c : parsed->changes)
                    numbers.push_back({c.field->number, 0.1 * c.step});
                what.sensitivity = core::binding_sensitivity(scenario, report.limits, report.result,
                                                             numbers, control);
                throw_if_cancelled(control);
            }
            return api::speed_limit_result_json(report);
        },
    };
}

}  // namespace rollgap::service
