#pragma once
// Elastic roll flattening (docs/model.md, "Roll flattening"): Hitchcock's deformed radius
//   R' = R (1 + c P' / dh),  c = 16 (1 - nu^2) / (pi E),  P' = F / w,  dh = y1 - y2,
// iterated with the roll force F of the bite solved at R' to the fixed point. The bite then
// uses R' for its geometry; the dynamics keep R' frozen at the steady state of each speed.

#include "core/roll_bite.h"
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

// The fixed point R' = hitchcock_radius(F(R')) for the bite `state` (its roll_radius is
// ignored), to `relative_tolerance` of R'. The map has slope (R' - R) / (2 R') < 1/2 when
// F grows like the contact length sqrt(R' dh), so plain iteration contracts.
FlatteningResult flattened_radius(const Scenario& s, const BiteState& state,
                                  double relative_tolerance = 1e-12, int max_iterations = 200);

}  // namespace rollgap::core
