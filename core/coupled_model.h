#pragma once
// The coupled mill-bite-film model of docs/model.md §6 for one stand: state
// z = (q, q', h0[, s_b][, s_f]), one stand block (core/stand_block.h, 13 states) and a span
// element (core/span_element.h) per tension side in span mode:
//   M q'' + C q' + K_s q = b (P(state) - P_ref)      (k4 cancels, docs/model.md §5)
//   h0'  = inlet film model (§2) with theta, theta', dyc/dt, u1bar of the current state
//   s_b' = (E / L_b) (u1 - u1_ref)                     (span mode)
//   s_f' = (E / L_f) (u2_ref - u2)                     (span mode)
// Each right-hand side solves the roll bite for the current gap, gap rate, film and tensions.
// The analyses take it as a DynamicModel (core/dynamic_model.h).

#include <optional>

#include <Eigen/Dense>

#include "core/dynamic_model.h"
#include "core/stand_structure.h"
#include "core/roll_bite.h"
#include "core/scenario.h"
#include "core/span_element.h"
#include "core/stand_block.h"

namespace rollgap::core {

class CoupledModel final : public DynamicModel {
public:
    CoupledModel(const Scenario& s, const ReferenceState& reference, Excitation excitation = {});

    static constexpr int film_index = StandBlock::film_index;  // the stand block is first
    int size() const override { return size_; }
    int back_tension_index() const { return back_span_ ? back_span_->index : -1; }  // span mode
    int front_tension_index() const { return front_span_ ? front_span_->index : -1; }

    // z0 = (0, 0, h00, tensions)
    Eigen::VectorXd equilibrium() const override;

    // The bite inputs of state z at time t.
    BiteState bite_state(double t, const double* z) const;
    double back_tension(double t, const double* z) const;  // as the span ODE sees it
    double front_tension(double t, const double* z) const;

    // z' = f(t, z). `bite` (optional) receives the bite solved for this state (no distributions;
    // for those, solve_roll_bite(scenario(), bite_state(t, z))).
    DynamicsStatus rhs(double t, const double* z, double* zdot) const override {
        return rhs(t, z, zdot, nullptr);
    }
    DynamicsStatus rhs(double t, const double* z, double* zdot, BiteResult* bite) const;

    // J = df/dz at (t, z), assembled (docs/model.md §6.1): the stack analytic, the bite through
    // one bite linearisation J_b (core/bite_jacobian.h) in the inputs the state moves (y2, the
    // gap rate, h0 and the tensions in span mode: two bite solves each), the film by the chain
    // rule, the spans from J_b's u1 and u2. Equal to finite_difference_jacobian() to rounding
    // and the bite's own noise; a state where a perturbed bite fails is that status, as there.
    Linearisation jacobian(const Eigen::VectorXd& z, double t) const override;

    // solve_roll_bite calls made by this model so far (right-hand sides and linearisations).
    long bite_solves() const { return stand_.bite_solves(); }

    double perturbation(int index, const Eigen::VectorXd& z) const override;
    double absolute_tolerance(int index) const override;

    // Signed distances to the physical limits that have a cheap test, positive inside: the
    // back and front tensions (slack at 0) and y1 - y2 (contact lost at 0). Time integration
    // stops where one crosses zero. Skidding needs the bite and has no margin here.
    static constexpr int limit_count = 3;
    int margin_count() const override { return limit_count; }
    void limit_margins(double t, const double* z, double* margins) const override;
    static DynamicsStatus limit_status(int index) {
        return index < 2 ? DynamicsStatus::slack_strip : DynamicsStatus::contact_lost;
    }
    DynamicsStatus margin_status(int index) const override { return limit_status(index); }

    int stand_count() const override { return 1; }
    int displacement_index(int) const override { return stand_.offset(); }

    const Scenario& scenario() const { return stand_.scenario(); }
    const ReferenceState& reference() const { return stand_.reference(); }
    const StructureMatrices& structure() const { return stand_.structure(); }

private:
    StandBlock stand_;
    std::optional<SpanElement> back_span_, front_span_;
    int size_ = StandBlock::state_size;
};

}  // namespace rollgap::core
