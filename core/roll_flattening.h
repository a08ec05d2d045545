#pragma once
// Elastic roll flattening (docs/model.md §10.3): Hitchcock's deformed radius
//   R' = R (1 + c P' / dh),  c = 16 (1 - nu^2) / (pi E),  P' = F / w,  dh = y1 - y2,
// iterated with the roll force F of the bite solved at R' to the fixed point. The bite then
// uses R' for its geometry; the dynamics keep R' frozen at the steady state of each speed.
//
// This file knows Hitchcock's formula and the iteration, not the bite: the force comes in as a
// function, so the bite solver (core/roll_bite.h) can use the fixed point without a loop between
// the two (flattened_radius() in core/roll_bite.h passes solve_roll_bite's force).

#include <functional>

#include "core/bite_state.h"
#include "core/scenario.h"

namespace rollgap::core {

// c = 16 (1 - nu^2) / (pi E), 1/Pa.
double hitchcock_constant(double youngs_modulus, double poisson_ratio);

// R (1 + c F / (w dh)): the radius Hitchcock's formula gives for the force F.
double hitchcock_radius(const Scenario& s, double force, double reduction_dh);

struct FlatteningResult {
    BiteStatus status = BiteStatus::solver_failure;  // of the last bite solved
    bool converged = false;
    double radius = 0.0;  // R', m (R when the bite has no force to flatten it)
    double force = 0.0;   // F at R', N
    int iterations = 0;
};

// The roll force of the bite `state` (on the arc of state.roll_radius) and the status of its
// solve; the force counts only when the status is ok.
struct BiteForce {
    BiteStatus status = BiteStatus::solver_failure;
    double force = 0.0;  // N
};
using BiteForceFunction = std::function<BiteForce(const BiteState&)>;

// The fixed point R' = hitchcock_radius(F(R')) for the bite `state` (its roll_radius is
// ignored), to `relative_tolerance` of R', with F given by `force_of`. The map has slope
// (R' - R) / (2 R') < 1/2 when F grows like the contact length sqrt(R' dh), so plain iteration
// contracts.
FlatteningResult hitchcock_fixed_point(const Scenario& s, const BiteState& state,
                                       const BiteForceFunction& force_of,
                                       double relative_tolerance = 1e-12, int max_iterations = 200);

}  // namespace rollgap::core
