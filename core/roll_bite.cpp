#include "core/roll_bite.h"

#include <algorithm>
#include <cmath>

#include "core/brent.h"
#include "core/christensen_contact.h"
#include "core/inlet_film.h"

namespace rollgap::core {

BiteState steady_bite_state(const Scenario& s) {
    BiteState state;
    state.entry_thickness = s.strip.entry_thickness;
    state.exit_thickness = exit_thickness(s);
    state.gap_rate = 0.0;
    state.inlet_film = 0.0;
    state.back_tension = s.tensions.back.stress;
    state.front_tension = s.tensions.front.stress;
    if (s.rolls.flattening == RollFlattening::hitchcock) {
        const FlatteningResult flattening = flattened_radius(s, state);
        if (flattening.status == BiteStatus::ok) state.roll_radius = flattening.radius;
    }
    return state;
}

FlatteningResult flattened_radius(const Scenario& s, const BiteState& state,
                                  double relative_tolerance, int max_iterations) {
    const auto force_of = [&s](const BiteState& at) {
        const BiteResult bite = solve_roll_bite(s, at, {false});
        return BiteForce{bite.status, bite.force};
    };
    return hitchcock_fixed_point(s, state, force_of, relative_tolerance, max_iterations);
}

const char* to_string(BiteStatus status) {
    switch (status) {
        case BiteStatus::ok: return "ok";
        case BiteStatus::skidding: return "skidding";
        case BiteStatus::contact_lost: return "contact_lost";
        case BiteStatus::solver_failure: return "solver_failure";
    }
    return "unknown";
}

const char* to_string(Regime regime) {
    switch (regime) {
        case Regime::boundary: return "boundary";
        case Regime::mixed: return "mixed";
        case Regime::full_film: return "full_film";
    }
    return "unknown";
}

namespace {

Regime regime_of(double film_ratio) {
    if (film_ratio < 0.5) return Regime::boundary;
    if (film_ratio <= 3.0) return Regime::mixed;
    return Regime::full_film;
}

// Everything about the bite that does not depend on the trial neutral point.
struct Bite {
    double y1, y2, a, v, sigma, back, front, width;
    double gap_rate;
    double contact_length, inlet_angle;
    double asperity_stress;  // tau_a = m_a sigma / 2
    double rq;               // composite roughness
    double fixed_film;       // h0 > 0, or <= 0 for the steady film h00(u1)
    const Scenario* s;
    int intervals;

    double thickness(double x) const { return y2 + x * x / a; }
};

// Kinematics along one side for one trial neutral point: u, h, A at the RK4 nodes and
// midpoints. They depend on x only (not on p), so they are computed once per side.
struct SidePoint {
    double x, y, u, slip, film, film_ratio, contact;
};

// The traction on one side: the asperity part always opposes the slip, the fluid part is
// Newtonian with Barus viscosity capped by the limiting shear lambda_L p (evaluated in log
// space: gamma p reaches ~700 and exp(gamma p) would overflow). Without the cap the bite
// viscosity is eta0 (docs/model.md §4). `direction` is +1 on the exit side (u > v), -1 on the
// entry side: the slip changes sign at the neutral point and only there.
struct FrictionLaw {
    const Scenario* s;
    double asperity_stress;

    double operator()(const SidePoint& pt, double p, double direction) const {
        const Friction& f = s->friction;
        if (f.model == FrictionModel::coulomb) return direction * f.coulomb_coefficient * p;

        const double speed = std::abs(pt.slip);
        double fluid = 0.0;
        const Lubricant& lub = s->lubricant;
        if (speed > 0.0) {
            if (!lub.limiting_shear) {
                fluid = lub.viscosity * speed / pt.film;
            } else if (p > 0.0) {
                // Newtonian / cap = ratio exp(gamma p); compared through exp(-gamma p), which
                // underflows to 0 (cap wins) where exp(gamma p) would overflow.
                // Beyond gamma p = 700 and ratio 1e-290 the Newtonian stress exceeds the cap by
                // ~1e14: skip exp, whose underflow path is slow.
                const double cap = lub.limiting_shear_coefficient * p;
                const double ratio = lub.viscosity * speed / (pt.film * cap);
                const double gp = lub.pressure_viscosity * p;
                if (gp > 700.0 && ratio > 1e-290) {
                    fluid = cap;
                } else {
                    const double threshold = std::exp(-gp);
                    fluid = ratio < threshold ? cap * (ratio / threshold) : cap;
                }
            }
        }
        return direction * (pt.contact * asperity_stress + (1.0 - pt.contact) * fluid);
    }
};

struct SideResult {
    bool finite = true;
    double end_pressure = 0.0;
    double integral_p = 0.0, integral_tau = 0.0, integral_abs_tau = 0.0;
};

struct Trial {
    double neutral_point, entry_speed, inlet_film;
    bool valid;
};

class BiteSolver {
public:
    BiteSolver(const Bite& bite) : b_(bite), law_{bite.s, bite.asperity_stress} {}

