#include "core/roll_flattening.h"

#include <cmath>
#include <numbers>

namespace rollgap::core {

double hitchcock_constant(double youngs_modulus, double poisson_ratio) {
    return 16.0 * (1.0 - poisson_ratio * poisson_ratio) / (std::numbers::pi * youngs_modulus);
}

double hitchcock_radius(const Scenario& s, double force, double reduction_dh) {
    const double c = hitchcock_constant(s.rolls.youngs_modulus, s.rolls.poisson_ratio);
    return s.rolls.radius * (1.0 + c * force / (s.strip.width * reduction_dh));
}

FlatteningResult hitchcock_fixed_point(const Scenario& s, const BiteState& state,
                                       const BiteForceFunction& force_of, double relative_tolerance,
                                       int max_iterations) {
    FlatteningResult out;
    const double dh = state.entry_thickness_or(s.strip.entry_thickness) - state.exit_thickness;
    BiteState at = state;
    at.roll_radius = s.rolls.radius;
    out.radius = s.rolls.radius;
    for (int i = 0; i < max_iterations; ++i) {
        const BiteForce bite = force_of(at);
        out.status = bite.status;
        out.iterations = i + 1;
        // A bite without a steady solution has no force to flatten the rolls with.
        if (bite.status != BiteStatus::ok || !(dh > 0.0)) return out;
        out.force = bite.force;
        const double next = hitchcock_radius(s, bite.force, dh);
        if (!std::isfinite(next)) {
            out.status = BiteStatus::solver_failure;
            return out;
        }
        const bool done = std::abs(next - at.roll_radius) <= relative_tolerance * next;
        at.roll_radius = next;
        out.radius = next;
        if (done) {
            out.converged = true;
            // the force at the converged radius itself, so that R' = R (1 + c F / (w dh)) holds
            const BiteForce final_bite = force_of(at);
            out.status = final_bite.status;
            out.force = final_bite.force;
            return out;
        }
    }
    return out;
}

}  // namespace rollgap::core
