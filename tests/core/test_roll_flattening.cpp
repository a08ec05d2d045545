// Roll flattening (docs/model.md, "Roll flattening"): Hitchcock's radius iterated with the roll
// force, checked against a secant solve of the same scalar fixed point written here, the
// fixed-point identity at the converged force, the rigid default, and the dynamics that keep
// the flattened radius frozen at the steady state.

#include <cmath>
#include <numbers>

#include <doctest/doctest.h>

#include "core/coupled_model.h"
#include "core/roll_bite.h"
#include "core/roll_flattening.h"
#include "core/stability.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace {

Scenario flattened(Scenario s = {}) {
    s.rolls.flattening = RollFlattening::hitchcock;
    return s;
}

Scenario rigid(Scenario s) {
    s.rolls.flattening = RollFlattening::none;
    return s;
}

double force_at_radius(const Scenario& s, double radius) {
    BiteState state = steady_bite_state(rigid(s));
    state.roll_radius = radius;
    const BiteResult bite = solve_roll_bite(s, state, {false});
    REQUIRE(bite.status == BiteStatus::ok);
    return bite.force;
}

// R' - R (1 + c F(R') / (w dh)) = 0 by the secant method from R and 2R: an independent
// solution of the scalar fixed point.
double secant_radius(const Scenario& s) {
    const double R = s.rolls.radius;
    const double dh = s.strip.entry_thickness - exit_thickness(s);
    const double c = 16.0 * (1.0 - 0.3 * 0.3) / (std::numbers::pi * 210e9);  // steel, written out
    auto g = [&](double r) {
        return r - R * (1.0 + c * force_at_radius(s, r) / (s.strip.width * dh));
    };
    double a = R, b = 2.0 * R, ga = g(a), gb = g(b);
    for (int i = 0; i < 60 && std::abs(b - a) > 1e-14 * b; ++i) {
        const double next = b - gb * (b - a) / (gb - ga);
        a = b;
        ga = gb;
        b = next;
        gb = g(b);
    }
    return b;
}

}  // namespace

TEST_CASE("Hitchcock's constant for steel rolls") {
    // 16 (1 - 0.09) / (pi 210e9) = 2.2069e-11 1/Pa
    CHECK(hitchcock_constant(210e9, 0.3) ==
          rollgap::test::approx(14.56 / (std::numbers::pi * 210e9)).epsilon(1e-14));
    CHECK(hitchcock_constant(210e9, 0.3) == rollgap::test::approx(2.2069e-11).epsilon(1e-4));
    CHECK(hitchcock_constant(420e9, 0.0) ==
          rollgap::test::approx(16.0 / (std::numbers::pi * 420e9)));
}

TEST_CASE(
    "the flattened radius equals an independent secant solve and satisfies the fixed-point identity") {
    for (double entry_mm : {1.6, 0.8}) {
        Scenario s = flattened();
        s.strip.entry_thickness = entry_mm * 1e-3;
        BiteState state = steady_bite_state(s);
        REQUIRE(state.roll_radius > s.rolls.radius);
        const double secant = secant_radius(s);
        CHECK(state.roll_radius == rollgap::test::approx(secant).epsilon(1e-9));

        // R' = R (1 + c F / (w dh)) at the force the bite gives on R'
        const BiteResult bite = solve_roll_bite(s, state, {false});
        REQUIRE(bite.status == BiteStatus::ok);
        CHECK(bite.roll_radius == state.roll_radius);
        const double dh = s.strip.entry_thickness - exit_thickness(s);
        const double c = hitchcock_constant(s.rolls.youngs_modulus, s.rolls.poisson_ratio);
        CHECK(state.roll_radius ==
              rollgap::test::approx(s.rolls.radius * (1.0 + c * bite.force / (s.strip.width * dh)))
                  .epsilon(1e-10));
        // the longer arc carries more force than the rigid roll's
        const Scenario plain = rigid(s);
        const BiteResult rigid_bite = solve_roll_bite(plain, steady_bite_state(plain), {false});
        CHECK(bite.force > rigid_bite.force);
        CHECK(bite.contact_length == rollgap::test::approx(std::sqrt(state.roll_radius * dh)));
    }
}

TEST_CASE(
    "flattening reports its own iteration: converged, with the force at the converged radius") {
    Scenario s = flattened();
    BiteState state = steady_bite_state(Scenario{});
    const FlatteningResult r = flattened_radius(s, state);
    REQUIRE(r.status == BiteStatus::ok);
    CHECK(r.converged);
    CHECK(r.iterations > 2);
    CHECK(r.radius == rollgap::test::approx(
                          hitchcock_radius(s, r.force, s.strip.entry_thickness - exit_thickness(s)))
                          .epsilon(1e-11));
    // stiffer rolls flatten less, and infinitely stiff ones not at all
    Scenario stiff = s;
    stiff.rolls.youngs_modulus = 1000e9;
    const FlatteningResult hard = flattened_radius(stiff, state);
    CHECK(hard.radius > s.rolls.radius);
    CHECK(hard.radius < r.radius);
}

TEST_CASE("the default stays rigid: the bite's radius is the scenario's, bit for bit") {
    const Scenario s;
    const BiteState state = steady_bite_state(s);
    CHECK(state.roll_radius == 0.0);
    const BiteResult bite = solve_roll_bite(s, state, {false});
    CHECK(bite.roll_radius == s.rolls.radius);
}

TEST_CASE("the flattened radius is frozen in the dynamics: the steady state stays an equilibrium") {
    const Scenario s = dynamics_scenario(flattened());
    const ReferenceState ref = reference_state(s, true);
    REQUIRE(ref.status == BiteStatus::ok);
    CHECK(ref.bite.roll_radius > s.rolls.radius);
    const CoupledModel model(s, ref);
    const Eigen::VectorXd z0 = model.equilibrium();
    CHECK(model.bite_state(0.0, z0.data()).roll_radius == ref.bite.roll_radius);
    // 1 nm more gap: the force changes by about k4 x 1 nm (20 N), the upper work roll's
    // acceleration by ~(k3 + k4) x 1 nm / m3 = 0.005 m/s^2; a bite re-solved on the rigid radius
    // would lose the ~1.1 MN between the flattened and the rigid force (~100 m/s^2)
    Eigen::VectorXd nudged = z0;
    nudged(2) += 1e-9;
    Eigen::VectorXd zdot(model.size());
    REQUIRE(model.rhs(0.0, nudged.data(), zdot.data()) == DynamicsStatus::ok);
    CHECK(std::abs(zdot(8)) < 1.0);

    // and a displaced gap still sees the frozen radius, not one re-flattened to the new force
    Eigen::VectorXd moved = z0;
    moved(2) += 1e-6;
    CHECK(model.bite_state(0.0, moved.data()).roll_radius == ref.bite.roll_radius);
}

TEST_CASE("with flattening the stand still has a critical speed") {
    const CriticalSpeedResult r = critical_speed(flattened());
    CHECK(r.status == CriticalSpeedStatus::found);
    CHECK(r.unstable_mode.chatter.type == ChatterType::third_octave);
}
