#include "service/analyses/speed_limit.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "api/speed_limit_json.h"
#include "core/limit_sensitivity.h"
#include "core/propagation.h"
#include "core/speed_limit.h"
#include "core/stability.h"

namespace rollgap::service {
namespace speed_limit_detail {

// docs/model.md §13.2: each plant limit's ends (force, torque, power, skid) carry the posterior
// as the critical speed does — the end found again near itself (core::limit_crossing) at the
// posterior's difference points, its sigma linear — and the window takes every end at its
// one-sided bound.
void bound_plant_limits(const core::Scenario& scenario, const api::SpeedLimitOptions& options,
                        core::SpeedLimitResult& result, const core::Control& control) {
    const api::Posterior& posterior = *options.posterior;
    const Eigen::MatrixXd covariance = posterior.covariance();
    for (core::LimitAnswer& a : result.limits) {
        if (a.kind == core::SpeedLimitKind::chatter || a.kind == core::SpeedLimitKind::steady_state)
            continue;
        for (const bool upper : {false, true}) {
            const std::optional<double>& end = upper ? a.upper_speed : a.lower_speed;
            if (!end) continue;
            const double at = *end;
            // wide enough for the end's move over one standard deviation, narrow enough to
            // hold this crossing alone
            const double half_width = std::max(2.0 * options.search.speed_step, 0.05 * at);
            const core::Figure crossing = [&](const Eigen::VectorXd& x) {
                return core::limit_crossing(posterior.at(scenario, x), a.kind, a.limit, at,
                                            half_width);
            };
            const core::Propagated p =
                core::propagate_linear(crossing, posterior.mean, covariance, control);
            if (control.should_stop()) return;
            if (p.ok) (upper ? a.upper_speed_sd : a.lower_speed_sd) = p.standard_deviation;
        }
    }
    core::bound_window(result, core::normal_quantile(options.limits.confidence));
}

}  // namespace speed_limit_detail

using speed_limit_detail::bound_plant_limits;

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
            if (parsed->posterior) {
                bound_plant_limits(scenario, *parsed, report.result, control);
                throw_if_cancelled(control);
            }
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
