#include "core/mill/mill_speed_limit.h"

#include "core/mill/mill_limit_sensitivity.h"

#include <cmath>
#include <utility>

namespace rollgap::core {

std::vector<SteadyFigures> mill_steady_figures(const Mill& mill, double speed) {
    Mill at = mill;
    at.speed = speed;
    const MillSteadyState steady = mill_steady_state(at);
    std::vector<SteadyFigures> out(static_cast<std::size_t>(mill.size()));
    for (std::size_t i = 0; i < out.size(); ++i) {
        SteadyFigures& f = out[i];
        f.speed = speed;
        if (steady.status != MillSteadyStatus::ok) continue;  // none ok: no steady state at V
        const MillStandState& stand = steady.stands[i];
        f.ok = true;
        f.force = stand.force;
        f.torque = std::abs(stand.torque);
        f.power = std::abs(stand.power);
        f.forward_slip = stand.forward_slip;
    }
    return out;
}

MillSpeedLimitResult mill_speed_limit(const Mill& mill, const MillPlantLimits& limits,
                                      const CriticalSpeedOptions& options, const Control& control) {
    MillSpeedLimitResult out;
    std::vector<SpeedCheck> checks;
    for (int i = 0; i < mill.size() && i < static_cast<int>(limits.stands.size()); ++i) {
        const PlantLimits& l = limits.stands[static_cast<std::size_t>(i)];
        if (l.max_force) checks.push_back({SpeedLimitKind::force, i, *l.max_force});
        if (l.max_torque) checks.push_back({SpeedLimitKind::torque, i, *l.max_torque});
        if (l.max_power) checks.push_back({SpeedLimitKind::power, i, *l.max_power});
        if (l.min_forward_slip) checks.push_back({SpeedLimitKind::skid, i, *l.min_forward_slip});
    }
    std::optional<ChatterLimit> chatter;
    if (limits.chatter) {
        const MillCriticalSpeeds& critical =
            out.critical.emplace(mill_critical_speeds(mill, options, control));
        const MillCrossing* crossings[] = {&critical.frozen, &critical.delay_independent,
                                           &critical.nominal_delay};
        for (const MillCrossing* c : crossings) {
            if (c->status == CriticalSpeedStatus::cancelled) {
                out.window.operating_speed = mill.speed;
                out.window.status = SpeedLimitStatus::cancelled;
                return out;
            }
        }
        ChatterLimit limit{options.speed_max, -1};
        if (critical.headline >= 0) {
            const MillCrossing& c = *crossings[critical.headline];
            double speed = c.speed;
            if (limits.posterior) {
                // docs/model.md §13.7: the limit at the headline's one-sided lower bound
                const MillSpeedUncertainty& u = out.uncertainty.emplace(mill_crossing_uncertainty(
                    mill, c, *limits.posterior, limits.confidence, control));
                if (u.ok) speed = u.lower_bound;
            }
            limit = {speed * (1.0 - limits.chatter_margin), c.moving_stand};
        } else {
            // Unstable at the range's lowest speed by any of the three: no speed is permitted.
            for (const MillCrossing* c : crossings)
                if (c->status == CriticalSpeedStatus::unstable_at_lower_bound) limit.speed = -1.0;
        }
        chatter = limit;
    }
    out.window = speed_window(
        checks, [&mill](double v) { return mill_steady_figures(mill, v); }, mill.speed, chatter,
        options, control);
    if (limits.posterior && !control.should_stop())
        bound_mill_plant_limits(mill, limits, out.window, control);
    return out;
}

}  // namespace rollgap::core
