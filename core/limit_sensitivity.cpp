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
    return plant_limit_margin(steady_figures(s, v), limits, kind);
}

}  // namespace

std::optional<double> plant_limit_margin(const SteadyFigures& f, const PlantLimits& limits,
                                         SpeedLimitKind kind) {
    if (!f.ok) return std::nullopt;
    const auto below = [](const std::optional<double>& limit, double figure) {
        return limit ? std::optional<double>(*limit - figure) : std::nullopt;
    };
    switch (kind) {
        case SpeedLimitKind::force: return below(limits.max_force, f.force);
        case SpeedLimitKind::torque: return below(limits.max_torque, f.torque);
        case SpeedLimitKind::power: return below(limits.max_power, f.power);
        case SpeedLimitKind::skid:
            if (!limits.min_forward_slip) return std::nullopt;
            return f.forward_slip - *limits.min_forward_slip;
        default: return std::nullopt;
    }
}

ImplicitDerivatives implicit_speed_derivatives(const CrossingMargin& margin,
                                               const std::vector<double>& steps, double speed,
                                               const Control& control) {
    ImplicitDerivatives out;
    const int n = static_cast<int>(steps.size());
    out.derivatives.assign(steps.size(), std::nullopt);
    const double h = 1e-4 * speed;
    // [0, 1]: V ± h; [2 + 2j, 3 + 2j]: number j ± its step; 2n + 2: the margin itself
    std::vector<std::optional<double>> values(static_cast<std::size_t>(2 * n + 3));
    parallel_for(2 * n + 3, control, [&](int k) {
        std::optional<double>& value = values[static_cast<std::size_t>(k)];
        if (k == 2 * n + 2) value = margin(-1, 0, speed);
        else if (k < 2) value = margin(-1, 0, speed + (k == 0 ? h : -h));
        else value = margin((k - 2) / 2, k % 2 == 0 ? 1 : -1, speed);
    });
    if (control.should_stop() || !values[0] || !values[1]) return out;
    out.margin_slope = (*values[0] - *values[1]) / (2.0 * h);
    if (!(std::abs(out.margin_slope) > 0.0)) return out;
    out.ok = true;
    const std::optional<double>& here = values[static_cast<std::size_t>(2 * n + 2)];
    for (int j = 0; j < n; ++j) {
        const auto& plus = values[static_cast<std::size_t>(2 + 2 * j)];
        const auto& minus = values[static_cast<std::size_t>(3 + 2 * j)];
        const double step = steps[static_cast<std::size_t>(j)];
        // central; one-sided where one side has no answer (a tension at its bound of 0)
        double dg_dx = 0.0;
        if (plus && minus) dg_dx = (*plus - *minus) / (2.0 * step);
        else if (plus && here) dg_dx = (*plus - *here) / step;
        else if (minus && here) dg_dx = (*here - *minus) / step;
        else continue;
        out.derivatives[static_cast<std::size_t>(j)] = -dg_dx / out.margin_slope;
    }
    return out;
}

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
    std::vector<double> steps;
    for (const ScenarioNumber& number : numbers) steps.push_back(number.step);
    const ImplicitDerivatives d = implicit_speed_derivatives(
        [&](int j, int sign, double v) -> std::optional<double> {
            if (j < 0) return margin(s, limits, kind, v);
            Scenario x = s;
            numbers[static_cast<std::size_t>(j)].number(x) +=
                sign * steps[static_cast<std::size_t>(j)];
            return margin(x, limits, kind, v);
        },
        steps, out.speed, control);
    out.ok = d.ok;
    out.margin_slope = d.margin_slope;
    if (!d.ok) return out;
    for (std::size_t j = 0; j < numbers.size(); ++j)
        if (d.derivatives[j]) out.derivatives[j] = scale * *d.derivatives[j];
    return out;
}

}  // namespace rollgap::core
