#include "service/analyses/tandem.h"

#include <algorithm>
#include <vector>

#include "api/tandem_options_json.h"
#include "api/tandem_result_json.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_stability.h"
#include "core/mill/mill_time.h"

namespace rollgap::service {
namespace {

// The mill in time from its steady state, the kicked stand's gap opened by the kick
// (docs/model.md §12.8): the stand asked for, or the one the rightmost root moves most.
void run_time_domain(const api::TandemOptions& options, const core::Control& control,
                     api::TandemReport& report) {
    report.kick = options.kick;
    report.kicked_stand = options.kick_stand > 0   ? options.kick_stand - 1
                          : report.rightmost.found ? report.rightmost.described.moving_stand
                                                   : report.mill.size() - 1;
    if (report.at_speed.steady.status != core::MillSteadyStatus::ok) {
        core::MillTimeResult none;
        none.status = core::MillTimeStatus::invalid;
        none.message = "the mill has no steady state at its speed to start from";
        report.time = std::move(none);
        return;
    }
    std::vector<double> times(static_cast<std::size_t>(options.time_series_points));
    for (std::size_t k = 0; k < times.size(); ++k)
        times[k] = options.window * static_cast<double>(k + 1) / static_cast<double>(times.size());
    core::MillKick kick;
    kick.stand = report.kicked_stand;
    kick.gap = options.kick;
    core::MillTimeOptions integration;
    // The model's absolute tolerances are set for micrometre motion (docs/model.md §6); a kick
    // of 0.1 um needs them a thousand times finer, or the tolerance is a tenth of the motion.
    integration.absolute_tolerance_scale = std::clamp(options.kick / 1e-4, 1e-3, 1.0);
    report.time = core::mill_time_domain(report.mill, report.at_speed.steady, kick, times,
                                         integration, control);
    if (report.time->status == core::MillTimeStatus::cancelled) throw AnalysisCancelled{};
}

}  // namespace

PreparedAnalysis prepare_tandem(const core::Mill& mill, const nlohmann::json& options,
                                const std::string& options_pointer, api::FieldErrors& errors) {
    // The stability analysis' search over mill speeds (the last stand's roll speed),
    // critical_speed and detail, and the time domain's options.
    api::TandemOptions parsed =
        api::tandem_options_from_json(options, options_pointer, mill.size(), errors);
    return {
        api::tandem_options_json(parsed),
        [mill, parsed](const core::Control& control) {
            api::TandemReport report;
            report.mill = mill;
            report.detail = parsed.stability.detail;
            report.at_speed = core::mill_stability_at(mill);
            throw_if_cancelled(control);
            report.rightmost = core::describe_rightmost_root(mill, report.at_speed);
            throw_if_cancelled(control);
            if (parsed.stability.critical_speed) {
                report.critical =
                    core::mill_critical_speeds(mill, parsed.stability.search, control);
                throw_if_cancelled(control);
            }
            if (parsed.time_series) run_time_domain(parsed, control, report);
            return api::tandem_result_json(report);
        },
    };
}

}  // namespace rollgap::service