    Trial trial(double xn) const {
        Trial t;
        t.neutral_point = xn;
        t.entry_speed = (b_.v * b_.thickness(xn) + (b_.contact_length - xn) * b_.gap_rate) / b_.y1;
        if (b_.fixed_film > 0.0) {
            t.inlet_film = b_.fixed_film;
        } else {
            const Lubricant& lub = b_.s->lubricant;
            t.inlet_film = wilson_walowit_film(lub.viscosity, lub.pressure_viscosity,
                                               0.5 * (t.entry_speed + b_.v), b_.inlet_angle,
                                               b_.sigma, b_.back);
        }
        t.valid = std::isfinite(t.entry_speed) && std::isfinite(t.inlet_film) &&
                  t.inlet_film > 0.0 && b_.v + t.entry_speed > 0.0;
        return t;
    }

    // Geometry, speed and film at x; the slip and the contact ratio at `inside`, which is x
    // except at the end of a segment next to a jump (the neutral point, a jump of the paper's
    // contact fit), where the segment's one-sided limit is wanted (see integrate()).
    SidePoint point(const Trial& t, double x, double inside) const {
        SidePoint pt;
        pt.x = x;
        pt.y = b_.thickness(x);
        pt.u = (t.entry_speed * b_.y1 - (b_.contact_length - x) * b_.gap_rate) / pt.y;
        // u - v factored so that it vanishes exactly at x_n (continuity with u(x_n) = v):
        // u - v = (x_n - x) (v (x_n + x) / a - dyc/dt) / y.
        const double xn = t.neutral_point;
        pt.slip =
            (xn - inside) * (b_.v * (xn + inside) / b_.a - b_.gap_rate) / b_.thickness(inside);
        pt.film = film_at(t, pt.u);
        pt.film_ratio = pt.film / b_.rq;
        double contact_film_ratio = pt.film_ratio;
        if (inside != x) {
            const double u_inside =
                (t.entry_speed * b_.y1 - (b_.contact_length - inside) * b_.gap_rate) /
                b_.thickness(inside);
            contact_film_ratio = film_at(t, u_inside) / b_.rq;
        }
        pt.contact = b_.s->friction.model == FrictionModel::mixed
                         ? contact_ratio(b_.s->friction.contact, contact_film_ratio)
                         : 0.0;
        return pt;
    }

    // eq. (15)
    double film_at(const Trial& t, double u) const {
        return t.inlet_film * (b_.v + t.entry_speed) / (b_.v + u);
    }

