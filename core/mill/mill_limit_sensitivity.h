#pragma once
// What to change to run a tandem mill faster (docs/model.md §13.6): the derivative of the mill
// speed at which the binding limit stops the mill, with respect to numbers of the mill (a span's
// tension, an intermediate thickness, a stand's viscosity, roughness or roll radius), by the
// implicit function theorem at that speed, as the single stand's (core/limit_sensitivity.h).
// The margin g(V, x) of a stand's force, torque, power or skid limit is that stand's figure in
// the pass schedule at mill speed V; the chatter limit's is the binding crossing's own:
//   frozen             -max Re lambda(A0), the tension path's least-stable root,
//   delay_independent  1 - rho, the regenerative margin (A0 stable),
//   nominal_delay      -Re s of the crossing root with the nominal delays, followed by Newton
//                      from the root at the crossing (so the same root, not the rightmost).

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/control.h"
#include "core/limit_sensitivity.h"
#include "core/mill/mill.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_speed_limit.h"
#include "core/propagation.h"

namespace rollgap::core {

// A found crossing's speed V_c as a function of the mill's numbers: dV_c/dx per number (m/s per
// SI unit), its margin's slope in V, by implicit_speed_derivatives at V_c. ok false when the
// crossing is not found or its margin has no slope there.
ImplicitDerivatives mill_crossing_derivatives(const Mill& mill, const MillCrossing& crossing,
                                              const std::vector<MillNumber>& numbers,
                                              const Control& control = {});

struct MillBindingSensitivity {
    // the binding limit's kind, where its margin crosses zero, its slope there and the advised
    // speed's derivatives (chatter: (1 - margin) dV_c/dx); kind nullopt when the range's top or
    // nothing binds
    BindingSensitivity binding;
    int stand = -1;  // the binding limit's stand (0-based; chatter: the crossing's moving stand)
    std::optional<MillCrossingKind> crossing;  // chatter: the critical speed that binds
};

// The headline crossing's uncertainty under the mill's posterior (docs/model.md §13.7): its
// gradient by mill_crossing_derivatives (each number differenced over a hundredth of its standard
// error), sigma = sqrt(g Σ gᵀ), the bound V_c − z sigma. ok false without a gradient.
MillSpeedUncertainty mill_crossing_uncertainty(const Mill& mill, const MillCrossing& crossing,
                                               const MillPosterior& posterior, double confidence,
                                               const Control& control = {});

// The headline critical speed at `count` seeded draws from the posterior (propagate_sampled: the
// same draws for the same seed), each draw's mill searched whole as `options` say (one thread a
// draw, the draws side by side): the check on mill_crossing_uncertainty's linear sigma, and on
// its one crossing, since a draw's headline may be another lobe's or another kind's. A draw
// without a headline crossing is a failed sample.
Propagated mill_sampled_critical_speed(const Mill& mill, const MillPosterior& posterior,
                                       const CriticalSpeedOptions& options, int count,
                                       std::uint64_t seed, const Control& control = {});

// Every stand's plant-limit end under limits.posterior: its sigma (LimitAnswer lower_speed_sd /
// upper_speed_sd) from the implicit gradient of its stand's margin at the end, then the window
// at the ends' one-sided bounds (bound_window). Nothing without a posterior.
void bound_mill_plant_limits(const Mill& mill, const MillPlantLimits& limits,
                             SpeedLimitResult& window, const Control& control = {});

// `result` is mill_speed_limit(mill, limits, ...)'s answer.
MillBindingSensitivity mill_binding_sensitivity(const Mill& mill, const MillPlantLimits& limits,
                                                const MillSpeedLimitResult& result,
                                                const std::vector<MillNumber>& numbers,
                                                const Control& control = {});

}  // namespace rollgap::core
