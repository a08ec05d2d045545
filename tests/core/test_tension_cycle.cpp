// Distributions over a sinusoidal back-tension cycle (docs/model.md §7.2, Figs. 14-15). At 10 Hz
// the cycle is far below the stack's lowest mode (~64 Hz), so the gap follows the force almost
// quasi-statically: g = b^T K_s^-1 b (P - P_ref), within the dynamic amplification
// 1 / (1 - (10/64)^2) ~ 1.025.

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "core/stand_structure.h"
#include "core/tension_cycle.h"
#include "support/approx.h"

using namespace rollgap::core;

TEST_CASE(
    "the phases see the sinusoidal back tension and the gap follows the force quasi-statically") {
    const Scenario s;
    const TensionCycleResult r = tension_cycle(s);
    REQUIRE(r.status == DynamicsStatus::ok);
    REQUIRE(r.phases.size() == 3);
    const double mean = s.tensions.back.stress, amplitude = s.tensions.back.amplitude;
    const StructureMatrices mill = structure_matrices(s.structure);
    const Vector6 b = gap_direction();
    const double compliance = b.dot(mill.structural_stiffness.ldlt().solve(b));
    const double reference_force = solve_roll_bite(s, steady_bite_state(s), {false}).force;
    for (const PhaseDistribution& p : r.phases) {
        CAPTURE(p.phase);
        CHECK(p.back_tension ==
              rollgap::test::approx(mean + amplitude * std::sin(2 * std::numbers::pi * p.phase))
                  .epsilon(1e-9));
        REQUIRE(p.bite.status == BiteStatus::ok);
        CHECK(p.bite.distribution.back().pressure ==
              rollgap::test::approx(s.strip.flow_stress - p.back_tension).epsilon(1e-12));
        if (p.phase != 0.5) {
            const double quasi_static = compliance * (p.bite.force - reference_force);
            CHECK(p.gap == rollgap::test::approx(quasi_static).epsilon(0.06));
        }
    }
    // the highest back tension (T = 0.25) pulls the force down and the gap closes
    CHECK(r.phases[0].bite.force < r.phases[2].bite.force);
    CHECK(r.phases[0].gap < 0.0);
    CHECK(r.phases[2].gap > 0.0);
}

TEST_CASE("a cancellation is heard within a cycle, not only at the phase outputs") {
    Scenario s;
    s.tensions.back.frequency =
        0.5;  // a 2 s cycle: the first phase output lies 1.5 s of simulation away
    int polls = 0;
    Control control;
    control.cancelled = [&] { return ++polls > 3; };
    TensionCycleOptions options;
    options.cycles = 1;
    options.phases = {0.75};
    const TensionCycleResult r = tension_cycle(s, options, control);
    CHECK(r.status == DynamicsStatus::cancelled);
    CHECK(r.phases.empty());
}

TEST_CASE("the phase outputs do not depend on the intermediate stops") {
    const Scenario s;
    TensionCycleOptions one, three;
    one.phases = {0.5};
    three.phases = {0.25, 0.5, 0.75};
    const TensionCycleResult a = tension_cycle(s, one), b = tension_cycle(s, three);
    REQUIRE(a.status == DynamicsStatus::ok);
    REQUIRE(b.status == DynamicsStatus::ok);
    CHECK(a.phases[0].time == b.phases[1].time);
    CHECK(a.phases[0].gap == rollgap::test::approx(b.phases[1].gap).epsilon(1e-4));
}

TEST_CASE("a direct caller's nonsense cycle is a status, not a hang") {
    for (double frequency : {0.0, -10.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
        Scenario s;
        s.tensions.back.frequency = frequency;
        CAPTURE(frequency);
        const TensionCycleResult r = tension_cycle(s);
        CHECK(r.status == DynamicsStatus::solver_failure);
        CHECK(r.phases.empty());
    }
    TensionCycleOptions options;
    options.phases = {0.25, std::nan("")};
    CHECK(tension_cycle(Scenario{}, options).status == DynamicsStatus::solver_failure);
}
