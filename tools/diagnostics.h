#pragma once
// Mechanism diagnostics for the paper reproduction: what the roll bite does to one mode of the
// coupled model, from core::linearise's Jacobian. Used to explain (not to change) the critical
// speeds: which coupling destabilises the mode, how much damping it has to overcome, and the
// lubrication state of the bite at that point.

#include <limits>

#include <Eigen/Dense>

#include "core/scenario.h"

namespace rollgap::tools {

struct ModeDiagnostics {
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    bool ok = false;
    const char* message = "";
    double speed = 0.0;  // m/s

    // The steady bite at this speed (scenario resolution).
    double mean_friction = nan;                         // int |tau| dx / int p dx
    double film_ratio_min = nan, film_ratio_max = nan;  // H_t over the bite
    double contact_ratio_max = nan;                     // A at the entry (largest)
    double inlet_film = nan;                            // h00, m
    double inlet_angle = nan;                           // theta, rad
    double contact_length = nan;                        // x_w, m
    double entry_speed = nan;                           // u1, m/s
    double force = nan;                                 // P, N
    double strip_stiffness = nan;                       // k4 = -dP/dy2, N/m

    // Couplings read off the Jacobian (the same linearisation core uses).
    double dP_dgap = nan;       // dP/dg at the frozen film and tension, N/m
    double dP_dgap_rate = nan;  // dP/d(gdot), N s/m
    double dP_dfilm = nan;      // dP/dh0, N/m
    double dP_dback = nan;      // dP/ds_b, m^2 (NaN unless the back tension is a span state)
    double du1_dgap = nan;      // du1/dg, 1/s (from the span row: (L/E) ds_b'/dg)
    double tension_pole = nan;  // d(s_b')/ds_b, 1/s

    // The tracked mode (the oscillatory eigenvalue nearest to the requested frequency).
    double frequency_Hz = nan;
    double growth_rate = nan;              // Re lambda, 1/s
    double growth_constant_tension = nan;  // with the s_b state removed (tension held at its mean)
    double growth_frozen_film = nan;       // with the h0 state removed (film held at h00)
    double gap_mass = nan;  // 1 / (phi3 - phi4)^2 of the nearest natural mode (mass-normalised), kg

    // Equivalent dampers across the gap at the mode's frequency (N s/m, positive = dissipative):
    // -Im(dP/g)/omega of each path of the force response to a harmonic gap motion.
    double direct_damping = nan;  // -dP/d(gdot)
    double film_damping = nan;    // through the inlet film state h0
    double loop_damping = nan;    // through the entry-span tension state s_b
    double squeeze_estimate =
        nan;  // docs/model.md §2's eulerian squeeze term |dP/dh0| h0 / (2 theta u1bar)
};

// Diagnoses the coupled model of scenario `s` at its own speed, following the oscillatory
// eigenvalue nearest to `mode_frequency_Hz` (<= 0: the least-damped one).
ModeDiagnostics diagnose(const core::Scenario& s, double mode_frequency_Hz);

}  // namespace rollgap::tools
