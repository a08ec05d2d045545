#include "core/mill/mill_model.h"

#include <algorithm>
#include <cmath>

#include "core/bite_jacobian.h"
#include "core/span_element.h"

namespace rollgap::core {

MillModel::MillModel(const Mill& mill, const MillSteadyState& steady) {
    const int n = mill.size();
    stands_.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const MillStandState& st = steady.stands[static_cast<std::size_t>(i)];
        // the steady state's tensions: the set points, or those speeds mode solved (§12.3)
        Scenario given = stand_scenario(mill, i, st.roll_speed);
        given.tensions.back.stress = st.back_tension;
        given.tensions.front.stress = st.front_tension;
        const Scenario s = dynamics_scenario(given);
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
    // §12.1: a spring is one segment; `segments` cuts every span into n of length L / n
    const int segments = mill.span_model == SpanModel::segments ? mill.span_segments : 1;
    const auto add_span = [&](int upstream, int downstream, double thickness, double length) {
        Span span;
        span.index = next;
        span.segments = segments;
        next += span.size();
        span.thickness = thickness;
        span.stiffness = mill.youngs_modulus * thickness * segments / length;
        span.mass = mill.strip_density * thickness * length / segments;
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
    span_length_ = mill.span_length;
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
        // every segment at the span's force, every node at the steady strip speed (zero)
        for (int k = 0; k < span.segments; ++k) z(span.index + k) = stress * span.thickness;
    }
    return z;
}

int MillModel::back_span(int stand) const {
    const int k = back_span_[static_cast<std::size_t>(stand)];
    return k < 0 ? -1 : spans_[static_cast<std::size_t>(k)].last_force();
}

MillModel::SpanStates MillModel::span_states(int number) const {
    const int count = stand_count();
    for (const Span& span : spans_) {
        if ((span.downstream >= 0 ? span.downstream : count) == number)
            return {span.index, span.size(), span.segments};
    }
    return {};
}

void MillModel::span_rates(const Span& span, const double* z, double behind, double ahead,
                           double* zdot) {
    const int n = span.segments;
    const double* force = z + span.index;
    const double* speed = z + span.first_speed();
    for (int k = 0; k < n; ++k) {
        const double back = k == 0 ? behind : speed[k - 1];
        const double front = k + 1 == n ? ahead : speed[k];
        zdot[span.index + k] = span.stiffness * (front - back);
    }
    for (int k = 0; k + 1 < n; ++k)
        zdot[span.first_speed() + k] = (force[k + 1] - force[k]) / span.mass;
}

int MillModel::front_span(int stand) const {
    const int k = front_span_[static_cast<std::size_t>(stand)];
    return k < 0 ? -1 : spans_[static_cast<std::size_t>(k)].index;
}

BiteState MillModel::bite_state(int i, const double* z, double entry_deviation) const {
    const StandBlock& stand = stands_[static_cast<std::size_t>(i)];
    const double* q = z + stand.offset();
    const double y1 = stand.scenario().strip.entry_thickness + entry_deviation;
    const double y2 = stand.reference().exit_thickness + (q[2] - q[3]);
    const int back = back_span(i), front = front_span(i);
    const double back_stress = back >= 0 ? z[back] / y1 : back_stress_[static_cast<std::size_t>(i)];
    const double front_stress =
        front >= 0 ? z[front] / y2 : front_stress_[static_cast<std::size_t>(i)];
    BiteState state = stand.bite_state(0.0, z, back_stress, front_stress);
    state.entry_thickness = y1;
    return state;
}

DynamicsStatus MillModel::rhs(double t, const double* z, double* zdot) const {
    return rhs_with_transport(t, z, nullptr, nullptr, zdot);
}

DynamicsStatus MillModel::rhs_with_transport(double, const double* z, const double* entry_deviation,
                                             const double* entry_rate, double* zdot) const {
    return evaluate_rates(z, entry_deviation, entry_rate, false, zdot, nullptr, nullptr);
}

DynamicsStatus MillModel::rhs_with_history(double, const double* z, const double* entry_deviation,
                                           const double* entry_rate_per_speed, double* zdot,
                                           double* exit_speed, MillFailure* failure) const {
    return evaluate_rates(z, entry_deviation, entry_rate_per_speed, true, zdot, exit_speed,
                          failure);
}

DynamicsStatus MillModel::evaluate_rates(const double* z, const double* entry_deviation,
                                         const double* entry_rate, bool rate_per_speed,
                                         double* zdot, double* exit_speed,
                                         MillFailure* failure) const {
    if (status_ != BiteStatus::ok) {
        if (failure) failure->stand = failed_stand_;
        return from_bite(status_);
    }
    const int count = stand_count();
    // a span is numbered by the stand behind it: 0 the entry, N the exit (MillFailure)
    const auto span_number = [count](const Span& span) {
        return span.downstream >= 0 ? span.downstream : count;
    };
    for (const Span& span : spans_) {
        for (int k = 0; k < span.segments; ++k) {
            if (!(z[span.index + k] > 0.0)) {  // a slack segment is a slack span
                if (failure) failure->span = span_number(span);
                return DynamicsStatus::slack_strip;
            }
        }
    }
    const std::size_t n = stands_.size();
    std::vector<double> du1(n), du2(n);  // the strip speeds' deviations from the reference
    double upstream_exit_speed = 0.0;    // u2 of the stand before, this evaluation's
    for (std::size_t i = 0; i < n; ++i) {
        const StandBlock& stand = stands_[i];
        const BiteState state =
            bite_state(static_cast<int>(i), z, entry_deviation ? entry_deviation[i] : 0.0);
        if (state.back_tension < 0.0 || state.front_tension < 0.0) {
            if (failure)
                failure->span =
                    state.back_tension < 0.0 ? static_cast<int>(i) : static_cast<int>(i) + 1;
            return DynamicsStatus::slack_strip;
        }
        if (failure) failure->stand = static_cast<int>(i);
        if (!(state.inlet_film > 0.0)) return DynamicsStatus::solver_failure;
        const BiteResult& bite = stand.solve_bite(state);
        if (bite.status != BiteStatus::ok) return from_bite(bite.status);
        if (failure) failure->stand = -1;
        double rate = entry_rate ? entry_rate[i] : 0.0;
        if (rate_per_speed) rate *= upstream_exit_speed;  // stand 0 has no stand upstream
        stand.rates(z, state, bite, zdot, rate);
        du1[i] = bite.entry_speed - stand.reference().bite.entry_speed;
        du2[i] = bite.exit_speed - stand.reference().bite.exit_speed;
        upstream_exit_speed = bite.exit_speed;
        if (exit_speed) exit_speed[i] = bite.exit_speed;
    }
    for (const Span& span : spans_) {
        const double in =
            span.downstream >= 0 ? du1[static_cast<std::size_t>(span.downstream)] : 0.0;
        const double out = span.upstream >= 0 ? du2[static_cast<std::size_t>(span.upstream)] : 0.0;
        span_rates(span, z, out, in, zdot);
    }
    for (int i = 0; i < size_; ++i) {
        if (!std::isfinite(zdot[i])) return DynamicsStatus::solver_failure;
    }
    return DynamicsStatus::ok;
}

Linearisation MillModel::jacobian(const Eigen::VectorXd& z, double) const {
    MillLinearisation assembled;
    assemble(z, false, assembled);
    Linearisation out;
    out.status = assembled.status;
    if (out.status == DynamicsStatus::ok) out.jacobian = std::move(assembled.jacobian);
    return out;
}

MillLinearisation MillModel::linearise(const Eigen::VectorXd& z, bool transport) const {
    MillLinearisation out;
    assemble(z, transport, out);
    return out;
}

void MillModel::assemble(const Eigen::VectorXd& z, bool transport, MillLinearisation& out) const {
    out.status = DynamicsStatus::solver_failure;
    if (status_ != BiteStatus::ok) {
        out.status = from_bite(status_);
        return;
    }
    for (const Span& span : spans_) {
        for (int k = 0; k < span.segments; ++k) {
            if (!(z(span.index + k) > 0.0)) {
                out.status = DynamicsStatus::slack_strip;
                return;
            }
        }
    }
    const int n = size_;
    const std::size_t count = stands_.size();
    // the delayed inputs: the thickness entering stands 2..N, one column each
    const int p = transport ? static_cast<int>(count) - 1 : 0;
    // A0 and B: the same chain rule, B on p more input columns
    Eigen::MatrixXd a0 = Eigen::MatrixXd::Zero(n, n);
    Eigen::MatrixXd input_columns = Eigen::MatrixXd::Zero(n, p);
    Eigen::MatrixXd rate_columns = Eigen::MatrixXd::Zero(n, p);
    std::vector<Eigen::RowVectorXd> du1(count), du2(count);
    constexpr int u1_row = static_cast<int>(BiteOutput::entry_speed);
    constexpr int u2_row = static_cast<int>(BiteOutput::exit_speed);
    constexpr int y1_row = static_cast<int>(BiteInput::entry_thickness);
    constexpr int back_row = static_cast<int>(BiteInput::back_tension);
    constexpr int front_row = static_cast<int>(BiteInput::front_tension);
    constexpr int y2_row = static_cast<int>(BiteInput::exit_thickness);
    for (std::size_t i = 0; i < count; ++i) {
        const StandBlock& stand = stands_[i];
        const BiteState state = bite_state(static_cast<int>(i), z.data());
        if (state.back_tension < 0.0 || state.front_tension < 0.0) {
            out.status = DynamicsStatus::slack_strip;
            return;
        }
        if (!(state.inlet_film > 0.0)) return;  // solver_failure
        const BiteResult& bite = stand.solve_bite(state);
        if (bite.status != BiteStatus::ok) {
            out.status = from_bite(bite.status);
            return;
        }
        // D = d(bite inputs)/d(z, u): the block's own rows, and the tensions s = T / y
        Eigen::Matrix<double, bite_input_count, Eigen::Dynamic> inputs =
            Eigen::Matrix<double, bite_input_count, Eigen::Dynamic>::Zero(bite_input_count, n + p);
        inputs.leftCols(n) = stand.bite_input_derivatives(n);
        const int back = back_span(static_cast<int>(i)), front = front_span(static_cast<int>(i));
        const double y1 = state.entry_thickness_or(stand.scenario().strip.entry_thickness);
        if (back >= 0) inputs(back_row, back) = 1.0 / y1;
        if (front >= 0) {
            const double y2 = state.exit_thickness;
            inputs.row(front_row) = (-z(front) / (y2 * y2)) * inputs.row(y2_row);
            inputs(front_row, front) += 1.0 / y2;
        }
        const int input = static_cast<int>(i) - 1;  // stand i's entering thickness, i >= 1
        if (transport && input >= 0) {
            inputs(y1_row, n + input) = 1.0;
            if (back >= 0) inputs(back_row, n + input) = -z(back) / (y1 * y1);  // s_b = T / y1
        }
        unsigned bite_columns = 0;
        for (int k = 0; k < bite_input_count; ++k) {
            if (inputs.row(k).cwiseAbs().maxCoeff() > 0.0)
                bite_columns |= bite_column(static_cast<BiteInput>(k));
        }
        const BiteJacobian jb = bite_jacobian(stand.scenario(), state, bite, bite_columns);
        if (jb.status != BiteStatus::ok) {
            out.status = from_bite(jb.status);
            return;
        }
        const Eigen::Matrix<double, bite_output_count, Eigen::Dynamic> outputs =
            bite_gain_.empty()
                ? Eigen::Matrix<double, bite_output_count, Eigen::Dynamic>(jb.derivative * inputs)
                : Eigen::Matrix<double, bite_output_count, Eigen::Dynamic>(
                      bite_gain_[i] * (jb.derivative * inputs));
        // the stand's rows of A0 (the stack's own terms), then the bite's part on every column
        stand.jacobian_rows(state, bite, outputs.leftCols(n), inputs.leftCols(n), a0);
        if (transport && input >= 0) {
            stand.add_bite_columns(state, bite, outputs.rightCols(p), inputs.rightCols(p),
                                   Eigen::RowVectorXd::Zero(p), input_columns);
            // y1' moves only the inlet angle's rate in the film equation (§12.2)
            Eigen::RowVectorXd rates = Eigen::RowVectorXd::Zero(p);
            rates(input) = 1.0;
            stand.add_bite_columns(
                state, bite,
                Eigen::Matrix<double, bite_output_count, Eigen::Dynamic>::Zero(bite_output_count,
                                                                               p),
                Eigen::Matrix<double, bite_input_count, Eigen::Dynamic>::Zero(bite_input_count, p),
                rates, rate_columns);
        }
        du1[i] = outputs.row(u1_row);
        du2[i] = outputs.row(u2_row);
    }
    for (const Span& span : spans_) {
        // the end segments see the stands' speeds; inside, the chain of §12.1 (constant rows)
        const int segments = span.segments;
        Eigen::RowVectorXd first = Eigen::RowVectorXd::Zero(n + p);
        Eigen::RowVectorXd last = Eigen::RowVectorXd::Zero(n + p);
        if (span.upstream >= 0) first -= du2[static_cast<std::size_t>(span.upstream)];
        if (span.downstream >= 0) last += du1[static_cast<std::size_t>(span.downstream)];
        if (segments == 1) {
            first += last;
        } else {
            first(span.first_speed()) += 1.0;
            last(span.first_speed() + segments - 2) -= 1.0;
            for (int k = 1; k + 1 < segments; ++k) {
                a0(span.index + k, span.first_speed() + k) = span.stiffness;
                a0(span.index + k, span.first_speed() + k - 1) = -span.stiffness;
            }
            for (int k = 0; k + 1 < segments; ++k) {
                a0(span.first_speed() + k, span.index + k + 1) = 1.0 / span.mass;
                a0(span.first_speed() + k, span.index + k) = -1.0 / span.mass;
            }
            a0.row(span.last_force()) = span.stiffness * last.head(n);
            if (p > 0) input_columns.row(span.last_force()) = span.stiffness * last.tail(p);
        }
        a0.row(span.index) = span.stiffness * first.head(n);
        // (a mill of one stand has no delayed input: no zero-width block of an empty matrix)
        if (p > 0) input_columns.row(span.index) = span.stiffness * first.tail(p);
    }
    if (!a0.allFinite() || !input_columns.allFinite() || !rate_columns.allFinite())
        return;  // solver_failure
    out.jacobian = std::move(a0);
    out.exit_speed = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(count), n);
    for (std::size_t i = 0; i < count; ++i)
        out.exit_speed.row(static_cast<Eigen::Index>(i)) = du2[i].head(n);
    if (transport) {
        out.input = std::move(input_columns);
        out.input_rate = std::move(rate_columns);
        out.output = Eigen::MatrixXd::Zero(p, n);
        out.delay.resize(static_cast<std::size_t>(p));
        for (int i = 0; i < p; ++i) {
            const StandBlock& stand = stands_[static_cast<std::size_t>(i)];
            out.output(i, stand.offset() + 2) = 1.0;  // y2 = y2_ref + q3 - q4 (§5)
            out.output(i, stand.offset() + 3) = -1.0;
            out.delay[static_cast<std::size_t>(i)] =
                span_length_[static_cast<std::size_t>(i)] / stand.reference().bite.exit_speed;
        }
    }
    out.status = DynamicsStatus::ok;
}