    // Where the paper's fit (26) jumps (H_t = 0.5 and 1.5) inside (lo, hi). H_t(x) = c means
    // v + u(x) = h0 (v + u1) / (c Rq) = v + U, and with continuity u y = u1 y1 - (x_w - x) dyc/dt
    // that is the quadratic (U / a) x^2 - dyc/dt x + U y2 - u1 y1 + x_w dyc/dt = 0.
    int contact_jumps(const Trial& t, double lo, double hi, double out[4]) const {
        int count = 0;
        if (b_.s->friction.model != FrictionModel::mixed ||
            b_.s->friction.contact != ContactModel::paper_fit) {
            return count;
        }
        for (double c : {0.5, 1.5}) {
            const double U = t.inlet_film * (b_.v + t.entry_speed) / (c * b_.rq) - b_.v;
            const double qa = U / b_.a, qb = -b_.gap_rate;
            const double qc = U * b_.y2 - t.entry_speed * b_.y1 + b_.contact_length * b_.gap_rate;
            double roots[2];
            int n = 0;
            if (qa == 0.0) {
                if (qb != 0.0) roots[n++] = -qc / qb;
            } else {
                const double disc = qb * qb - 4 * qa * qc;
                if (disc >= 0.0) {
                    const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
                    roots[n++] = q / qa;
                    if (q != 0.0) roots[n++] = qc / q;
                }
            }
            for (int i = 0; i < n; ++i) {
                if (roots[i] > lo && roots[i] < hi) out[count++] = roots[i];
            }
        }
        for (int i = 1; i < count; ++i) {  // at most four: insertion sort
            for (int j = i; j > 0 && out[j] < out[j - 1]; --j) std::swap(out[j], out[j - 1]);
        }
        return count;
    }

    // dp/dx = (sigma y' + 2 tau) / y, eq. (36) with y' = 2x / a.
    double slope(const SidePoint& pt, double tau) const {
        return (b_.sigma * 2.0 * pt.x / b_.a + 2.0 * tau) / pt.y;
    }

    // Classical RK4 with a fixed number of steps from x_start to x_end (per segment between
    // jumps of the contact law): the same steps for the same inputs, so the solution is a smooth,
    // repeatable function of them. The integrals of p, tau and |tau| ride along as quadratures of
    // the same stages.
    SideResult integrate(const Trial& t, double x_start, double x_end, double p_start,
                         double direction, std::vector<BitePoint>* record) const {
        SideResult r;
        double p = p_start;
        auto emit = [&](const SidePoint& pt, double pressure) {
            if (!record) return;
            record->push_back({pt.x, pressure, law_(pt, pressure, direction), pt.film,
                               pt.film_ratio, pt.contact, pt.u, pt.y, regime_of(pt.film_ratio)});
        };
        emit(point(t, x_start, x_start), p);
        if (x_end == x_start) {  // an empty side: the neutral point sits at the bite's end
            r.end_pressure = p;
            return r;
        }

        double jumps[4];
        const int jump_count =
            contact_jumps(t, std::min(x_start, x_end), std::max(x_start, x_end), jumps);
        double bounds[6];
        int segments = 0;
        bounds[0] = x_start;
        for (int j = 0; j < jump_count; ++j)
            bounds[++segments] = x_end > x_start ? jumps[j] : jumps[jump_count - 1 - j];
        bounds[++segments] = x_end;

        const int n = b_.intervals;
        for (int seg = 0; seg < segments; ++seg) {
            const double a = bounds[seg], b = bounds[seg + 1];
            const double step = (b - a) / n;
            // A segment's ends next to a jump take the segment's one-sided limit, a billionth of a
            // step inside. At the neutral point the fluid stress jumps from +cap to -cap through a
            // layer of width ~ lambda_L p h exp(-gamma p) / (eta0 |d(u - v)/dx|), far below double
            // resolution at the printed gamma; where the layer is resolved this is the continuous
            // value. At a jump of the paper's fit, A takes the branch of the segment.
            SidePoint left = point(t, a, seg == 0 ? a : a + 1e-9 * step);
            if (seg > 0) emit(left, p);
            for (int i = 0; i < n; ++i) {
                const double x_mid = a + (i + 0.5) * step;
                const bool last = i + 1 == n;
                const double x_right = last ? b : a + (i + 1) * step;
                const SidePoint mid = point(t, x_mid, x_mid);
                const SidePoint right = point(t, x_right, last ? b - 1e-9 * step : x_right);
                if (!(b_.v + mid.u > 0.0) || !(b_.v + right.u > 0.0)) {
                    r.finite = false;
                    return r;
                }
                const double t1 = law_(left, p, direction);
                const double k1 = slope(left, t1);
                const double p2 = p + 0.5 * step * k1;
                const double t2 = law_(mid, p2, direction);
                const double k2 = slope(mid, t2);
                const double p3 = p + 0.5 * step * k2;
                const double t3 = law_(mid, p3, direction);
                const double k3 = slope(mid, t3);
                const double p4 = p + step * k3;
                const double t4 = law_(right, p4, direction);
                const double k4 = slope(right, t4);

                r.integral_p += step * (p + 2.0 * p2 + 2.0 * p3 + p4) / 6.0;
                r.integral_tau += step * (t1 + 2.0 * t2 + 2.0 * t3 + t4) / 6.0;
                r.integral_abs_tau +=
                    step * (std::abs(t1) + 2.0 * std::abs(t2) + 2.0 * std::abs(t3) + std::abs(t4)) /
                    6.0;

                p += step * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
                left = right;
                emit(left, p);
            }
        }
        r.end_pressure = p;
        r.finite = std::isfinite(p) && std::isfinite(r.integral_p);
        return r;
    }

