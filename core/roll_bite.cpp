#include "core/roll_bite.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/brent.h"
#include "core/bite_kernel.h"
#include "core/dual.h"

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

using bite_kernel::Bite;
using bite_kernel::BiteSolver;
using bite_kernel::SideResult;
using bite_kernel::Trial;

BiteResult failure(BiteResult r, const char* message) {
    r.status = BiteStatus::solver_failure;
    r.message = message;
    return r;
}

// The residual of BiteSolver::residual, remembering the last few trials it integrated: the root
// search returns one of the points it evaluated, whose two sides then need no second integration
// (unless the distributions are recorded). The same arithmetic as BiteSolver::residual.
class RememberingResidual {
public:
    struct Evaluated {
        double x = std::nan("");  // none yet
        Trial<double> trial{};
        SideResult<double> exit, entry;
    };

    explicit RememberingResidual(const BiteSolver<double>& solver) : solver_(&solver) {}

    double operator()(double xn) {
        const Trial<double> t = solver_->trial(xn);
        if (!t.valid) return std::nan("");
        Evaluated& e = ring_[next_++ % ring_.size()];
        e.x = xn;
        e.trial = t;
        e.exit = solver_->exit_side(t);
        e.entry = solver_->entry_side(t);
        if (!e.exit.finite || !e.entry.finite) {
            e.x = std::nan("");
            return std::nan("");
        }
        return e.entry.end_pressure - e.exit.end_pressure;
    }

    void remember(double xn, const Trial<double>& t, const SideResult<double>& exit,
                  const SideResult<double>& entry) {
        ring_[next_++ % ring_.size()] = {xn, t, exit, entry};
    }

    const Evaluated* find(double xn) const {
        for (const Evaluated& e : ring_) {
            if (e.x == xn) return &e;
        }
        return nullptr;
    }

private:
    const BiteSolver<double>* solver_;
    std::array<Evaluated, 4> ring_{};
    std::size_t next_ = 0;
};

// Newton on the neutral point with the residual's exact slope dR/dx_n: the kernel in one dual
// direction (core/dual.h), whose values are the double pass's own. From `start`. Converged when a
// step s_k is below `tolerance` (the point is the last one evaluated, within about that step of
// the root, as the bracketed search's is within its tolerance) — or one step earlier, when the
// convergence seen says the step lands there: for a quadratically converging iteration the error
// after x_k + s_k is about C s_k^2 with C ~ |s_k| / s_{k-1}^2, so once |s_k|^3 / s_{k-1}^2 is below
// the tolerance the root is x_k + s_k, and the pass's values (the sides' pressures and integrals,
// the trial's speed and film) are carried to it by their x_n-derivatives, to O(s_k^2) (~1e-20 of
// themselves). An iteration that converges only linearly (a kink) never passes that test. Every
// point is remembered as a trial of the search. Gives up — not converged, and the bracketed search
// decides — when a step would leave the bite, the slope is not negative (no neutral point there:
// the residual falls from exit to entry where one exists) or 8 steps did not converge.
RootResult newton_root(const Bite<double>& b, RememberingResidual& memo, double start,
                       double tolerance) {
    using D = Dual<1>;
    const BiteSolver<D> solver(bite_kernel::lifted<D>(b));
    const auto at = [](const D& value, double step) { return value.v + value.d[0] * step; };
    RootResult out;
    double x = start, previous_step = 0.0;
    for (int k = 0; k < 8; ++k) {
        const Trial<D> t = solver.trial(D::variable(x, 0));
        if (!t.valid) return out;
        const SideResult<D> exit = solver.exit_side(t);
        const SideResult<D> entry = solver.entry_side(t);
        if (!exit.finite || !entry.finite) return out;
        memo.remember(x, bite_kernel::values_of(t), bite_kernel::values_of(exit),
                      bite_kernel::values_of(entry));
        out.iterations = k + 1;
        const D r = entry.end_pressure - exit.end_pressure;
        if (!(r.d[0] < 0.0)) return out;
        const double step = -r.v / r.d[0];
        if (r.v == 0.0 || std::abs(step) <= tolerance) {
            out.x = x;
            out.converged = true;
            return out;
        }
        const double next = x + step;
        if (!(next > 0.0 && next < b.contact_length)) return out;
        const double a = std::abs(step);
        if (k > 0 && a * a * a <= tolerance * previous_step * previous_step) {
            const auto side_at = [&](const SideResult<D>& side) {
                return SideResult<double>{true,
                                          at(side.end_pressure, step),
                                          at(side.integral_p, step),
                                          at(side.integral_tau, step),
                                          at(side.integral_abs_tau, step),
                                          side.pressure_negative};
            };
            memo.remember(next, {next, at(t.entry_speed, step), at(t.inlet_film, step), true},
                          side_at(exit), side_at(entry));
            out.x = next;
            out.converged = true;
            return out;
        }
        previous_step = step;
        x = next;
    }
    return out;
}