double MillModel::perturbation(int index, const Eigen::VectorXd& z) const {
    if (index < StandBlock::state_size * stand_count()) {
        return StandBlock::perturbation(index % StandBlock::state_size, z(index));
    }
    // a span force: the single stand's tension step (1 kPa) on the span's thickness; a node
    // speed: the step whose segment force change over 1 ms is that force step
    for (const Span& span : spans_) {
        if (index >= span.index && index < span.index + span.size()) {
            const double force = SpanElement::perturbation * span.thickness;
            return index < span.first_speed() ? force : force / (span.stiffness * 1e-3);
        }
    }
    return SpanElement::perturbation;
}

double MillModel::absolute_tolerance(int index) const {
    if (index < StandBlock::state_size * stand_count())
        return StandBlock::absolute_tolerance(index % StandBlock::state_size);
    for (const Span& span : spans_) {
        if (index >= span.index && index < span.index + span.size()) {
            const double force = SpanElement::absolute_tolerance * span.thickness;
            return index < span.first_speed() ? force : force / (span.stiffness * 1e-3);
        }
    }
    return SpanElement::absolute_tolerance;
}

int MillModel::margin_count() const { return static_cast<int>(spans_.size()) + stand_count(); }

void MillModel::limit_margins(double, const double* z, double* margins) const {
    int k = 0;
    // one margin per span: its least segment force (a slack segment is a slack span)
    for (const Span& span : spans_) {
        double least = z[span.index];
        for (int j = 1; j < span.segments; ++j) least = std::min(least, z[span.index + j]);
        margins[k++] = least;
    }
    for (int i = 0; i < stand_count(); ++i)
        margins[k++] = stands_[static_cast<std::size_t>(i)].contact_margin(bite_state(i, z));
}

DynamicsStatus MillModel::margin_status(int index) const {
    return index < static_cast<int>(spans_.size()) ? DynamicsStatus::slack_strip
                                                   : DynamicsStatus::contact_lost;
}

}  // namespace rollgap::core
