#pragma once
// The mill's frozen stability (docs/model.md §12.4-12.5): the eigenvalues of A0, the mill
// linearised with the thickness transport frozen (tension coupling only), at one mill speed, and
// the frozen critical speed over a range of mill speeds (the single stand's search, §7.3, with
// each speed re-solving the schedule).

#include "core/control.h"
#include "core/mill/mill.h"
#include "core/mill/mill_delay.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_regenerative.h"
#include "core/stability.h"

namespace rollgap::core {

struct MillStability {
    MillSteadyState steady;
    // the eigenvalues and modes of A0 (speed = the mill speed; steady_status ok only when the
    // whole schedule solved; the modes' shapes by stand, read on the stand that moves most)
    SpeedStability frozen;
};

MillStability mill_frozen_stability(const Mill& mill);

// Everything §12.4-12.6 say about one mill speed: the schedule, A0's eigenvalues and modes, the
// regenerative margin rho, the count of roots with the nominal delays right of the imaginary axis
// and the rightmost of them.
// rho's anatomy at the frequency of its peak, per interstand span i (docs/model.md §12.5): the
// thickness the span delivers enters stand i + 1 (its receiving stand), whose bite turns it into
// a force and an entry-speed change, whose structure turns the force into a gap; the loop comes
// back to span i through the tension (M_ii, stand i's exit thickness) and goes on to span i + 1
// through the thickness (M_{i+1,i}, stand i + 1's exit thickness).
struct MarginFactors {
    int span = 0;                    // 0-based interstand span; the receiving stand is span + 1
    double worst_input_share = 0.0;  // |u_i|^2 / |u|^2, u the loop's worst input at the peak
    double tension_loop_gain = 0.0;  // |M_ii(i omega)|: the span's own loop, the tension path
    double thickness_gain = -1.0;    // |M_{i+1,i}(i omega)|; -1 for the last span (none)
    double force_per_entry_thickness = 0.0;        // dF/dy1 of the receiving stand's bite, N/m
    double entry_speed_per_entry_thickness = 0.0;  // du1/dy1 of that bite, 1/s
    double compliance = 0.0;  // |gap / force| of the receiving stand's structure at omega, m/N
};

// The factors of `margin` (its peak frequency, D and M there) for the mill `model` built on (at
// its equilibrium; empty when the margin has no peak): the bite gains by central differences of
// the stand's own bite in its entering thickness (+-1e-6 of it, the film and tensions held: J_b's
// y1 column), the compliance g^T (K_s - omega^2 M + i omega C)^-1 g of its six masses (the
// strip's spring k4 excluded: the bite is the strip).
std::vector<MarginFactors> margin_factors(const Mill& mill, const MillModel& model,
                                          const TransportTransfer& transfer,
                                          const RegenerativeMargin& margin);

struct MillSpeedStability {
    MillSteadyState steady;
    SpeedStability frozen;
    RegenerativeMargin margin;
    std::vector<MarginFactors> factors;  // the margin's per span (margin_factors)
    DelayRootCount nominal;              // alpha = 0
    RightmostDelayRoot rightmost;
    std::vector<double> delay;  // tau_i, s
    // no root right of the axis (A0's and the delays' together), when the count is ok
    bool nominal_stable = false;
    // A0 stable and rho < 1: stable for every set of delays (sufficient; necessary too for up to
    // three spans)
    bool delay_independent_stable = false;
};

MillSpeedStability mill_stability_at(const Mill& mill, const RegenerativeOptions& options = {});

// The frozen critical speed: the lowest mill speed V in the range where A0 turns unstable.
CriticalSpeedResult mill_frozen_critical_speed(const Mill& mill,
                                               const CriticalSpeedOptions& options = {},
                                               const Control& control = {});

}  // namespace rollgap::core
