#include "core/limit_sensitivity.h"

#include <cmath>

#include "core/parallel_for.h"
#include "core/stability.h"

namespace rollgap::core {
namespace {

// The binding limit's margin at speed v of scenario s: ≥ 0 where it permits v. nullopt where the
// model has no answer (no steady state, a failed linearisation).
std::optional<double> margin(const Scenario& s, const PlantLimits& limits, SpeedLimitKind kind,
                             double v) {
    if (kind == SpeedLimitKind::chatter) {
        Scenario at = s;
        at.rolls.speed = v;
        const SpeedStability st = stability_at(at);
        if (st.steady_status != BiteStatus::ok || st.status != DynamicsStatus::ok)
            return std::nullopt;
        return -st.max_real_part;  // stable: the largest real part is negative
    }
    const SteadyFigures f = steady_figures(s, v);
    if (!f.ok) return std::nullopt;
    switch (kind) {
        case SpeedLimitKind::force: return *limits.max_force - f.force;
        case SpeedLimitKind::torque: return *limits.max_torque - f.torque;
        case SpeedLimitKind::power: return *limits.max_power - f.power;
        case SpeedLimitKind::skid: return f.forward_slip - *limits.min_forward_slip;
        default: return std::nullopt;
    }
}

}  // namespace

BindingSensitivity binding_sensitivity(const Scenario& s, const PlantLimits& limits,
                                       const SpeedLimitResult& result,
                                       const std::vector<ScenarioNumber>& numbers,
                                       const Control& control) {
    BindingSensitivity out;
    out.derivatives.assign(numbers.size(), std::nullopt);
    if (result.status != SpeedLimitStatus::ok || !result.binding_max) return out;
    const SpeedLimitKind kind = *result.binding_max;
    out.kind = kind;
    if (kind == SpeedLimitKind::steady_state) return out;
    double scale = 1.0;  // d(advised)/d(crossing speed)
    if (kind == SpeedLimitKind::chatter) {
        if (result.chatter.status != CriticalSpeedStatus::found) return out;
        out.speed = result.chatter.critical_speed;
        scale = 1.0 - limits.chatter_margin;
    } else {
        // where the margin crosses zero: the limit's own end, which is the window's unless the
        // window takes that end at its bound under a posterior (bound_window)
        out.speed = result.window_max;
        for (const LimitAnswer& a : result.limits)
            if (a.kind == kind && a.stand == result.binding_max_stand && a.upper_speed)
                out.speed = *a.upper_speed;
    }
    // Central differences: in V over 1e-4 of the speed, in x over the number's step; both are
    // 2 evaluations, all of them side by side.
    const double h = 1e-4 * out.speed;
    const int n = static_cast<int>(numbers.size());
    std::vector<std::optional<double>> values(static_cast<std::size_t>(2 * n + 3));
    parallel_for(2 * n + 3, control, [&](int k) {
        if (k == 2 * n + 2) {  // the margin itself, for a one-sided difference
            values[static_cast<std::size_t>(k)] = margin(s, limits, kind, out.speed);
            return;
        }
        if (k < 2) {
            values[static_cast<std::size_t>(k)] =
                margin(s, limits, kind, out.speed + (k == 0 ? h : -h));
            return;
        }
        const int j = (k - 2) / 2;
        Scenario x = s;
        const ScenarioNumber& number = numbers[static_cast<std::size_t>(j)];
        number.number(x) += (k % 2 == 0 ? number.step : -number.step);
        values[static_cast<std::size_t>(k)] = margin(x, limits, kind, out.speed);
    });
    if (control.should_stop() || !values[0] || !values[1]) return out;
    out.margin_slope = (*values[0] - *values[1]) / (2.0 * h);
    if (!(std::abs(out.margin_slope) > 0.0)) return out;
    out.ok = true;
    for (int j = 0; j < n; ++j) {
        const auto& plus = values[static_cast<std::size_t>(2 + 2 * j)];
        const auto& minus = values[static_cast<std::size_t>(3 + 2 * j)];
        const auto& here = values[static_cast<std::size_t>(2 * n + 2)];
        const double step = numbers[static_cast<std::size_t>(j)].step;
        // central; one-sided where one side has no answer (a tension at its bound of 0)
        double dg_dx = 0.0;
        if (plus && minus) dg_dx = (*plus - *minus) / (2.0 * step);
        else if (plus && here) dg_dx = (*plus - *here) / step;
        else if (minus && here) dg_dx = (*here - *minus) / step;
        else continue;
        out.derivatives[static_cast<std::size_t>(j)] = -scale * dg_dx / out.margin_slope;
    }
    return out;
}

}  // namespace rollgap::core
