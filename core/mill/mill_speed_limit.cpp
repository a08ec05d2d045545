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

namespace mill_speed_limit_detail {

// The steady_state limit's row named by the stand that loses its steady state just beyond the
// row's end (the upper end when it has one: the advised speed's side), and the window's binding
// stand with it (docs/model.md §13.5). The window's ends are bisected to 1e-9 m/s, so a
// micrometre per second beyond is past the schedule's failure.
void name_steady_state_stand(const Mill& mill, SpeedLimitResult& window) {
    for (LimitAnswer& a : window.limits) {
        if (a.kind != SpeedLimitKind::steady_state) continue;
        const bool upper = a.upper_speed.has_value();
        const std::optional<double> end = upper ? a.upper_speed : a.lower_speed;
        if (!end) return;
        Mill beyond = mill;
        beyond.speed = *end + (upper ? 1e-6 : -1e-6);
        const MillSteadyState s = mill_steady_state(beyond);
        if (s.status == MillSteadyStatus::ok || s.stand < 0) return;
        a.stand = s.stand;
        if (window.binding_max == SpeedLimitKind::steady_state && upper)
            window.binding_max_stand = s.stand;
        if (window.binding_min == SpeedLimitKind::steady_state && !upper)
            window.binding_min_stand = s.stand;
        return;
    }
}

}  // namespace mill_speed_limit_detail

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
                MillSpeedUncertainty& u = out.uncertainty.emplace(mill_crossing_uncertainty(
                    mill, c, *limits.posterior, limits.confidence, control));
                if (limits.samples > 0 && !control.should_stop())
                    u.sampled.emplace(mill_sampled_critical_speed(
                        mill, *limits.posterior, options, limits.samples, limits.seed, control));
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
    mill_speed_limit_detail::name_steady_state_stand(mill, out.window);
    if (limits.posterior && !control.should_stop())
        bound_mill_plant_limits(mill, limits, out.window, control);
    return out;
}

}  // namespace rollgap::core
