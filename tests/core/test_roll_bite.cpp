// The roll-bite solver (docs/model.md §1, §4): conservation, boundary and continuity conditions,
// the slab equation itself, convergence, smoothness and the failure states.

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/inlet_film.h"
#include "core/roll_bite.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace {

struct Sides {
    std::vector<BitePoint> exit, entry;  // both ascending in x, sharing the neutral point
};

Sides split_at_neutral_point(const BiteResult& r) {
    Sides s;
    const std::size_t half = r.distribution.size() / 2;
    s.exit.assign(r.distribution.begin(), r.distribution.begin() + half);
    s.entry.assign(r.distribution.begin() + half, r.distribution.end());
    return s;
}

// Composite Simpson on uniformly spaced nodes (an even number of intervals).
template <class F>
double simpson(const std::vector<BitePoint>& pts, F value) {
    const std::size_t n = pts.size() - 1;
    REQUIRE(n % 2 == 0);
    const double h = (pts.back().x - pts.front().x) / n;
    double sum = value(pts.front()) + value(pts.back());
    for (std::size_t i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * value(pts[i]);
    return sum * h / 3.0;
}

double relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

}  // namespace

TEST_CASE("the default bite is solved and both ends carry the tension boundary pressures") {
    const Scenario s;
    const BiteState state = steady_bite_state(s);
    const BiteResult r = solve_roll_bite(s, state);
    REQUIRE(r.status == BiteStatus::ok);
    REQUIRE(r.distribution.size() == 2 * (s.numerics.bite_intervals + 1));

    const double y1 = s.strip.entry_thickness, y2 = exit_thickness(s);
    CHECK(r.contact_length ==
          rollgap::test::approx(std::sqrt(s.rolls.radius * (y1 - y2))).epsilon(1e-15));
    CHECK(r.inlet_angle ==
          rollgap::test::approx(std::sqrt((y1 - y2) / s.rolls.radius)).epsilon(1e-15));
    CHECK(r.neutral_point > 0.0);
    CHECK(r.neutral_point < r.contact_length);

    // eq. (7): p = sigma - s at both ends
    CHECK(r.distribution.front().x == 0.0);
    CHECK(r.distribution.front().pressure == s.strip.flow_stress - s.tensions.front.stress);
    CHECK(r.distribution.back().x == rollgap::test::approx(r.contact_length).epsilon(1e-15));
    CHECK(r.distribution.back().pressure == s.strip.flow_stress - s.tensions.back.stress);
}

TEST_CASE("mass is conserved along the bite, with and without a moving gap (Yun, eq. 12)") {
    const Scenario s;
    for (double gap_rate : {0.0, 2e-3, -2e-3}) {
        BiteState state = steady_bite_state(s);
        state.gap_rate = gap_rate;
        state.inlet_film = 3.4e-6;
        const BiteResult r = solve_roll_bite(s, state);
        REQUIRE(r.status == BiteStatus::ok);
        const double y1 = s.strip.entry_thickness;
        for (const BitePoint& p : r.distribution) {
            const double inflow = r.entry_speed * y1 - (r.contact_length - p.x) * gap_rate;
            CHECK(p.strip_speed * p.thickness == rollgap::test::approx(inflow).epsilon(1e-13));
            CHECK(p.thickness ==
                  rollgap::test::approx(state.exit_thickness + p.x * p.x / s.rolls.radius)
                      .epsilon(1e-14));
        }
        CHECK(r.exit_speed ==
              rollgap::test::approx(r.distribution.front().strip_speed).epsilon(1e-14));
        CHECK(r.forward_slip ==
              rollgap::test::approx((r.exit_speed - s.rolls.speed) / s.rolls.speed).epsilon(1e-12));
    }
}

