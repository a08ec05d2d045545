#include "core/coupled_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rollgap::core {

namespace {

double tension_at(const TensionSide& side, double t) {
    if (side.mode == TensionMode::sinusoid) {
        return side.stress + side.amplitude * std::sin(2.0 * std::numbers::pi * side.frequency * t);
    }
    return side.stress;
}

}  // namespace

CoupledModel::CoupledModel(const Scenario& s, const ReferenceState& reference,
                           Excitation excitation)
    : stand_(s, reference, excitation, 0) {
    int next = StandBlock::state_size;
    const double E = s.strip.youngs_modulus;
    if (s.tensions.back.mode == TensionMode::span)
        back_span_ = SpanElement(next++, E, s.tensions.back.span_length);
    if (s.tensions.front.mode == TensionMode::span)
        front_span_ = SpanElement(next++, E, s.tensions.front.span_length);
    size_ = next;

    // At z0 the bite is the reference bite: seeding the memo with it makes f(z0) = 0 exactly.
    const Eigen::VectorXd z0 = equilibrium();
    stand_.remember(bite_state(0.0, z0.data()), reference.bite);
}

Eigen::VectorXd CoupledModel::equilibrium() const {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(size_);
    stand_.equilibrium(z);
    if (back_span_) z(back_span_->index) = scenario().tensions.back.stress;
    if (front_span_) z(front_span_->index) = scenario().tensions.front.stress;
    return z;
}

double CoupledModel::back_tension(double t, const double* z) const {
    return back_span_ ? z[back_span_->index] : tension_at(scenario().tensions.back, t);
}

double CoupledModel::front_tension(double t, const double* z) const {
    return front_span_ ? z[front_span_->index] : tension_at(scenario().tensions.front, t);
}

BiteState CoupledModel::bite_state(double t, const double* z) const {
    return stand_.bite_state(t, z, back_tension(t, z), front_tension(t, z));
}

double CoupledModel::perturbation(int index, const Eigen::VectorXd& z) const {
    const int local = index - stand_.offset();
    if (local >= 0 && local < StandBlock::state_size)
        return StandBlock::perturbation(local, z(index));
    return SpanElement::perturbation;
}

double CoupledModel::absolute_tolerance(int index) const {
    const int local = index - stand_.offset();
    if (local >= 0 && local < StandBlock::state_size) return StandBlock::absolute_tolerance(local);
    return SpanElement::absolute_tolerance;
}

void CoupledModel::limit_margins(double t, const double* z, double* margins) const {
    const BiteState state = bite_state(t, z);
    const Scenario& s = scenario();
    // A side whose tension is a constant input cannot go slack (a constant zero is legitimate).
    const bool back_varies = back_span_ || s.tensions.back.mode == TensionMode::sinusoid ||
                             stand_.excitation().back_tension_amplitude != 0.0;
    const bool front_varies = front_span_ || s.tensions.front.mode == TensionMode::sinusoid;
    margins[0] = back_varies ? state.back_tension : 1.0;
    if (back_span_) margins[0] = std::min(margins[0], z[back_span_->index]);
    margins[1] = front_varies ? state.front_tension : 1.0;
    if (front_span_) margins[1] = std::min(margins[1], z[front_span_->index]);
    margins[2] = stand_.contact_margin(state);
}

