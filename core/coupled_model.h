#pragma once
// The coupled mill-bite-film model of docs/model.md §6: state z = (q, q', h0[, s_b][, s_f]),
//   M q'' + C q' + K_s q = b (P(state) - P_ref)      (k4 cancels, docs/model.md §5)
//   h0'  = inlet film model (§2) with theta, theta', dyc/dt, u1bar of the current state
//   s_b' = (E / L_b) (u1 - u1_ref)                     (span mode)
//   s_f' = (E / L_f) (u2_ref - u2)                     (span mode)
// Each right-hand side solves the roll bite for the current gap, gap rate, film and tensions.

#include <Eigen/Dense>

#include "core/mill_structure.h"
#include "core/roll_bite.h"
#include "core/scenario.h"

namespace rollgap::core {

// Why a state has no valid right-hand side, or why a run ended.
enum class DynamicsStatus { ok, contact_lost, skidding, slack_strip, solver_failure, cancelled };
const char* to_string(DynamicsStatus);

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

class CoupledModel {
public:
    CoupledModel(const Scenario& s, const ReferenceState& reference, Excitation excitation = {});

    static constexpr int film_index = 12;
    int size() const { return size_; }
    int back_tension_index() const { return back_index_; }    // -1 unless span mode
    int front_tension_index() const { return front_index_; }  // -1 unless span mode

    // z0 = (0, 0, h00, tensions)
    Eigen::VectorXd equilibrium() const;

    // The bite inputs of state z at time t.
    BiteState bite_state(double t, const double* z) const;
    double back_tension(double t, const double* z) const;  // as the span ODE sees it
    double front_tension(double t, const double* z) const;

    // z' = f(t, z). `bite` (optional) receives the bite solved for this state (no distributions;
    // for those, solve_roll_bite(scenario(), bite_state(t, z))).
    DynamicsStatus rhs(double t, const double* z, double* zdot, BiteResult* bite = nullptr) const;

    // Signed distances to the physical limits that have a cheap test, positive inside: the
    // back and front tensions (slack at 0) and y1 - y2 (contact lost at 0). Time integration
    // stops where one crosses zero. Skidding needs the bite and has no margin here.
    static constexpr int limit_count = 3;
    void limit_margins(double t, const double* z, double margins[limit_count]) const;
    static DynamicsStatus limit_status(int index) {
        return index < 2 ? DynamicsStatus::slack_strip : DynamicsStatus::contact_lost;
    }

    const Scenario& scenario() const { return s_; }
    const ReferenceState& reference() const { return ref_; }
    const MillMatrices& mill() const { return mill_; }

private:
    Scenario s_;
    ReferenceState ref_;
    Excitation excitation_;
    MillMatrices mill_;
    Matrix6 mass_inverse_;
    int size_ = 13, back_index_ = -1, front_index_ = -1;
    mutable double last_neutral_point_ = -1.0;  // warm start of the root search only

    // The last few bites solved, by exact inputs: most Jacobian columns (and the paired q3/q4
    // perturbations) repeat a bite state, and a repeat returns the same numbers anyway.
    struct Memo {
        BiteState state;
        BiteResult bite;
    };
    static constexpr int memo_size = 8;
    mutable Memo memo_[memo_size];
    mutable int memo_count_ = 0, memo_next_ = 0;
    const BiteResult& solve_bite(const BiteState& state) const;
};

}  // namespace rollgap::core