// A start for Newton when there is no guess: the neutral point of the same bite integrated with
// two RK4 steps a side, to 1e-6 of x_w. A cheap predictor only (a pass costs 1/16 of the default
// bite's, 1/8 of the dynamics'; finer predictors cost more than the Newton step they save): the
// answer is the full bite's root. -1 when the coarse bite has no root (the full search decides).
double coarse_neutral_point(const Bite<double>& b) {
    Bite<double> coarse = b;
    coarse.intervals = 2;
    const BiteSolver<double> solver(coarse);
    const auto residual = [&](double xn) { return solver.residual(xn); };
    const double at_exit = residual(0.0), at_entry = residual(b.contact_length);
    if (!(at_exit > 0.0 && at_entry < 0.0)) return -1.0;
    const RootResult root =
        brent_root(residual, 0.0, b.contact_length, at_exit, at_entry, 1e-6 * b.contact_length);
    return root.converged ? root.x : -1.0;
}

// The root search over the whole bite [0, x_w]. Returns `partial` with status ok and the root
// in `root`, or the skidding / failure result.
BiteResult bracket_and_solve(RememberingResidual& residual, const Bite<double>& b,
                             BiteResult partial, RootResult& root) {
    const double at_exit = residual(0.0);
    const double at_entry = residual(b.contact_length);
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
    root = brent_root(residual, 0.0, b.contact_length, at_exit, at_entry, 1e-14 * b.contact_length);
    if (!root.converged) return failure(partial, "the neutral-point search did not converge");
    partial.status = BiteStatus::ok;
    return partial;
}

}  // namespace

BiteResult solve_roll_bite(const Scenario& s, const BiteState& state, const BiteOptions& options) {
    BiteResult result;
    Bite<double> b = bite_kernel::bite_of(s, state);

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

    bite_kernel::set_contact(b);
    result.roll_radius = b.a;
    result.contact_length = b.contact_length;
    result.inlet_angle = b.inlet_angle;

    const BiteSolver<double> solver(b);
    RememberingResidual residual(solver);

    // Newton from the guess (time stepping, the previous bite) or from the coarse bite's root:
    // two or three passes where the bracketed search over [0, x_w] takes a dozen. Where Newton
    // gives up, the bracketed search decides (and says skidding when there is no root). The
    // root is the same to the tolerance, 1e-14 of x_w, either way.
    const double tolerance = 1e-14 * b.contact_length;
    const double guess = options.neutral_point_guess;
    const double start = guess > 0.0 && guess < b.contact_length ? guess : coarse_neutral_point(b);
    RootResult root;
    if (start > 0.0) root = newton_root(b, residual, start, tolerance);
    if (!root.converged) {
        const BiteResult outcome = bracket_and_solve(residual, b, result, root);
        if (outcome.status != BiteStatus::ok) return outcome;
    }

    // the root is a point the search evaluated: its sides again only to record the distributions
    const RememberingResidual::Evaluated* known =
        options.distributions ? nullptr : residual.find(root.x);
    const Trial<double> t = known ? known->trial : solver.trial(root.x);
    std::vector<BitePoint> exit_points, entry_points;
    if (options.distributions) {  // a point per step and segment end (up to 5 segments a side)
        exit_points.reserve(static_cast<std::size_t>(b.intervals) + 8);
        entry_points.reserve(static_cast<std::size_t>(b.intervals) + 8);
    }
    const SideResult<double> exit =
        known ? known->exit : solver.exit_side(t, options.distributions ? &exit_points : nullptr);
    const SideResult<double> entry =
        known ? known->entry
              : solver.entry_side(t, options.distributions ? &entry_points : nullptr);
    if (!exit.finite || !entry.finite)
        return failure(result, "the bite equations gave non-finite values");
    // Tensions near the flow stress with little friction: the pressure that starts at sigma - s
    // at the bite's ends can fall through zero inside it. A contact pressure cannot pull, so the
    // strip would leave the roll there; the model (docs/model.md §4) has no such state.
    if (exit.pressure_negative || entry.pressure_negative)
        return failure(result,
                       "the pressure falls below zero inside the bite (tensions near the flow "
                       "stress with little friction): the strip would leave the roll, a state "
                       "outside the model");

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
