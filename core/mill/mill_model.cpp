#include "core/mill/mill_model.h"

#include <cmath>

#include "core/bite_jacobian.h"
#include "core/span_element.h"

namespace rollgap::core {

MillModel::MillModel(const Mill& mill, const MillSteadyState& steady) {
    const int n = mill.size();
    stands_.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const MillStandState& st = steady.stands[static_cast<std::size_t>(i)];
        const Scenario s = dynamics_scenario(stand_scenario(mill, i, st.roll_speed));
        const ReferenceState ref = reference_state(s, false);
        if (ref.status != BiteStatus::ok && status_ == BiteStatus::ok) {
            status_ = ref.status;
            failed_stand_ = i;
        }
        stands_.emplace_back(s, ref, Excitation{}, StandBlock::state_size * i);
    }
    int next = StandBlock::state_size * n;
    back_span_.assign(static_cast<std::size_t>(n), -1);
    front_span_.assign(static_cast<std::size_t>(n), -1);
    back_stress_.assign(static_cast<std::size_t>(n), 0.0);
    front_stress_.assign(static_cast<std::size_t>(n), 0.0);
    const auto add_span = [&](int upstream, int downstream, double thickness, double length) {
        Span span;
        span.index = next++;
        span.thickness = thickness;
        span.stiffness = mill.youngs_modulus * thickness / length;
        span.upstream = upstream;
        span.downstream = downstream;
        spans_.push_back(span);
        const int k = static_cast<int>(spans_.size()) - 1;
        if (downstream >= 0) back_span_[static_cast<std::size_t>(downstream)] = k;
        if (upstream >= 0) front_span_[static_cast<std::size_t>(upstream)] = k;
    };
    if (mill.entry == MillBoundary::span)
        add_span(-1, 0, mill.thickness.front(), mill.entry_span_length);
    else back_stress_.front() = mill.entry_tension;
    for (int i = 0; i + 1 < n; ++i)
        add_span(i, i + 1, mill.thickness[static_cast<std::size_t>(i + 1)],
                 mill.span_length[static_cast<std::size_t>(i)]);
    if (mill.exit == MillBoundary::span)
        add_span(n - 1, -1, mill.thickness.back(), mill.exit_span_length);
    else front_stress_.back() = mill.exit_tension;
    size_ = next;

    if (status_ != BiteStatus::ok) return;
    // at z0 each stand's bite is its reference bite: f(z0) = 0 exactly
    const Eigen::VectorXd z0 = equilibrium();
    for (int i = 0; i < n; ++i)
        stands_[static_cast<std::size_t>(i)].remember(
            bite_state(i, z0.data()), stands_[static_cast<std::size_t>(i)].reference().bite);
}

Eigen::VectorXd MillModel::equilibrium() const {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(size_);
    for (const StandBlock& stand : stands_) stand.equilibrium(z);
    for (const Span& span : spans_) {
        // T = sigma ybar: the stand downstream's back stress, or the exit stress
        const double stress =
            span.downstream >= 0
                ? stands_[static_cast<std::size_t>(span.downstream)].scenario().tensions.back.stress
                : stands_[static_cast<std::size_t>(span.upstream)].scenario().tensions.front.stress;
        z(span.index) = stress * span.thickness;
    }
    return z;
}

int MillModel::back_span(int stand) const {
    const int k = back_span_[static_cast<std::size_t>(stand)];
    return k < 0 ? -1 : spans_[static_cast<std::size_t>(k)].index;
}

int MillModel::front_span(int stand) const {
    const int k = front_span_[static_cast<std::size_t>(stand)];
    return k < 0 ? -1 : spans_[static_cast<std::size_t>(k)].index;
}

BiteState MillModel::bite_state(int i, const double* z) const {
    const StandBlock& stand = stands_[static_cast<std::size_t>(i)];
    const double* q = z + stand.offset();
    const double y1 = stand.scenario().strip.entry_thickness;  // transport frozen
    const double y2 = stand.reference().exit_thickness + (q[2] - q[3]);
    const int back = back_span(i), front = front_span(i);
    const double back_stress = back >= 0 ? z[back] / y1 : back_stress_[static_cast<std::size_t>(i)];
    const double front_stress =
        front >= 0 ? z[front] / y2 : front_stress_[static_cast<std::size_t>(i)];
    return stand.bite_state(0.0, z, back_stress, front_stress);
}

DynamicsStatus MillModel::rhs(double, const double* z, double* zdot) const {
    if (status_ != BiteStatus::ok) return from_bite(status_);
    for (const Span& span : spans_) {
        if (!(z[span.index] > 0.0)) return DynamicsStatus::slack_strip;
    }
    const std::size_t n = stands_.size();
    std::vector<double> du1(n), du2(n);  // the strip speeds' deviations from the reference
    for (std::size_t i = 0; i < n; ++i) {
        const StandBlock& stand = stands_[i];
        const BiteState state = bite_state(static_cast<int>(i), z);
        if (state.back_tension < 0.0 || state.front_tension < 0.0)
            return DynamicsStatus::slack_strip;
        if (!(state.inlet_film > 0.0)) return DynamicsStatus::solver_failure;
        const BiteResult& bite = stand.solve_bite(state);
        if (bite.status != BiteStatus::ok) return from_bite(bite.status);
        stand.rates(z, state, bite, zdot);
        du1[i] = bite.entry_speed - stand.reference().bite.entry_speed;
        du2[i] = bite.exit_speed - stand.reference().bite.exit_speed;
    }
    for (const Span& span : spans_) {
        const double in =
            span.downstream >= 0 ? du1[static_cast<std::size_t>(span.downstream)] : 0.0;
        const double out = span.upstream >= 0 ? du2[static_cast<std::size_t>(span.upstream)] : 0.0;
        zdot[span.index] = span.stiffness * (in - out);
    }
    for (int i = 0; i < size_; ++i) {
        if (!std::isfinite(zdot[i])) return DynamicsStatus::solver_failure;
    }
    return DynamicsStatus::ok;
}

