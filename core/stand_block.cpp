#include "core/stand_block.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/inlet_film.h"

namespace rollgap::core {

Scenario dynamics_scenario(Scenario s) {
    s.numerics.bite_intervals = s.numerics.dynamics_bite_intervals;
    return s;
}

ReferenceState reference_state(const Scenario& s, bool with_strip_stiffness) {
    ReferenceState ref;
    const BiteState steady = steady_bite_state(s);
    ref.exit_thickness = steady.exit_thickness;
    ref.bite = solve_roll_bite(s, steady, {false});
    ref.status = ref.bite.status;
    ref.message = ref.bite.message;
    if (ref.status != BiteStatus::ok || !with_strip_stiffness) return ref;

    // The film relaxes in microseconds: k4 is the stiffness at the steady film of each y2.
    const double delta = 1e-7;
    BiteState thinner = steady, thicker = steady;
    thinner.exit_thickness -= delta;
    thicker.exit_thickness += delta;
    const BiteOptions options{false, ref.bite.neutral_point};
    const BiteResult a = solve_roll_bite(s, thinner, options);
    const BiteResult b = solve_roll_bite(s, thicker, options);
    if (a.status != BiteStatus::ok || b.status != BiteStatus::ok) {
        ref.status = a.status != BiteStatus::ok ? a.status : b.status;
        ref.message = "the bite has no steady state within 0.1 um of the reference exit thickness";
        return ref;
    }
    ref.strip_stiffness = -(b.force - a.force) / (2.0 * delta);
    return ref;
}

DynamicsStatus from_bite(BiteStatus status) {
    switch (status) {
        case BiteStatus::ok: return DynamicsStatus::ok;
        case BiteStatus::skidding: return DynamicsStatus::skidding;
        case BiteStatus::contact_lost: return DynamicsStatus::contact_lost;
        case BiteStatus::solver_failure: break;
    }
    return DynamicsStatus::solver_failure;
}

StandBlock::StandBlock(const Scenario& s, const ReferenceState& reference, Excitation excitation,
                       int offset)
    : s_(s), ref_(reference), excitation_(excitation), structure_(structure_matrices(s.structure)),
      offset_(offset) {
    mass_inverse_ = structure_.mass.inverse();
    last_neutral_point_ = ref_.bite.neutral_point;
}

void StandBlock::equilibrium(Eigen::VectorXd& z) const {
    z.segment(offset_, state_size).setZero();
    z(offset_ + film_index) = ref_.bite.inlet_film;
}

BiteState StandBlock::bite_state(double t, const double* z, double back_tension,
                                 double front_tension) const {
    const double* q = z + offset_;
    BiteState state;
    state.entry_thickness = s_.strip.entry_thickness;  // a single stand's y1 is the scenario's
    state.exit_thickness = ref_.exit_thickness + (q[2] - q[3]);
    state.gap_rate = q[8] - q[9];
    state.inlet_film = q[film_index];
    state.back_tension = back_tension;
    if (excitation_.back_tension_amplitude != 0.0) {
        state.back_tension += excitation_.back_tension_amplitude *
                              std::sin(2.0 * std::numbers::pi * excitation_.frequency_Hz * t);
    }
    state.front_tension = front_tension;
    state.roll_radius = ref_.bite.roll_radius;  // flattened or not: frozen at the steady state
    return state;
}

void StandBlock::rates(const double* z, const BiteState& state, const BiteResult& bite,
                       double* zdot, double entry_rate) const {
    const double* x = z + offset_;
    double* xdot = zdot + offset_;
    Eigen::Map<const Vector6> q(x), qdot(x + 6);
    const Vector6 load = gap_direction() * (bite.force - ref_.bite.force);
    const Vector6 qddot =
        mass_inverse_ * (load - structure_.damping * qdot - structure_.structural_stiffness * q);
    for (int i = 0; i < 6; ++i) {
        xdot[i] = x[6 + i];
        xdot[6 + i] = qddot(i);
    }

    xdot[film_index] = inlet_film_rate(s_.inlet_film, film_inputs(state, bite, entry_rate));
}

InletFilmInputs StandBlock::film_inputs(const BiteState& state, const BiteResult& bite,
                                        double entry_rate) const {
    InletFilmInputs film;
    film.inlet_film = state.inlet_film;
    film.inlet_angle = bite.inlet_angle;
    film.gap_rate = state.gap_rate;
    // theta = sqrt((y1 - y2) / a): theta' = (y1' - y2') / (2 a theta), y2' the gap rate
    film.inlet_angle_rate =
        (entry_rate - state.gap_rate) / (2.0 * bite.roll_radius * bite.inlet_angle);
    film.mean_inlet_speed = 0.5 * (bite.entry_speed + s_.rolls.speed);
    film.roll_radius = bite.roll_radius;
    film.viscosity = s_.lubricant.viscosity;
    film.pressure_viscosity = s_.lubricant.pressure_viscosity;
    film.flow_stress = s_.strip.flow_stress;
    film.back_tension = state.back_tension;
    return film;
}

Eigen::Matrix<double, bite_input_count, Eigen::Dynamic> StandBlock::bite_input_derivatives(
    int size) const {
    Eigen::Matrix<double, bite_input_count, Eigen::Dynamic> d =
        Eigen::Matrix<double, bite_input_count, Eigen::Dynamic>::Zero(bite_input_count, size);
    const int y2 = static_cast<int>(BiteInput::exit_thickness);
    const int rate = static_cast<int>(BiteInput::gap_rate);
    d(y2, offset_ + 2) = 1.0;  // the gap g = q3 - q4 (docs/model.md §5)
    d(y2, offset_ + 3) = -1.0;
    d(rate, offset_ + 8) = 1.0;
    d(rate, offset_ + 9) = -1.0;
    d(static_cast<int>(BiteInput::inlet_film), offset_ + film_index) = 1.0;
    return d;
}

namespace {

// The partial derivative of the inlet film rate in one of its inputs, by central differences of
// inlet_film_rate alone (closed form, no bite solve).
template <class Member>
double film_rate_partial(InletFilmModel model, const InletFilmInputs& at, Member member,
                         double step) {
    InletFilmInputs lo = at, hi = at;
    lo.*member -= step;
    hi.*member += step;
    return (inlet_film_rate(model, hi) - inlet_film_rate(model, lo)) / (hi.*member - lo.*member);
}

}  // namespace

void StandBlock::jacobian_rows(
    const BiteState& state, const BiteResult& bite,
    const Eigen::Matrix<double, bite_output_count, Eigen::Dynamic>& outputs,
    const Eigen::Matrix<double, bite_input_count, Eigen::Dynamic>& inputs,
    Eigen::MatrixXd& jacobian) const {
    const int o = offset_;
    jacobian.middleRows(o, state_size).setZero();
    // q' = q' (rows 0..5)
    for (int i = 0; i < 6; ++i) jacobian(o + i, o + 6 + i) = 1.0;

    // q'' = M^-1 (b (F - F_ref) - C q' - K_s q) (rows 6..11): the stack analytic, the force
    // through the bite (§5; k4 cancels)
    const Matrix6 mk = -mass_inverse_ * structure_.structural_stiffness;
    const Matrix6 mc = -mass_inverse_ * structure_.damping;
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            jacobian(o + 6 + i, o + j) += mk(i, j);
            jacobian(o + 6 + i, o + 6 + j) += mc(i, j);
        }
    }
    add_bite_columns(state, bite, outputs, inputs, Eigen::RowVectorXd(), jacobian);
}

