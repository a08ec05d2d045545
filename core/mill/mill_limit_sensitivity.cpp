#include "core/mill/mill_limit_sensitivity.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "core/mill/mill_delay.h"
#include "core/mill/mill_regenerative.h"
#include "core/propagation.h"

namespace rollgap::core {
namespace mill_limit_sensitivity_detail {

Mill moved(const Mill& mill, const std::vector<MillNumber>& numbers, int j, int sign,
           double speed) {
    Mill m = mill;
    m.speed = speed;
    if (j >= 0) {
        const MillNumber& number = numbers[static_cast<std::size_t>(j)];
        number.shift(m, sign * number.step);
    }
    return m;
}

// The margin of `crossing` of the mill `m` at its own speed (docs/model.md §13.6); `root` is the
// nominal-delay crossing's root at the crossing, followed from there.
std::optional<double> crossing_margin(const Mill& m, MillCrossingKind kind,
                                      std::complex<double> root) {
    const MillTransfer l = mill_transfer(m);
    if (!l.ok) return std::nullopt;
    switch (kind) {
        case MillCrossingKind::frozen: return -l.transfer.frozen_max_real_part;
        case MillCrossingKind::delay_independent: {
            if (!(l.transfer.frozen_max_real_part < 0.0)) return std::nullopt;
            const RegenerativeMargin rho = regenerative_margin(l.transfer);
            if (!rho.ok) return std::nullopt;
            return 1.0 - rho.margin;
        }
        case MillCrossingKind::nominal_delay: {
            const DelayRoot moved = delay_root(l.transfer, root);
            // the same root: converged near where it was (a tenth of its frequency)
            if (!moved.converged || !(moved.residual < 1e-8) ||
                !(std::abs(moved.s - root) < 0.1 * std::abs(root)))
                return std::nullopt;
            return -moved.s.real();
        }
    }
    return std::nullopt;
}

// The posterior's numbers, each differenced over a hundredth of its standard error.
std::vector<MillNumber> posterior_numbers(const MillPosterior& p) {
    std::vector<MillNumber> numbers = p.numbers;
    for (std::size_t j = 0; j < numbers.size(); ++j) {
        const auto at = static_cast<Eigen::Index>(j);
        numbers[j].step = 0.01 * std::sqrt(std::max(p.covariance(at, at), 0.0));
    }
    return numbers;
}

// sqrt(g Σ gᵀ) from the derivatives; nullopt when one is missing for a number that carries
// uncertainty (one known exactly, sigma 0, carries nothing).
std::optional<double> linear_sigma(const ImplicitDerivatives& d, const Eigen::MatrixXd& covariance,
                                   Eigen::VectorXd* gradient = nullptr) {
    if (!d.ok) return std::nullopt;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(covariance.rows());
    for (Eigen::Index j = 0; j < g.size(); ++j) {
        if (!(covariance(j, j) > 0.0)) continue;
        const std::optional<double>& dj = d.derivatives[static_cast<std::size_t>(j)];
        if (!dj) return std::nullopt;
        g(j) = *dj;
    }
    if (gradient != nullptr) *gradient = g;
    return std::sqrt(std::max(g.dot(covariance * g), 0.0));
}

}  // namespace mill_limit_sensitivity_detail

namespace detail_mls = mill_limit_sensitivity_detail;

ImplicitDerivatives mill_crossing_derivatives(const Mill& mill, const MillCrossing& crossing,
                                              const std::vector<MillNumber>& numbers,
                                              const Control& control) {
    ImplicitDerivatives out;
    out.derivatives.assign(numbers.size(), std::nullopt);
    if (crossing.status != CriticalSpeedStatus::found) return out;
    std::complex<double> root{0.0, 2.0 * std::numbers::pi * crossing.frequency_Hz};
    if (crossing.kind == MillCrossingKind::nominal_delay) {
        // the crossing's root itself, from its frequency on the axis
        const MillTransfer l =
            mill_transfer(detail_mls::moved(mill, numbers, -1, 0, crossing.speed));
        if (!l.ok) return out;
        const DelayRoot at = delay_root(l.transfer, root);
        if (!at.converged) return out;
        root = at.s;
    }
    std::vector<double> steps;
    for (const MillNumber& number : numbers) steps.push_back(number.step);
    return implicit_speed_derivatives(
        [&](int j, int sign, double v) {
            return detail_mls::crossing_margin(detail_mls::moved(mill, numbers, j, sign, v),
                                               crossing.kind, root);
        },
        steps, crossing.speed, control);
}

MillSpeedUncertainty mill_crossing_uncertainty(const Mill& mill, const MillCrossing& crossing,
                                               const MillPosterior& posterior, double confidence,
                                               const Control& control) {
    MillSpeedUncertainty out;
    out.critical_speed = crossing.speed;
    const ImplicitDerivatives d = mill_crossing_derivatives(
        mill, crossing, detail_mls::posterior_numbers(posterior), control);
    const std::optional<double> sigma =
        detail_mls::linear_sigma(d, posterior.covariance, &out.gradient);
    if (!sigma) return out;
    out.ok = true;
    out.standard_deviation = *sigma;
    out.lower_bound = crossing.speed - normal_quantile(confidence) * *sigma;
    return out;
}

Propagated mill_sampled_critical_speed(const Mill& mill, const MillPosterior& posterior,
                                       const CriticalSpeedOptions& options, int count,
                                       std::uint64_t seed, const Control& control) {
    const auto n = static_cast<Eigen::Index>(posterior.numbers.size());
    // each draw's search on its own thread: the cancellation is passed on, the pool is not
    Control serial;
    serial.cancelled = control.cancelled;
    const Figure headline = [&](const Eigen::VectorXd& x) -> std::optional<double> {
        Mill m = mill;
        for (Eigen::Index j = 0; j < n; ++j)
            posterior.numbers[static_cast<std::size_t>(j)].shift(m, x(j));
        const MillCriticalSpeeds c = mill_critical_speeds(m, options, serial);
        if (c.headline < 0) return std::nullopt;
        const MillCrossing* crossings[] = {&c.frozen, &c.delay_independent, &c.nominal_delay};
        return crossings[c.headline]->speed;
    };
    return propagate_sampled(headline, Eigen::VectorXd::Zero(n), posterior.covariance, count, seed,
                             control);
}

void bound_mill_plant_limits(const Mill& mill, const MillPlantLimits& limits,
                             SpeedLimitResult& window, const Control& control) {
    if (!limits.posterior) return;
    const MillPosterior& posterior = *limits.posterior;
    const std::vector<MillNumber> numbers = detail_mls::posterior_numbers(posterior);
    std::vector<double> steps;
    for (const MillNumber& n : numbers) steps.push_back(n.step);
    for (LimitAnswer& a : window.limits) {
        if (a.kind == SpeedLimitKind::chatter || a.kind == SpeedLimitKind::steady_state ||
            a.stand < 0 || a.stand >= static_cast<int>(limits.stands.size()))
            continue;
        const auto stand = static_cast<std::size_t>(a.stand);
        for (const bool upper : {false, true}) {
            const std::optional<double> end = upper ? a.upper_speed : a.lower_speed;
            if (!end) continue;
            const ImplicitDerivatives d = implicit_speed_derivatives(
                [&](int j, int sign, double v) -> std::optional<double> {
                    const Mill m = detail_mls::moved(mill, numbers, j, sign, v);
                    const std::vector<SteadyFigures> f = mill_steady_figures(m, v);
                    if (stand >= f.size()) return std::nullopt;
                    return plant_limit_margin(f[stand], limits.stands[stand], a.kind);
                },
                steps, *end, control);
            if (control.should_stop()) return;
            if (const std::optional<double> sigma =
                    detail_mls::linear_sigma(d, posterior.covariance))
                (upper ? a.upper_speed_sd : a.lower_speed_sd) = *sigma;
        }
    }
    bound_window(window, normal_quantile(limits.confidence));
}

MillBindingSensitivity mill_binding_sensitivity(const Mill& mill, const MillPlantLimits& limits,
                                                const MillSpeedLimitResult& result,
                                                const std::vector<MillNumber>& numbers,
                                                const Control& control) {
    MillBindingSensitivity out;
    BindingSensitivity& b = out.binding;
    b.derivatives.assign(numbers.size(), std::nullopt);
    const SpeedLimitResult& window = result.window;
    if (window.status != SpeedLimitStatus::ok || !window.binding_max) return out;
    const SpeedLimitKind kind = *window.binding_max;
    out.stand = window.binding_max_stand;
    if (kind == SpeedLimitKind::chatter) {
        // the range's top stands in for a chatter limit when no crossing inside the model's
        // range was found: nothing to gain by a change
        if (!result.critical || result.critical->headline < 0) return out;
        const MillCriticalSpeeds& critical = *result.critical;
        const MillCrossing* crossings[] = {&critical.frozen, &critical.delay_independent,
                                           &critical.nominal_delay};
        const MillCrossing& c = *crossings[critical.headline];
        b.kind = kind;
        out.crossing = c.kind;
        b.speed = c.speed;
        const ImplicitDerivatives d = mill_crossing_derivatives(mill, c, numbers, control);
        b.ok = d.ok;
        b.margin_slope = d.margin_slope;
        for (std::size_t j = 0; j < numbers.size() && d.ok; ++j)
            if (d.derivatives[j])
                b.derivatives[j] = (1.0 - limits.chatter_margin) * *d.derivatives[j];
        return out;
    }
    b.kind = kind;
    if (kind == SpeedLimitKind::steady_state) return out;
    b.speed = window.window_max;
    for (const LimitAnswer& a : window.limits)
        if (a.kind == kind && a.stand == out.stand && a.upper_speed) b.speed = *a.upper_speed;
    if (out.stand < 0 || out.stand >= static_cast<int>(limits.stands.size())) return out;
    const PlantLimits& stand_limits = limits.stands[static_cast<std::size_t>(out.stand)];
    const std::size_t stand = static_cast<std::size_t>(out.stand);
    std::vector<double> steps;
    for (const MillNumber& number : numbers) steps.push_back(number.step);
    const ImplicitDerivatives d = implicit_speed_derivatives(
        [&](int j, int sign, double v) -> std::optional<double> {
            const Mill m = detail_mls::moved(mill, numbers, j, sign, v);
            const std::vector<SteadyFigures> figures = mill_steady_figures(m, v);
            if (stand >= figures.size()) return std::nullopt;
            return plant_limit_margin(figures[stand], stand_limits, kind);
        },
        steps, b.speed, control);
    b.ok = d.ok;
    b.margin_slope = d.margin_slope;
    b.derivatives = d.derivatives;
    return out;
}

}  // namespace rollgap::core
