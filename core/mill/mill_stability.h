#pragma once
// The mill's frozen stability (docs/model.md §12.4-12.5): the eigenvalues of A0, the mill
// linearised with the thickness transport frozen (tension coupling only), at one mill speed, and
// the frozen critical speed over a range of mill speeds (the single stand's search, §7.3, with
// each speed re-solving the schedule).

#include "core/control.h"
#include "core/mill/mill.h"
#include "core/mill/mill_delay.h"
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
struct MillSpeedStability {
    MillSteadyState steady;
    SpeedStability frozen;
    RegenerativeMargin margin;
    DelayRootCount nominal;  // alpha = 0
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