TEST_CASE("at the neutral point the strip moves with the rolls and the pressure is continuous") {
    const Scenario s;
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    const Sides sides = split_at_neutral_point(r);
    const BitePoint& from_exit = sides.exit.back();
    const BitePoint& from_entry = sides.entry.front();
    CHECK(from_exit.x == rollgap::test::approx(r.neutral_point).epsilon(1e-15));
    CHECK(from_entry.x == rollgap::test::approx(r.neutral_point).epsilon(1e-15));
    CHECK(from_exit.strip_speed == rollgap::test::approx(s.rolls.speed).epsilon(1e-13));
    CHECK(relative(from_exit.pressure, from_entry.pressure) < 1e-9);
    // the friction reverses there: it pulls the strip in on the entry side (tau < 0) and holds
    // it back on the exit side (tau > 0)
    for (const BitePoint& p : sides.exit) CHECK(p.friction > 0.0);
    for (const BitePoint& p : sides.entry) CHECK(p.friction < 0.0);
    for (const BitePoint& p : sides.exit) CHECK(p.strip_speed >= s.rolls.speed * (1 - 1e-13));
    for (const BitePoint& p : sides.entry) CHECK(p.strip_speed <= s.rolls.speed * (1 + 1e-13));
}

TEST_CASE("the pressure satisfies the slab equation dp/dx = (sigma y' + 2 tau) / y (eq. 36)") {
    Scenario s;
    s.numerics.bite_intervals = 256;
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    const Sides sides = split_at_neutral_point(r);
    for (const auto* side : {&sides.exit, &sides.entry}) {
        const auto& pts = *side;
        for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
            const double dpdx =
                (pts[i + 1].pressure - pts[i - 1].pressure) / (pts[i + 1].x - pts[i - 1].x);
            const double rhs =
                (s.strip.flow_stress * 2.0 * pts[i].x / s.rolls.radius + 2.0 * pts[i].friction) /
                pts[i].thickness;
            // central differences are second order: |error| ~ h^2 |p'''| / 6, far below 1e-4 here
            CHECK(std::abs(dpdx - rhs) < 1e-4 * std::abs(s.strip.flow_stress / r.contact_length));
        }
    }
}

TEST_CASE("the friction is the mixed law of eqs. (16)-(18) with the limiting-shear cap") {
    const Scenario s;
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    const double tau_a = s.friction.asperity_factor * s.strip.flow_stress / 2.0;
    const double rq = std::hypot(s.roughness.roll_rq, s.roughness.strip_rq);
    for (const BitePoint& p : r.distribution) {
        // with the printed gamma the Newtonian stress exceeds lambda_L p wherever u != v
        const double magnitude =
            p.contact_ratio * tau_a +
            (1.0 - p.contact_ratio) * s.lubricant.limiting_shear_coefficient * p.pressure;
        CHECK(std::abs(p.friction) == rollgap::test::approx(magnitude).epsilon(1e-13));
        CHECK(p.film_ratio == rollgap::test::approx(p.film / rq).epsilon(1e-14));
        // eq. (15): h (v + u) = h0 (v + u1)
        CHECK(p.film * (s.rolls.speed + p.strip_speed) ==
              rollgap::test::approx(r.inlet_film * (s.rolls.speed + r.entry_speed)).epsilon(1e-13));
        const Regime expected = p.film_ratio < 0.5    ? Regime::boundary
                                : p.film_ratio <= 3.0 ? Regime::mixed
                                                      : Regime::full_film;
        CHECK(p.regime == expected);
    }
}

TEST_CASE("without the cap the bite fluid is Newtonian at eta0 (docs/model.md §4)") {
    Scenario s;
    s.lubricant.limiting_shear = false;
    s.rolls.speed = 10.0;
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    const double tau_a = s.strip.flow_stress / 2.0;
    for (const BitePoint& p : r.distribution) {
        const double fluid = s.lubricant.viscosity * (p.strip_speed - s.rolls.speed) / p.film;
        const double sign = p.friction > 0 ? 1.0 : -1.0;
        CHECK(p.friction ==
              rollgap::test::approx(sign * p.contact_ratio * tau_a + (1 - p.contact_ratio) * fluid)
                  .epsilon(1e-9));
    }
}