DynamicsStatus CoupledModel::rhs(double t, const double* z, double* zdot,
                                 BiteResult* bite_out) const {
    const BiteState state = bite_state(t, z);
    // A strip cannot push: a span whose tension falls to zero has gone slack, and no tension the
    // bite sees may be compressive. A constant zero tension is a legitimate input.
    const bool slack_span = (back_span_ && z[back_span_->index] <= 0.0) ||
                            (front_span_ && z[front_span_->index] <= 0.0);
    if (slack_span || state.back_tension < 0.0 || state.front_tension < 0.0)
        return DynamicsStatus::slack_strip;
    if (!(state.inlet_film > 0.0)) return DynamicsStatus::solver_failure;

    const BiteResult& bite = stand_.solve_bite(state);
    if (bite.status != BiteStatus::ok) return from_bite(bite.status);
    stand_.rates(z, state, bite, zdot);

    // The entry span runs from a bridle at the steady entry speed into the bite; the exit span
    // from the bite to a coiler at the steady exit speed (core/span_element.h).
    const BiteResult& steady = reference().bite;
    if (back_span_)
        zdot[back_span_->index] = back_span_->rate(bite.entry_speed, steady.entry_speed);
    if (front_span_)
        zdot[front_span_->index] = front_span_->rate(steady.exit_speed, bite.exit_speed);
    for (int i = 0; i < size_; ++i) {
        if (!std::isfinite(zdot[i])) return DynamicsStatus::solver_failure;
    }
    if (bite_out) *bite_out = bite;
    return DynamicsStatus::ok;
}

Linearisation CoupledModel::jacobian(const Eigen::VectorXd& z, double t) const {
    Linearisation out;
    const BiteState state = bite_state(t, z.data());
    // The states the finite-difference Jacobian would visit fail where this one's perturbed
    // bites would: a tension within its step of zero is slack there (as in rhs()), a film that
    // is not positive a solver failure.
    const bool slack_span =
        (back_span_ && z(back_span_->index) - SpanElement::perturbation <= 0.0) ||
        (front_span_ && z(front_span_->index) - SpanElement::perturbation <= 0.0);
    const double back_step = back_span_ ? SpanElement::perturbation : 0.0;
    const double front_step = front_span_ ? SpanElement::perturbation : 0.0;
    if (slack_span || state.back_tension - back_step < 0.0 ||
        state.front_tension - front_step < 0.0) {
        out.status = DynamicsStatus::slack_strip;
        return out;
    }
    if (!(state.inlet_film > 0.0)) return out;  // solver_failure

    const BiteResult bite = stand_.solve_bite(state);  // at z0 the reference bite (the memo)
    if (bite.status != BiteStatus::ok) {
        out.status = from_bite(bite.status);
        return out;
    }

    // D = d(bite inputs)/dz: the stand block's own, and each span's tension, seen one to one
    Eigen::Matrix<double, bite_input_count, Eigen::Dynamic> inputs =
        stand_.bite_input_derivatives(size_);
    if (back_span_) inputs(static_cast<int>(BiteInput::back_tension), back_span_->index) = 1.0;
    if (front_span_) inputs(static_cast<int>(BiteInput::front_tension), front_span_->index) = 1.0;
    // only the bite columns some state moves: y1 is a constant of the single stand
    unsigned columns = 0;
    for (int k = 0; k < bite_input_count; ++k) {
        if (inputs.row(k).cwiseAbs().maxCoeff() > 0.0)
            columns |= bite_column(static_cast<BiteInput>(k));
    }
    // forward sensitivities of the bite: no bite solve beyond the reference one (§6.1)
    const BiteJacobian jb = bite_jacobian(scenario(), state, bite, columns);
    if (jb.status != BiteStatus::ok) {
        out.status = from_bite(jb.status);
        return out;
    }
    const Eigen::Matrix<double, bite_output_count, Eigen::Dynamic> outputs = jb.derivative * inputs;

    out.jacobian = Eigen::MatrixXd::Zero(size_, size_);
    stand_.jacobian_rows(state, bite, outputs, inputs, out.jacobian);
    // s_b' = (E/L_b)(u1 - u1_ref), s_f' = (E/L_f)(u2_ref - u2) (core/span_element.h)
    if (back_span_) {
        out.jacobian.row(back_span_->index) =
            back_span_->stiffness * outputs.row(static_cast<int>(BiteOutput::entry_speed));
    }
    if (front_span_) {
        out.jacobian.row(front_span_->index) =
            -front_span_->stiffness * outputs.row(static_cast<int>(BiteOutput::exit_speed));
    }
    if (!out.jacobian.allFinite()) {
        out.jacobian.resize(0, 0);
        return out;  // solver_failure
    }
    out.status = DynamicsStatus::ok;
    return out;
}

}  // namespace rollgap::core