    SideResult exit_side(const Trial& t, std::vector<BitePoint>* record = nullptr) const {
        return integrate(t, 0.0, t.neutral_point, b_.sigma - b_.front, +1.0, record);
    }
    SideResult entry_side(const Trial& t, std::vector<BitePoint>* record = nullptr) const {
        return integrate(t, b_.contact_length, t.neutral_point, b_.sigma - b_.back, -1.0, record);
    }

    // Pressure jump at the trial neutral point: entry-side pressure minus exit-side pressure.
    // NaN flags an inconsistent state.
    double residual(double xn) const {
        const Trial t = trial(xn);
        if (!t.valid) return std::nan("");
        const SideResult exit = exit_side(t);
        const SideResult entry = entry_side(t);
        if (!exit.finite || !entry.finite) return std::nan("");
        return entry.end_pressure - exit.end_pressure;
    }

private:
    Bite b_;
    FrictionLaw law_;
};

BiteResult failure(BiteResult r, const char* message) {
    r.status = BiteStatus::solver_failure;
    r.message = message;
    return r;
}

// The root search over the whole bite [0, x_w]. Returns `partial` with status ok and the root
// in `root`, or the skidding / failure result.
BiteResult bracket_and_solve(const BiteSolver& solver, const Bite& b, BiteResult partial,
                             RootResult& root) {
    const double at_exit = solver.residual(0.0);
    const double at_entry = solver.residual(b.contact_length);
    if (!std::isfinite(at_exit) || !std::isfinite(at_entry)) {
        return failure(
            partial,
            "the bite equations gave non-finite values (strip speed or film out of range)");
    }
    // The residual falls from the exit to the entry when a neutral point exists. If it is
    // negative already at the exit, friction cannot build the pressure the exit needs: the
    // neutral point has left through the exit (the rolls slide ahead of the strip).
    if (at_exit <= 0.0 || at_entry >= 0.0) {
        partial.status = BiteStatus::skidding;
        partial.skid_at_exit = at_exit <= 0.0;
        partial.skid_residual = partial.skid_at_exit ? at_exit : at_entry;
        partial.message =
            partial.skid_at_exit
                ? "no neutral point: the rolls slide over the strip (neutral point beyond the exit)"
                : "no neutral point: the strip slides over the rolls (neutral point beyond the entry)";
        return partial;
    }
    root = brent_root([&](double xn) { return solver.residual(xn); }, 0.0, b.contact_length,
                      at_exit, at_entry, 1e-14 * b.contact_length);
    if (!root.converged) return failure(partial, "the neutral-point search did not converge");
    partial.status = BiteStatus::ok;
    return partial;
}

}  // namespace

BiteResult solve_roll_bite(const Scenario& s, const BiteState& state, const BiteOptions& options) {
    BiteResult result;
    Bite b;
    b.s = &s;
    b.y1 = state.entry_thickness_or(s.strip.entry_thickness);
    b.y2 = state.exit_thickness;
    b.a = state.roll_radius > 0.0 ? state.roll_radius : s.rolls.radius;
    b.v = s.rolls.speed;
    b.sigma = s.strip.flow_stress;
    b.back = state.back_tension;
    b.front = state.front_tension;
    b.width = s.strip.width;
    b.gap_rate = state.gap_rate;
    b.asperity_stress = s.friction.asperity_factor * 0.5 * s.strip.flow_stress;
    b.rq = std::hypot(s.roughness.roll_rq, s.roughness.strip_rq);
    b.fixed_film = state.inlet_film;
    b.intervals = std::max(2, s.numerics.bite_intervals);

    const double inputs[] = {b.y1,    b.y2,    b.a,        b.v,  b.sigma,     b.back,
                             b.front, b.width, b.gap_rate, b.rq, b.fixed_film};
    for (double value : inputs) {
        if (!std::isfinite(value)) return failure(result, "non-finite input to the roll bite");
    }
    if (!(b.y2 > 0.0) || !(b.a > 0.0) || !(b.v > 0.0) || !(b.rq > 0.0)) {
        return failure(result,
                       "exit thickness, roll radius, roll speed and roughness must be positive");
    }
    if (!(b.y1 > b.y2)) {
        result.status = BiteStatus::contact_lost;
        result.message =
            "the exit thickness is not below the entry thickness: the rolls do not touch the strip";
        return result;
    }

    b.contact_length = std::sqrt(b.a * (b.y1 - b.y2));
    b.inlet_angle = b.contact_length / b.a;
    result.roll_radius = b.a;
    result.contact_length = b.contact_length;
    result.inlet_angle = b.inlet_angle;

    const BiteSolver solver(b);
    auto residual = [&](double xn) { return solver.residual(xn); };

    // With a guess (time stepping, linearisation, the k4 difference) first try a narrow bracket
    // around it: the root search then converges in a few steps. The root is the same to ~1e-14.
    RootResult root;
    const double guess = options.neutral_point_guess;
    const double half_width = 1e-3 * b.contact_length;
    if (guess - half_width > 0.0 && guess + half_width < b.contact_length) {
        const double lo = residual(guess - half_width), hi = residual(guess + half_width);
        if (std::isfinite(lo) && std::isfinite(hi) && lo > 0.0 && hi < 0.0) {
            root = brent_root(residual, guess - half_width, guess + half_width, lo, hi,
                              1e-14 * b.contact_length);
        }
    }
    if (!root.converged) {
        const BiteResult outcome = bracket_and_solve(solver, b, result, root);
        if (outcome.status != BiteStatus::ok) return outcome;
    }

    const Trial t = solver.trial(root.x);
    std::vector<BitePoint> exit_points, entry_points;
    const SideResult exit = solver.exit_side(t, options.distributions ? &exit_points : nullptr);
    const SideResult entry = solver.entry_side(t, options.distributions ? &entry_points : nullptr);
    if (!exit.finite || !entry.finite)
        return failure(result, "the bite equations gave non-finite values");

    // Mass flow through a gap that closes fast enough can put the strip's entry (or exit) speed
    // at or below zero: the strip would have to enter (or leave) the bite backwards, which is no
    // rolling state the model describes (docs/model.md §1, kinematics), so it is not an answer.
    const double exit_speed = (t.entry_speed * b.y1 - b.contact_length * b.gap_rate) / b.y2;
    if (!(t.entry_speed > 0.0) || !(exit_speed > 0.0))
        return failure(result,
                       "the strip would move backwards through the bite (entry or exit "
                       "speed <= 0): the gap closes faster than the strip feeds it");

    result.status = BiteStatus::ok;
    result.message = "ok";
    result.inlet_film = t.inlet_film;
    result.neutral_point = t.neutral_point;
    result.entry_speed = t.entry_speed;
    result.exit_speed = exit_speed;
    result.forward_slip = (result.exit_speed - b.v) / b.v;
    // The entry side was integrated from x_w down to x_n: its integrals carry the sign of dx < 0.
    const double integral_p = exit.integral_p - entry.integral_p;
    const double integral_tau = exit.integral_tau - entry.integral_tau;
    const double integral_abs_tau = exit.integral_abs_tau - entry.integral_abs_tau;
    result.force = b.width * integral_p;
    // the tractions act on the roll's surface, at its own radius from its axis, flattened or not
    result.torque = -b.width * s.rolls.radius * integral_tau;
    result.mean_friction_coefficient = integral_abs_tau / integral_p;

    if (options.distributions) {
        result.distribution = std::move(exit_points);
        result.distribution.insert(result.distribution.end(), entry_points.rbegin(),
                                   entry_points.rend());
    }
    return result;
}

}  // namespace rollgap::core