TEST_CASE("the steady inlet film is the stationary point of the unsteady film equation (11)") {
    const Scenario s;
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    InletFilmInputs in{};
    in.inlet_film = r.inlet_film;
    in.inlet_angle = r.inlet_angle;
    in.mean_inlet_speed = 0.5 * (r.entry_speed + s.rolls.speed);
    in.roll_radius = s.rolls.radius;
    in.viscosity = s.lubricant.viscosity;
    in.pressure_viscosity = s.lubricant.pressure_viscosity;
    in.flow_stress = s.strip.flow_stress;
    in.back_tension = s.tensions.back.stress;
    for (InletFilmModel model : {InletFilmModel::paper, InletFilmModel::eulerian}) {
        CHECK(std::abs(inlet_film_rate(model, in)) < 1e-12 * r.inlet_angle * in.mean_inlet_speed);
    }
    // docs/model.md §8: about 3.4 um at the defaults
    CHECK(r.inlet_film == rollgap::test::approx(3.4e-6).epsilon(0.02));
}

TEST_CASE("force, torque and mean friction are the integrals of the distributions") {
    Scenario s;
    s.numerics.bite_intervals = 64;
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    const Sides sides = split_at_neutral_point(r);
    auto p = [](const BitePoint& b) { return b.pressure; };
    auto tau = [](const BitePoint& b) { return b.friction; };
    auto abs_tau = [](const BitePoint& b) { return std::abs(b.friction); };
    const double integral_p = simpson(sides.exit, p) + simpson(sides.entry, p);
    const double integral_tau = simpson(sides.exit, tau) + simpson(sides.entry, tau);
    const double integral_abs_tau = simpson(sides.exit, abs_tau) + simpson(sides.entry, abs_tau);
    CHECK(r.force == rollgap::test::approx(s.strip.width * integral_p).epsilon(1e-8));
    CHECK(r.torque ==
          rollgap::test::approx(-s.strip.width * s.rolls.radius * integral_tau).epsilon(1e-6));
    CHECK(r.mean_friction_coefficient ==
          rollgap::test::approx(integral_abs_tau / integral_p).epsilon(1e-7));
    CHECK(r.torque > 0.0);  // the rolls drive the strip
    // docs/model.md §4: about 6.5 MN at 19 m/s
    CHECK(r.force == rollgap::test::approx(6.5e6).epsilon(0.02));
}

TEST_CASE("the force converges under refinement to 1e-6") {
    Scenario s;
    Scenario fine = s;
    fine.numerics.bite_intervals = 2048;
    SUBCASE("default mixed lubrication") {}
    SUBCASE("paper fit, its jump at H_t = 1.5 inside the bite") {
        // H_t runs from ~1.43 to ~1.55 across the bite with Rq = 2.2 um
        s.friction.contact = fine.friction.contact = ContactModel::paper_fit;
        s.roughness.strip_rq = fine.roughness.strip_rq =
            std::sqrt(2.2e-6 * 2.2e-6 - 1.2e-6 * 1.2e-6);
    }
    SUBCASE("boundary lubrication at 1 m/s") { s.rolls.speed = fine.rolls.speed = 1.0; }
    const BiteResult coarse_r = solve_roll_bite(s, steady_bite_state(s), {false});
    const BiteResult fine_r = solve_roll_bite(fine, steady_bite_state(fine), {false});
    REQUIRE(coarse_r.status == BiteStatus::ok);
    REQUIRE(fine_r.status == BiteStatus::ok);
    CHECK(relative(coarse_r.force, fine_r.force) < 1e-6);
}