void StandBlock::add_bite_columns(
    const BiteState& state, const BiteResult& bite,
    const Eigen::Matrix<double, bite_output_count, Eigen::Dynamic>& outputs,
    const Eigen::Matrix<double, bite_input_count, Eigen::Dynamic>& inputs,
    const Eigen::RowVectorXd& entry_rates, Eigen::MatrixXd& columns) const {
    const int n = static_cast<int>(columns.cols());
    const int o = offset_;
    const Vector6 mb = mass_inverse_ * gap_direction();
    const auto force = outputs.row(static_cast<int>(BiteOutput::force));
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < n; ++j) columns(o + 6 + i, j) += mb(i) * force(j);
    }

    // h0' = g(h0, theta, theta', dyc/dt, u1bar, s_b) of §2, theta' = (y1' - dyc/dt) / (2 a theta):
    // the chain rule through the bite's theta and u1 and the film's own partials
    const InletFilmInputs film = film_inputs(state, bite);
    const InletFilmModel model = s_.inlet_film;
    const double theta = film.inlet_angle, a = film.roll_radius;
    // steps: h0 and theta relative 1e-5 (h0 as the state Jacobian's); g is linear in theta',
    // dyc/dt and u1bar, so any step is exact there; the tension 1 kPa as the span states'
    const double g_h0 =
        film_rate_partial(model, film, &InletFilmInputs::inlet_film, 1e-5 * film.inlet_film);
    const double g_theta =
        film_rate_partial(model, film, &InletFilmInputs::inlet_angle, 1e-5 * theta);
    const double g_theta_rate = film_rate_partial(model, film, &InletFilmInputs::inlet_angle_rate,
                                                  1e-3 / (2.0 * a * theta));
    const double g_gap_rate = film_rate_partial(model, film, &InletFilmInputs::gap_rate, 1e-3);
    const double g_speed = film_rate_partial(model, film, &InletFilmInputs::mean_inlet_speed,
                                             1e-5 * film.mean_inlet_speed);
    const double g_tension = film_rate_partial(model, film, &InletFilmInputs::back_tension, 1e3);

    const auto d_theta = outputs.row(static_cast<int>(BiteOutput::inlet_angle));
    const auto d_u1 = outputs.row(static_cast<int>(BiteOutput::entry_speed));
    const auto d_h0 = inputs.row(static_cast<int>(BiteInput::inlet_film));
    const auto d_rate = inputs.row(static_cast<int>(BiteInput::gap_rate));
    const auto d_sb = inputs.row(static_cast<int>(BiteInput::back_tension));
    // (the state's own y1' is taken as zero: the mill is linearised about its steady state)
    for (int j = 0; j < n; ++j) {
        const double entry_rate = entry_rates.size() > 0 ? entry_rates(j) : 0.0;
        const double d_theta_rate = (entry_rate - d_rate(j)) / (2.0 * a * theta) +
                                    state.gap_rate / (2.0 * a * theta * theta) * d_theta(j);
        columns(o + film_index, j) += g_h0 * d_h0(j) + g_theta * d_theta(j) +
                                      g_theta_rate * d_theta_rate + g_gap_rate * d_rate(j) +
                                      g_speed * 0.5 * d_u1(j) + g_tension * d_sb(j);
    }
}

