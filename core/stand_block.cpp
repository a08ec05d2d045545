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
                       double* zdot) const {
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

    InletFilmInputs film;
    film.inlet_film = state.inlet_film;
    film.inlet_angle = bite.inlet_angle;
    film.gap_rate = state.gap_rate;
    film.inlet_angle_rate = -state.gap_rate / (2.0 * bite.roll_radius * bite.inlet_angle);
    film.mean_inlet_speed = 0.5 * (bite.entry_speed + s_.rolls.speed);
    film.roll_radius = bite.roll_radius;
    film.viscosity = s_.lubricant.viscosity;
    film.pressure_viscosity = s_.lubricant.pressure_viscosity;
    film.flow_stress = s_.strip.flow_stress;
    film.back_tension = state.back_tension;
    xdot[film_index] = inlet_film_rate(s_.inlet_film, film);
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
    if (slot.bite.status == BiteStatus::ok) last_neutral_point_ = slot.bite.neutral_point;
    return slot.bite;
}

}  // namespace rollgap::core