TEST_CASE("the solution is a smooth, repeatable function of its inputs") {
    const Scenario s;
    const BiteState state = steady_bite_state(s);
    const BiteResult a = solve_roll_bite(s, state, {false});
    const BiteResult b = solve_roll_bite(s, state, {false});
    CHECK(a.force == b.force);  // bit for bit

    // a neutral-point guess changes the search path (Newton from it, or the bracketed search
    // where Newton gives up: a start next to an end of the bite), not the answer: the root to
    // its tolerance, 1e-14 of x_w, and the force with it
    for (double factor : {0.001, 0.5, 0.99, 1.01, 1.7, 2.8}) {
        CAPTURE(factor);
        BiteOptions o{false, a.neutral_point * factor};
        const BiteResult g = solve_roll_bite(s, state, o);
        REQUIRE(g.status == BiteStatus::ok);
        CHECK(std::abs(g.neutral_point - a.neutral_point) <= 2e-14 * a.contact_length);
        CHECK(relative(g.force, a.force) < 1e-12);
    }

    // the force is smooth in the exit thickness on the scale the dynamics differentiate it
    // (1e-7 m): second differences are O(delta^2 P''), first differences agree at two steps
    auto force_at = [&](double dy) {
        BiteState st = state;
        st.exit_thickness += dy;
        return solve_roll_bite(s, st, {false}).force;
    };
    const double d = 1e-7;
    const double slope1 = (force_at(d) - force_at(-d)) / (2 * d);
    const double slope2 = (force_at(2 * d) - force_at(-2 * d)) / (4 * d);
    CHECK(slope1 < 0.0);  // a thinner exit needs more force
    CHECK(relative(slope1, slope2) < 1e-5);
}

TEST_CASE(
    "limit: with the film far thicker than the roughness the law is Coulomb with mu = lambda_L") {
    Scenario mixed;
    mixed.rolls.speed = 60.0;  // H_t > 3 everywhere: A = 0
    Scenario coulomb = mixed;
    coulomb.friction.model = FrictionModel::coulomb;
    coulomb.friction.coulomb_coefficient = mixed.lubricant.limiting_shear_coefficient;
    const BiteResult m = solve_roll_bite(mixed, steady_bite_state(mixed));
    const BiteResult c = solve_roll_bite(coulomb, steady_bite_state(coulomb), {false});
    REQUIRE(m.status == BiteStatus::ok);
    REQUIRE(c.status == BiteStatus::ok);
    for (const BitePoint& p : m.distribution) CHECK(p.contact_ratio == 0.0);
    CHECK(relative(m.force, c.force) < 1e-12);
    CHECK(relative(m.neutral_point, c.neutral_point) < 1e-10);
}

// With A = 1 the friction is the constant shear m_a k and eq. (36) integrates in closed form:
//   p(x) = p(x0) + sigma ln(y(x) / y(x0)) + 2 tau sqrt(a / y2) [atan(x / sqrt(a y2))]_{x0}^{x}.
TEST_CASE(
    "limit: in boundary lubrication (A -> 1) the pressure is the closed-form constant-shear solution") {
    Scenario s;
    s.lubricant.viscosity = 1e-13;  // h0 ~ 1e-15 m: H_t ~ 1e-9, 1 - A ~ 1e-7
    s.friction.asperity_factor = 0.3;
    s.tensions.back.stress = 40e6;
    s.tensions.front.stress = 20e6;
    s.numerics.bite_intervals = 128;
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);

    const double a = s.rolls.radius, sigma = s.strip.flow_stress, y2 = exit_thickness(s);
    const double tau = s.friction.asperity_factor * sigma / 2.0, c = std::sqrt(a * y2);
    const double xw = r.contact_length;
    auto y = [&](double x) { return y2 + x * x / a; };
    auto exit_p = [&](double x) {
        return sigma - s.tensions.front.stress + sigma * std::log(y(x) / y2) +
               2 * tau * (c / y2) * std::atan(x / c);
    };
    auto entry_p = [&](double x) {
        return sigma - s.tensions.back.stress + sigma * std::log(y(x) / y(xw)) -
               2 * tau * (c / y2) * (std::atan(x / c) - std::atan(xw / c));
    };
    double lo = 0.0, hi = xw;  // bisection on the pressure jump
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (entry_p(mid) - exit_p(mid) > 0 ? lo : hi) = mid;
    }
    const double xn = 0.5 * (lo + hi);
    CHECK(r.neutral_point == rollgap::test::approx(xn).epsilon(1e-5));
    for (const BitePoint& p : r.distribution) {
        const double exact = p.x <= xn ? exit_p(p.x) : entry_p(p.x);
        if (std::abs(p.x - xn) > 1e-3 * xw)
            CHECK(p.pressure == rollgap::test::approx(exact).epsilon(1e-5));
    }
}

