#pragma once
// The stand block of the dynamics (docs/model.md §5-6): one stand's six masses on the strip, its
// roll bite and its inlet film, 13 states (q, q', h0) at an offset in the model's state vector:
//   M q'' + C q' + K_s q = b (P(state) - P_ref)      (k4 cancels, docs/model.md §5)
//   h0'  = inlet film model (§2) with theta, theta', dyc/dt, u1bar of the current state
// The tensions are inputs: span elements (core/span_element.h) or the scenario's constant or
// sinusoidal tension. A model composes stand blocks and span elements (core/coupled_model.h).

#include <Eigen/Dense>

#include "core/bite_jacobian.h"
#include "core/dynamic_model.h"
#include "core/inlet_film.h"
#include "core/stand_structure.h"
#include "core/roll_bite.h"
#include "core/scenario.h"

namespace rollgap::core {

// The steady operating point at the scenario's speed, from which the dynamics start.
struct ReferenceState {
    BiteStatus status = BiteStatus::solver_failure;
    const char* message = "";
    BiteResult bite;               // the steady bite (no distributions)
    double exit_thickness = 0.0;   // y2_ref = y1 (1 - R)
    double strip_stiffness = 0.0;  // k4 = -dP/dy2 at the steady film, N/m
};

// The scenario the dynamics run on: the bite with numerics.dynamics_bite_intervals steps.
Scenario dynamics_scenario(Scenario s);

// k4 by central differences (delta = 1e-7 m) with the film at its steady value h00(y2).
// k4 cancels from the coupled equations; `with_strip_stiffness = false` skips it.
ReferenceState reference_state(const Scenario& s, bool with_strip_stiffness = true);

// An extra back-tension term seen by the bite and the inlet (not by the span ODE): the
// excitation of the amplitude analysis (docs/model.md §7.4).
struct Excitation {
    double back_tension_amplitude = 0.0;  // Pa
    double frequency_Hz = 0.0;
};

DynamicsStatus from_bite(BiteStatus status);

class StandBlock {
public:
    static constexpr int state_size = 13;
    static constexpr int film_index = 12;  // within the block

    StandBlock(const Scenario& s, const ReferenceState& reference, Excitation excitation,
               int offset);

    int offset() const { return offset_; }  // the block's first state in z

    // Writes the block's part of z0 = (0, 0, h00).
    void equilibrium(Eigen::VectorXd& z) const;

    // The bite inputs of state z (the whole vector) at time t under the given tensions.
    BiteState bite_state(double t, const double* z, double back_tension,
                         double front_tension) const;

    // The bite for `state`, from a small memo of exact repeats (most Jacobian columns, and the
    // paired q3/q4 perturbations, repeat a bite state; a repeat returns the same numbers anyway).
    const BiteResult& solve_bite(const BiteState& state) const;
    // Makes `bite` the memo's answer for `state` (the reference bite at z0: f(z0) = 0 exactly).
    void remember(const BiteState& state, const BiteResult& bite) const;

    // The block's 13 rates for state z, whose bite inputs are `state` and bite `bite` (ok).
    // `entry_rate` is dy1/dt, the rate of the entering thickness (a mill stand fed by the stand
    // before it, docs/model.md §12.2); it moves the inlet angle's rate in the film equation only.
    void rates(const double* z, const BiteState& state, const BiteResult& bite, double* zdot,
               double entry_rate = 0.0) const;

    // The derivatives of the bite's inputs with respect to z (rows BiteInput, one column per
    // state of a model of `size` states), as far as this block moves them: y2 = y2_ref + q3 - q4,
    // the gap rate q3' - q4', h0. The tensions and y1 are the model's to fill (span elements, the
    // stand upstream); an input with a zero row is constant for the model (docs/model.md §6.1).
    Eigen::Matrix<double, bite_input_count, Eigen::Dynamic> bite_input_derivatives(int size) const;

    // The block's 13 rows of J = df/dz at a state whose bite inputs are `state` and bite `bite`
    // (ok), assembled (docs/model.md §6.1) from the stack, analytic, and the bite outputs'
    // derivatives `outputs` = J_b D with D = `inputs`, the bite inputs' derivatives (5 x n and
    // 6 x n). The inlet film's own partials are central differences of inlet_film_rate. Writes
    // the block's rows of `jacobian` (n x n) whole, and nothing else.
    void jacobian_rows(const BiteState& state, const BiteResult& bite,
                       const Eigen::Matrix<double, bite_output_count, Eigen::Dynamic>& outputs,
                       const Eigen::Matrix<double, bite_input_count, Eigen::Dynamic>& inputs,
                       Eigen::MatrixXd& jacobian) const;

    // The bite's part of the block's rows for input columns of any kind: `outputs` = J_b D and
    // D = `inputs` (5 x m, 6 x m), `entry_rates` (1 x m or empty) the columns' dy1/dt. Adds to
    // rows offset..offset+12 of `columns` (the force through the stack's M^-1 b, the film by the
    // chain rule); the stack's own terms are jacobian_rows'. The mill's delayed thickness inputs
    // (docs/model.md §12.5) are such columns.
    void add_bite_columns(const BiteState& state, const BiteResult& bite,
                          const Eigen::Matrix<double, bite_output_count, Eigen::Dynamic>& outputs,
                          const Eigen::Matrix<double, bite_input_count, Eigen::Dynamic>& inputs,
                          const Eigen::RowVectorXd& entry_rates, Eigen::MatrixXd& columns) const;

    // solve_roll_bite calls made for this block so far: memo misses and `count_bite_solves`.
    long bite_solves() const { return bite_solves_; }
    void count_bite_solves(long n) const { bite_solves_ += n; }

    // y1 - y2: contact is lost at zero.
    double contact_margin(const BiteState& state) const {
        return state.entry_thickness_or(s_.strip.entry_thickness) - state.exit_thickness;
    }

    // docs/model.md §6, §7.3, by the block's own index: q 1e-7 m, q' 1e-3 m/s, h0 1e-5 h0;
    // tolerances q 1e-10 m, q' 1e-7 m/s, h0 1e-12 m.
    static double perturbation(int local, double value) {
        return local < 6 ? 1e-7 : local < film_index ? 1e-3 : 1e-5 * value;
    }
    static double absolute_tolerance(int local) {
        return local < 6 ? 1e-10 : local < film_index ? 1e-7 : 1e-12;
    }

    const Scenario& scenario() const { return s_; }
    const ReferenceState& reference() const { return ref_; }
    const Excitation& excitation() const { return excitation_; }
    const StructureMatrices& structure() const { return structure_; }

private:
    // The inlet film equation's inputs (§2) at bite inputs `state` and bite `bite`.
    InletFilmInputs film_inputs(const BiteState& state, const BiteResult& bite,
                                double entry_rate = 0.0) const;

    Scenario s_;
    ReferenceState ref_;
    Excitation excitation_;
    StructureMatrices structure_;
    Matrix6 mass_inverse_;
    int offset_ = 0;
    mutable double last_neutral_point_ = -1.0;  // warm start of the root search only

    struct Memo {
        BiteState state;
        BiteResult bite;
    };
    static constexpr int memo_size = 8;
    mutable Memo memo_[memo_size];
    mutable int memo_count_ = 0, memo_next_ = 0;
    mutable long bite_solves_ = 0;
};

}  // namespace rollgap::core
