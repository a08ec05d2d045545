#pragma once
// What to change to run faster (docs/model.md §13.4): the derivative of the speed at which the
// binding limit stops a stand, with respect to numbers of its scenario, by the implicit function
// theorem at that speed. A limit binds where its margin g(V, x) crosses zero, so along the
// crossing dV*/dx = −(∂g/∂x) / (∂g/∂V): two differences in x and two in V at the binding speed
// instead of a new search per number. The margin is the steady figure's (force, torque, power,
// forward slip) for those limits and the growth rate of the least-stable root (the largest real
// part of the linearisation's eigenvalues) for chatter, whose limit (V_c − zσ)(1 − m) moves by
// (1 − m) dV_c/dx (σ held).
#include <functional>
#include <optional>
#include <vector>

#include "core/control.h"
#include "core/scenario.h"
#include "core/speed_limit.h"

namespace rollgap::core {

// A scenario number and the step to difference it with (SI).
struct ScenarioNumber {
    std::function<double&(Scenario&)> number;
    double step = 0.0;
};

struct BindingSensitivity {
    // What sets the advised speed; nullopt when it is the range's own end (nothing to gain by a
    // change) or there is no window.
    std::optional<SpeedLimitKind> kind;
    bool ok = false;     // derivatives computed (not for steady_state, nor without a kind)
    double speed = 0.0;  // where the margin crosses zero: the window's end, or V_c for chatter
    double margin_slope = 0.0;  // ∂g/∂V there, per m/s
    // d(advised speed)/dx per number, m/s per SI unit: central differences, one-sided where one
    // side has no answer (a field at its bound); nullopt where neither side has one
    std::vector<std::optional<double>> derivatives;
};

// A plant limit's margin on steady figures (>= 0 where they are permitted): limit − figure for
// the force, torque and power, slip − minimum for the skid margin; nullopt for chatter and the
// steady state, a limit not given, or figures that are not ok.
std::optional<double> plant_limit_margin(const SteadyFigures& figures, const PlantLimits& limits,
                                         SpeedLimitKind kind);

// The implicit derivatives dV*/dx_j = −(∂g/∂x_j) / (∂g/∂V) of a crossing g(V*, x) = 0 at `speed`,
// for any model (a stand, a mill): margin(j, sign, v) is g at speed v with number j moved by
// sign · steps[j] (sign ±1), or unmoved (j = -1, sign 0). ∂g/∂V is a central difference over
// 1e-4 of the speed, ∂g/∂x_j one over steps[j] (one-sided where one side has no answer, nullopt
// where neither has): 2n + 3 evaluations side by side on the control's threads.
struct ImplicitDerivatives {
    bool ok = false;  // ∂g/∂V found and nonzero
    double margin_slope = 0.0;
    std::vector<std::optional<double>> derivatives;  // m/s per SI unit
};
using CrossingMargin = std::function<std::optional<double>(int number, int sign, double speed)>;
ImplicitDerivatives implicit_speed_derivatives(const CrossingMargin& margin,
                                               const std::vector<double>& steps, double speed,
                                               const Control& control = {});

// `result` is speed_limit(s, limits, ...)'s answer (its binding end and critical speed).
BindingSensitivity binding_sensitivity(const Scenario& s, const PlantLimits& limits,
                                       const SpeedLimitResult& result,
                                       const std::vector<ScenarioNumber>& numbers,
                                       const Control& control = {});

}  // namespace rollgap::core