TEST_CASE("failure states are values: contact lost, skidding, solver failure") {
    const Scenario s;
    SUBCASE("no reduction: contact lost, no force") {
        BiteState state = steady_bite_state(s);
        state.exit_thickness = s.strip.entry_thickness * 1.001;
        const BiteResult r = solve_roll_bite(s, state);
        CHECK(r.status == BiteStatus::contact_lost);
        CHECK(r.force == 0.0);
        CHECK(r.distribution.empty());
    }
    SUBCASE(
        "too little friction to drive the strip: the rolls skid (docs/model.md §4, cap off, 30 m/s)") {
        Scenario fast = s;
        fast.lubricant.limiting_shear = false;
        fast.rolls.speed = 30.0;
        const BiteResult r = solve_roll_bite(fast, steady_bite_state(fast));
        CHECK(r.status == BiteStatus::skidding);
        CHECK(r.skid_at_exit);
        CHECK(r.skid_residual < 0.0);
        CHECK(r.force == 0.0);
    }
    SUBCASE("a front tension pulling harder than friction holds: the strip slides forward") {
        Scenario pulled = s;
        pulled.friction.model = FrictionModel::coulomb;
        pulled.friction.coulomb_coefficient = 0.005;
        BiteState state = steady_bite_state(pulled);
        state.back_tension = 0.0;
        state.front_tension = 300e6;
        const BiteResult r = solve_roll_bite(pulled, state);
        CHECK(r.status == BiteStatus::skidding);
        CHECK_FALSE(r.skid_at_exit);
        CHECK(r.skid_residual > 0.0);
    }
    SUBCASE("non-finite input") {
        BiteState state = steady_bite_state(s);
        state.gap_rate = std::nan("");
        CHECK(solve_roll_bite(s, state).status == BiteStatus::solver_failure);
        state = steady_bite_state(s);
        state.back_tension = INFINITY;
        CHECK(solve_roll_bite(s, state).status == BiteStatus::solver_failure);
    }
    SUBCASE("a gap closing faster than the strip can flow") {
        BiteState state = steady_bite_state(s);
        state.inlet_film = 3e-6;
        state.gap_rate = -1e4;
        const BiteResult r = solve_roll_bite(s, state);
        CHECK(r.status != BiteStatus::ok);
    }
}

TEST_CASE("a pressure that falls through zero inside the bite is no rolling state") {
    // Found by the fuzzer (fuzz/corpus/fuzz_roll_bite/negative-pressure-under-near-yield-tensions):
    // tensions near the flow stress start the pressure near zero at both ends, and a heavy pass
    // with rough strip lets it fall below zero inside the bite. A contact pressure cannot pull:
    // the strip would leave the roll, so the solver says it has no answer (docs/model.md §4)
    // instead of a negative force and mean friction.
    Scenario s;
    s.friction.contact = ContactModel::paper_fit;
    s.roughness.strip_rq = 50e-6;
    s.strip.flow_stress = 3000e6;
    s.strip.reduction = 0.7;
    BiteState state = steady_bite_state(s);
    state.exit_thickness = 0.575256e-3;
    state.gap_rate = -0.019;
    state.inlet_film = 9.62934e-05;
    state.back_tension = 0.999 * s.strip.flow_stress;
    state.front_tension = 0.7258 * s.strip.flow_stress;
    for (bool distributions : {false, true}) {
        const BiteResult r = solve_roll_bite(s, state, {distributions});
        CHECK(r.status == BiteStatus::solver_failure);
        CHECK(std::string(r.message).find("below zero") != std::string::npos);
    }
    // the same bite with the tensions at a third of the flow stress: an answer, every pressure
    // positive, and so a force and a mean friction that are
    state.back_tension = state.front_tension = s.strip.flow_stress / 3.0;
    const BiteResult r = solve_roll_bite(s, state, {true});
    REQUIRE(r.status == BiteStatus::ok);
    for (const BitePoint& p : r.distribution) CHECK(p.pressure > 0.0);
    CHECK(r.force > 0.0);
    CHECK(r.mean_friction_coefficient > 0.0);
}
