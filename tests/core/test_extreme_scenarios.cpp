// Extreme but valid scenarios (corners of the API's bounds) through every analysis: each
// returns a status, never crashes, never hangs, and whatever it calls ok is finite.

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/amplitude.h"
#include "core/stability.h"
#include "core/tension_cycle.h"
#include "support/pool_control.h"

using namespace rollgap::core;

namespace {

struct Corner {
    std::string name;
    std::function<void(Scenario&)> apply;
};

std::vector<Corner> corners() {
    return {
        {"light, stiff stack (modes near 500 kHz)",
         [](Scenario& s) {
             s.structure.mass = {1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
             s.structure.k1 = s.structure.k2 = s.structure.k3 = s.structure.k5 = s.structure.k6 =
                 s.structure.k7 = 1e13;
         }},
        {"heavy, soft stack",
         [](Scenario& s) {
             s.structure.mass = {1e7, 1e7, 1e7, 1e7, 1e7, 1e7};
             s.structure.k1 = s.structure.k2 = s.structure.k3 = s.structure.k5 = s.structure.k6 =
                 s.structure.k7 = 1e6;
         }},
        {"no damping at all",
         [](Scenario& s) {
             s.structure.c1 = s.structure.c2 = 0.0;
             s.structure.rayleigh = false;
         }},
        {"crawling speed", [](Scenario& s) { s.rolls.speed = 0.01; }},
        {"100 m/s", [](Scenario& s) { s.rolls.speed = 100.0; }},
        {"foil, small rolls",
         [](Scenario& s) {
             s.strip.entry_thickness = 0.05e-3;
             s.strip.reduction = 0.5;
             s.rolls.radius = 0.01;
         }},
        {"thick plate, big reduction",
         [](Scenario& s) {
             s.strip.entry_thickness = 20e-3;
             s.strip.reduction = 0.7;
             s.rolls.radius = 2.0;
         }},
        {"isoviscous lubricant, thick oil",
         [](Scenario& s) {
             s.lubricant.pressure_viscosity = 0.0;
             s.lubricant.viscosity = 10.0;
         }},
        {"tensions near the flow stress",
         [](Scenario& s) {
             s.tensions.back.stress = 0.95 * s.strip.flow_stress;
             s.tensions.front.stress = 0.9 * s.strip.flow_stress;
         }},
        {"zero back tension, span mode", [](Scenario& s) { s.tensions.back.stress = 0.0; }},
        {"rough, boundary lubrication",
         [](Scenario& s) { s.roughness.roll_rq = s.roughness.strip_rq = 50e-6; }},
        {"paper fit, eulerian film, coulomb",
         [](Scenario& s) {
             s.friction.contact = ContactModel::paper_fit;
             s.inlet_film = InletFilmModel::eulerian;
             s.friction.model = FrictionModel::coulomb;
             s.friction.coulomb_coefficient = 0.0;
         }},
    };
}

}  // namespace

TEST_CASE("extreme scenarios end every analysis with a status and finite numbers") {
    const rollgap::test::PoolControl two_threads(2);
    for (const Corner& corner : corners()) {
        CAPTURE(corner.name);
        Scenario s;
        corner.apply(s);

        const BiteResult bite = solve_roll_bite(s, steady_bite_state(s));
        if (bite.status == BiteStatus::ok) {
            CHECK(std::isfinite(bite.force));
            CHECK(bite.force >= 0.0);
            for (const BitePoint& p : bite.distribution) CHECK(std::isfinite(p.pressure));
        }

        const SpeedStability linear = stability_at(s);
        if (linear.status == DynamicsStatus::ok) CHECK(std::isfinite(linear.max_real_part));

        CriticalSpeedOptions range;
        range.speed_min = std::max(0.01, s.rolls.speed * 0.5);
        range.speed_max = range.speed_min + 1.0;
        const CriticalSpeedResult critical = critical_speed(s, range, two_threads.control);
        if (critical.status == CriticalSpeedStatus::found)
            CHECK(std::isfinite(critical.critical_speed));

        AmplitudeOptions amplitude;
        amplitude.window = 0.02;
        const AmplitudeResult response = vibration_amplitude(s, amplitude);
        CHECK(std::isfinite(response.upper_roll));

        TensionCycleOptions cycle;
        cycle.cycles = 1;
        const TensionCycleResult distributions = tension_cycle(s, cycle);
        for (const PhaseDistribution& p : distributions.phases)
            CHECK(std::isfinite(p.back_tension));
    }
}