Linearisation MillModel::jacobian(const Eigen::VectorXd& z, double) const {
    Linearisation out;
    if (status_ != BiteStatus::ok) {
        out.status = from_bite(status_);
        return out;
    }
    for (const Span& span : spans_) {
        if (!(z(span.index) > 0.0)) {
            out.status = DynamicsStatus::slack_strip;
            return out;
        }
    }
    const int n = size_;
    out.jacobian = Eigen::MatrixXd::Zero(n, n);
    const std::size_t count = stands_.size();
    std::vector<Eigen::RowVectorXd> du1(count), du2(count);
    constexpr int u1_row = static_cast<int>(BiteOutput::entry_speed);
    constexpr int u2_row = static_cast<int>(BiteOutput::exit_speed);
    for (std::size_t i = 0; i < count; ++i) {
        const StandBlock& stand = stands_[i];
        const BiteState state = bite_state(static_cast<int>(i), z.data());
        if (state.back_tension < 0.0 || state.front_tension < 0.0) {
            out.status = DynamicsStatus::slack_strip;
            return out;
        }
        if (!(state.inlet_film > 0.0)) return out;  // solver_failure
        const BiteResult& bite = stand.solve_bite(state);
        if (bite.status != BiteStatus::ok) {
            out.status = from_bite(bite.status);
            return out;
        }
        // D = d(bite inputs)/dz: the block's own rows, and the tensions s = T / y
        Eigen::Matrix<double, bite_input_count, Eigen::Dynamic> inputs =
            stand.bite_input_derivatives(n);
        constexpr int back_row = static_cast<int>(BiteInput::back_tension);
        constexpr int front_row = static_cast<int>(BiteInput::front_tension);
        constexpr int y2_row = static_cast<int>(BiteInput::exit_thickness);
        const int back = back_span(static_cast<int>(i)), front = front_span(static_cast<int>(i));
        if (back >= 0) inputs(back_row, back) = 1.0 / stand.scenario().strip.entry_thickness;
        if (front >= 0) {
            const double y2 = state.exit_thickness;
            inputs.row(front_row) = (-z(front) / (y2 * y2)) * inputs.row(y2_row);
            inputs(front_row, front) += 1.0 / y2;
        }
        unsigned columns = 0;
        for (int k = 0; k < bite_input_count; ++k) {
            if (inputs.row(k).cwiseAbs().maxCoeff() > 0.0)
                columns |= bite_column(static_cast<BiteInput>(k));
        }
        const BiteJacobian jb = bite_jacobian(stand.scenario(), state, bite, columns);
        if (jb.status != BiteStatus::ok) {
            out.status = from_bite(jb.status);
            return out;
        }
        const Eigen::Matrix<double, bite_output_count, Eigen::Dynamic> outputs =
            jb.derivative * inputs;
        stand.jacobian_rows(state, bite, outputs, inputs, out.jacobian);
        du1[i] = outputs.row(u1_row);
        du2[i] = outputs.row(u2_row);
    }
    for (const Span& span : spans_) {
        Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(n);
        if (span.downstream >= 0) row += du1[static_cast<std::size_t>(span.downstream)];
        if (span.upstream >= 0) row -= du2[static_cast<std::size_t>(span.upstream)];
        out.jacobian.row(span.index) = span.stiffness * row;
    }
    if (!out.jacobian.allFinite()) {
        out.jacobian.resize(0, 0);
        return out;  // solver_failure
    }
    out.status = DynamicsStatus::ok;
    return out;
}

double MillModel::perturbation(int index, const Eigen::VectorXd& z) const {
    if (index < StandBlock::state_size * stand_count()) {
        return StandBlock::perturbation(index % StandBlock::state_size, z(index));
    }
    // a span force: the single stand's tension step (1 kPa) on the span's thickness
    for (const Span& span : spans_) {
        if (span.index == index) return SpanElement::perturbation * span.thickness;
    }
    return SpanElement::perturbation;
}

double MillModel::absolute_tolerance(int index) const {
    if (index < StandBlock::state_size * stand_count())
        return StandBlock::absolute_tolerance(index % StandBlock::state_size);
    for (const Span& span : spans_) {
        if (span.index == index) return SpanElement::absolute_tolerance * span.thickness;
    }
    return SpanElement::absolute_tolerance;
}

int MillModel::margin_count() const { return static_cast<int>(spans_.size()) + stand_count(); }

void MillModel::limit_margins(double, const double* z, double* margins) const {
    int k = 0;
    for (const Span& span : spans_) margins[k++] = z[span.index];
    for (int i = 0; i < stand_count(); ++i)
        margins[k++] = stands_[static_cast<std::size_t>(i)].contact_margin(bite_state(i, z));
}

DynamicsStatus MillModel::margin_status(int index) const {
    return index < static_cast<int>(spans_.size()) ? DynamicsStatus::slack_strip
                                                   : DynamicsStatus::contact_lost;
}

}  // namespace rollgap::core
