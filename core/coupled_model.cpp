#include "core/coupled_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/inlet_film.h"

namespace rollgap::core {

const char* to_string(DynamicsStatus status) {
    switch (status) {
        case DynamicsStatus::ok: return "ok";
        case DynamicsStatus::contact_lost: return "contact_lost";
        case DynamicsStatus::skidding: return "skidding";
        case DynamicsStatus::slack_strip: return "slack_strip";
        case DynamicsStatus::solver_failure: return "solver_failure";
        case DynamicsStatus::cancelled: return "cancelled";
    }
    return "unknown";
}

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

namespace {

double tension_at(const TensionSide& side, double t) {
    if (side.mode == TensionMode::sinusoid) {
        return side.stress + side.amplitude * std::sin(2.0 * std::numbers::pi * side.frequency * t);
    }
    return side.stress;
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

}  // namespace

CoupledModel::CoupledModel(const Scenario& s, const ReferenceState& reference,
                           Excitation excitation)
    : s_(s), ref_(reference), excitation_(excitation), mill_(mill_matrices(s.mill)) {
    mass_inverse_ = mill_.mass.inverse();
    last_neutral_point_ = ref_.bite.neutral_point;
    int next = 13;
    if (s_.tensions.back.mode == TensionMode::span) back_index_ = next++;
    if (s_.tensions.front.mode == TensionMode::span) front_index_ = next++;
    size_ = next;

    // At z0 the bite is the reference bite: seeding the memo with it makes f(z0) = 0 exactly.
    const Eigen::VectorXd z0 = equilibrium();
    memo_[0] = {bite_state(0.0, z0.data()), ref_.bite};
    memo_count_ = 1;
    memo_next_ = 1;
}

Eigen::VectorXd CoupledModel::equilibrium() const {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(size_);
    z(film_index) = ref_.bite.inlet_film;
    if (back_index_ >= 0) z(back_index_) = s_.tensions.back.stress;
    if (front_index_ >= 0) z(front_index_) = s_.tensions.front.stress;
    return z;
}

double CoupledModel::back_tension(double t, const double* z) const {
    return back_index_ >= 0 ? z[back_index_] : tension_at(s_.tensions.back, t);
}

double CoupledModel::front_tension(double t, const double* z) const {
    return front_index_ >= 0 ? z[front_index_] : tension_at(s_.tensions.front, t);
}

BiteState CoupledModel::bite_state(double t, const double* z) const {
    BiteState state;
    state.exit_thickness = ref_.exit_thickness + (z[2] - z[3]);
    state.gap_rate = z[8] - z[9];
    state.inlet_film = z[film_index];
    state.back_tension = back_tension(t, z);
    if (excitation_.back_tension_amplitude != 0.0) {
        state.back_tension += excitation_.back_tension_amplitude *
                              std::sin(2.0 * std::numbers::pi * excitation_.frequency_Hz * t);
    }
    state.front_tension = front_tension(t, z);
    state.roll_radius = ref_.bite.roll_radius;  // flattened or not: frozen at the steady state
    return state;
}

void CoupledModel::limit_margins(double t, const double* z, double margins[limit_count]) const {
    const BiteState state = bite_state(t, z);
    // A side whose tension is a constant input cannot go slack (a constant zero is legitimate).
    const bool back_varies = back_index_ >= 0 || s_.tensions.back.mode == TensionMode::sinusoid ||
                             excitation_.back_tension_amplitude != 0.0;
    const bool front_varies = front_index_ >= 0 || s_.tensions.front.mode == TensionMode::sinusoid;
    margins[0] = back_varies ? state.back_tension : 1.0;
    if (back_index_ >= 0) margins[0] = std::min(margins[0], z[back_index_]);
    margins[1] = front_varies ? state.front_tension : 1.0;
    if (front_index_ >= 0) margins[1] = std::min(margins[1], z[front_index_]);
    margins[2] = s_.strip.entry_thickness - state.exit_thickness;
}

DynamicsStatus CoupledModel::rhs(double t, const double* z, double* zdot,
                                 BiteResult* bite_out) const {
    const BiteState state = bite_state(t, z);
    // A strip cannot push: a span whose tension falls to zero has gone slack, and no tension the
    // bite sees may be compressive. A constant zero tension is a legitimate input.
    const bool slack_span = (back_index_ >= 0 && z[back_index_] <= 0.0) ||
                            (front_index_ >= 0 && z[front_index_] <= 0.0);
    if (slack_span || state.back_tension < 0.0 || state.front_tension < 0.0)
        return DynamicsStatus::slack_strip;
    if (!(state.inlet_film > 0.0)) return DynamicsStatus::solver_failure;

    const BiteResult& bite = solve_bite(state);
    if (bite.status != BiteStatus::ok) return from_bite(bite.status);

    Eigen::Map<const Vector6> q(z), qdot(z + 6);
    const Vector6 load = gap_direction() * (bite.force - ref_.bite.force);
    const Vector6 qddot =
        mass_inverse_ * (load - mill_.damping * qdot - mill_.structural_stiffness * q);
    for (int i = 0; i < 6; ++i) {
        zdot[i] = z[6 + i];
        zdot[6 + i] = qddot(i);
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
    zdot[film_index] = inlet_film_rate(s_.inlet_film, film);

    if (back_index_ >= 0) {
        zdot[back_index_] = s_.strip.youngs_modulus / s_.tensions.back.span_length *
                            (bite.entry_speed - ref_.bite.entry_speed);
    }
    if (front_index_ >= 0) {
        zdot[front_index_] = s_.strip.youngs_modulus / s_.tensions.front.span_length *
                             (ref_.bite.exit_speed - bite.exit_speed);
    }
    for (int i = 0; i < size_; ++i) {
        if (!std::isfinite(zdot[i])) return DynamicsStatus::solver_failure;
    }
    if (bite_out) *bite_out = bite;
    return DynamicsStatus::ok;
}

namespace {
bool same(const BiteState& a, const BiteState& b) {
    return a.exit_thickness == b.exit_thickness && a.gap_rate == b.gap_rate &&
           a.inlet_film == b.inlet_film && a.back_tension == b.back_tension &&
           a.front_tension == b.front_tension && a.roll_radius == b.roll_radius;
}
}  // namespace

const BiteResult& CoupledModel::solve_bite(const BiteState& state) const {
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
