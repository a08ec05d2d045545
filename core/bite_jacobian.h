#pragma once
// The bite linearisation of docs/model.md §6.1: J_b, the derivatives of the roll bite's outputs
// that the dynamics use (force F, entry and exit speeds u1 and u2, inlet angle theta, torque) with
// respect to its dynamic inputs (entry and exit thickness y1 and y2, gap rate, inlet film h0, back
// and front tension). Two methods: forward sensitivities carried through one pass of the bite
// kernel at the solved neutral point (the one the dynamics use), and central differences of
// solve_roll_bite in each input (the reference it is checked against). A stand's Jacobian is
// assembled from it and the analytic stack (core/stand_block.h); a mill reuses it as it is.

#include <Eigen/Dense>

#include "core/bite_state.h"
#include "core/roll_bite.h"
#include "core/scenario.h"

namespace rollgap::core {

// The rows of J_b.
enum class BiteOutput { force, entry_speed, exit_speed, inlet_angle, torque };
// The columns of J_b, each one bit of a column mask.
enum class BiteInput {
    entry_thickness,
    exit_thickness,
    gap_rate,
    inlet_film,
    back_tension,
    front_tension
};
inline constexpr int bite_output_count = 5;
inline constexpr int bite_input_count = 6;

constexpr unsigned bite_column(BiteInput input) { return 1u << static_cast<unsigned>(input); }
inline constexpr unsigned all_bite_columns = (1u << bite_input_count) - 1u;

// The half-steps of the central differences, the ones the finite-difference Jacobian of the
// dynamics takes on the state components that move each input (docs/model.md §7.3), so that the
// assembled Jacobian reproduces it to rounding: y1 and y2 1e-7 m (q), gap rate 1e-3 m/s (q'),
// h0 1e-5 h0, tensions 1 kPa (span states).
struct BiteSteps {
    double entry_thickness = 1e-7;      // m
    double exit_thickness = 1e-7;       // m
    double gap_rate = 1e-3;             // m/s
    double inlet_film_relative = 1e-5;  // of h0
    double tension = 1e3;               // Pa

    double step(BiteInput input, const BiteState& at) const;
};

struct BiteJacobian {
    // ok, or the status of the first perturbed bite that failed (the derivatives are then
    // incomplete and must not be used); `message` says which input.
    BiteStatus status = BiteStatus::solver_failure;
    const char* message = "";
    // d(output)/d(input), SI units; the columns not asked for are zero.
    Eigen::Matrix<double, bite_output_count, bite_input_count> derivative =
        Eigen::Matrix<double, bite_output_count, bite_input_count>::Zero();
    unsigned columns = 0;   // the columns computed
    int bite_solves = 0;    // solve_roll_bite calls made (differences: two per column)
    int kernel_passes = 0;  // dual-number passes of the bite kernel (sensitivities: one)

    double operator()(BiteOutput output, BiteInput input) const {
        return derivative(static_cast<int>(output), static_cast<int>(input));
    }
};

// J_b at the bite state `at`, whose solved bite (status ok) is `bite`, by forward sensitivities
// (docs/model.md §6.1): the kernel of solve_roll_bite run once more at `bite`'s neutral point x_n
// in dual numbers, seeded in the inputs whose bit is set in `columns` and in x_n; the neutral
// point's own motion follows from the residual staying zero (implicit function theorem). The
// exact derivative of the discrete bite that solve_roll_bite solves, at the cost of about three
// of its integrations and no bite solve. The inlet film must be a given one (at.inlet_film > 0)
// when its column is asked for: a steady film (<= 0) moves with the others.
BiteJacobian bite_jacobian(const Scenario& s, const BiteState& at, const BiteResult& bite,
                           unsigned columns = all_bite_columns);

// The same J_b by central differences of solve_roll_bite (no distributions) in each input asked
// for, warm-started at `bite`'s neutral point, the other inputs held: two bite solves a column.
// A perturbed bite that does not solve is its status (the derivatives are then not given).
BiteJacobian bite_jacobian_differences(const Scenario& s, const BiteState& at,
                                       const BiteResult& bite, unsigned columns = all_bite_columns,
                                       const BiteSteps& steps = {});

}  // namespace rollgap::core
