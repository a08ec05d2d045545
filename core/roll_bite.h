#pragma once
// The roll-bite model of docs/model.md §1-4: slab pressure equation with mixed-lubrication
// friction, solved by shooting on the neutral point. A pure function of its inputs; failures are
// values.

#include <vector>

#include "core/bite_state.h"
#include "core/roll_flattening.h"
#include "core/scenario.h"

namespace rollgap::core {

enum class Regime { boundary, mixed, full_film };

// One point of a distribution. At the neutral point two points share x (the friction jumps).
struct BitePoint {
    double x;              // m, from the roll centre line (exit, 0) toward the entry (x_w)
    double pressure;       // p, Pa
    double friction;       // tau, Pa, x-component of the traction on the strip (> 0 where u > v)
    double film;           // h, m, mean film thickness in the bite
    double film_ratio;     // H_t = h / Rq
    double contact_ratio;  // A
    double strip_speed;    // u, m/s
    double thickness;      // y, m
    Regime regime;
};

struct BiteResult {
    BiteStatus status = BiteStatus::solver_failure;
    const char* message = "";

    // skidding detail: which end the neutral point left through, and the pressure mismatch
    // (Pa) at the end nearest a root.
    bool skid_at_exit = false;
    double skid_residual = 0.0;

    double roll_radius = 0.0;     // the radius of the arc the bite was solved on (R or R'), m
    double contact_length = 0.0;  // x_w, m
    double inlet_angle = 0.0;     // theta, rad
    double inlet_film = 0.0;      // h0 actually used, m
    double neutral_point = 0.0;   // x_n, m
    double entry_speed = 0.0;     // u1, m/s
    double exit_speed = 0.0;      // u2 = u(0), m/s
    double forward_slip = 0.0;    // (u2 - v) / v
    double force = 0.0;           // P = w int p dx, N
    double torque = 0.0;          // per roll, -w a int tau dx, N m (> 0: roll drives the strip)
    double mean_friction_coefficient = 0.0;  // int |tau| dx / int p dx

    std::vector<BitePoint> distribution;  // ascending x; empty unless asked for
};

struct BiteOptions {
    bool distributions = true;
    // Optional starting guess for the neutral point (m). Only speeds the root search; the
    // result does not depend on it beyond the root tolerance (~1e-14 of x_w).
    double neutral_point_guess = -1.0;
};

// The reference (steady) state of a scenario: y2 = y1 (1 - R), no gap motion, steady film,
// the scenario's mean tensions; with rolls.flattening = hitchcock, the flattened radius of this
// steady state (rigid when the bite has none).
BiteState steady_bite_state(const Scenario& s);

// The flattened radius of the slab bite (docs/model.md §10.3): hitchcock_fixed_point() with the
// roll force of solve_roll_bite() (no distributions) for the bite `state`.
FlatteningResult flattened_radius(const Scenario& s, const BiteState& state,
                                  double relative_tolerance = 1e-12, int max_iterations = 200);

BiteResult solve_roll_bite(const Scenario& s, const BiteState& state,
                           const BiteOptions& options = {});

const char* to_string(BiteStatus);
const char* to_string(Regime);

}  // namespace rollgap::core