namespace {
bool same(const BiteState& a, const BiteState& b) {
    return a.entry_thickness == b.entry_thickness && a.exit_thickness == b.exit_thickness &&
           a.gap_rate == b.gap_rate && a.inlet_film == b.inlet_film &&
           a.back_tension == b.back_tension && a.front_tension == b.front_tension &&
           a.roll_radius == b.roll_radius;
}
}  // namespace

void StandBlock::remember(const BiteState& state, const BiteResult& bite) const {
    Memo& slot = memo_[memo_next_];
    memo_next_ = (memo_next_ + 1) % memo_size;
    memo_count_ = std::min(memo_count_ + 1, memo_size);
    slot.state = state;
    slot.bite = bite;
}

const BiteResult& StandBlock::solve_bite(const BiteState& state) const {
    for (int i = 0; i < memo_count_; ++i) {
        if (same(memo_[i].state, state)) return memo_[i].bite;
    }
    Memo& slot = memo_[memo_next_];
    memo_next_ = (memo_next_ + 1) % memo_size;
    memo_count_ = std::min(memo_count_ + 1, memo_size);
    slot.state = state;
    slot.bite = solve_roll_bite(s_, state, {false, last_neutral_point_});
    ++bite_solves_;
    if (slot.bite.status == BiteStatus::ok) last_neutral_point_ = slot.bite.neutral_point;
    return slot.bite;
}

}  // namespace rollgap::core
