// Sweeps (docs/model.md §7.5): the parallel results equal the serial ones bit for bit, and each
// point equals the analysis run on its own.

#include <doctest/doctest.h>

#include "core/sweep.h"
#include "support/pool_control.h"

using namespace rollgap::core;

TEST_CASE(
    "a critical-speed sweep gives identical results with 1 and 2 threads, and equals single runs") {
    std::vector<Scenario> scenarios;
    for (double viscosity : {4e-4, 8e-4, 1.2e-3}) {
        Scenario s;
        s.lubricant.viscosity = viscosity;
        scenarios.push_back(s);
    }
    CriticalSpeedOptions options;
    options.speed_min = 5.0;
    options.speed_max = 30.0;
    const auto serial = sweep_critical_speed(scenarios, options);
    const auto parallel =
        sweep_critical_speed(scenarios, options, rollgap::test::PoolControl(2).control);
    REQUIRE(serial.size() == scenarios.size());
    for (std::size_t i = 0; i < scenarios.size(); ++i) {
        CHECK(serial[i].status == parallel[i].status);
        CHECK(serial[i].critical_speed == parallel[i].critical_speed);
        CHECK(serial[i].critical_speed == critical_speed(scenarios[i], options).critical_speed);
    }
}

TEST_CASE("an amplitude sweep gives identical results with 1 and 2 threads") {
    std::vector<Scenario> scenarios;
    for (double speed : {8.0, 12.0}) {
        Scenario s;
        s.rolls.speed = speed;
        scenarios.push_back(s);
    }
    AmplitudeOptions options;
    options.window = 0.2;
    const auto serial = sweep_amplitude(scenarios, options);
    const auto parallel =
        sweep_amplitude(scenarios, options, rollgap::test::PoolControl(2).control);
    for (std::size_t i = 0; i < scenarios.size(); ++i) {
        CHECK(serial[i].upper_roll == parallel[i].upper_roll);
        CHECK(serial[i].upper_roll > 0.0);
    }
}

TEST_CASE("cancelling a sweep stops it") {
    std::vector<Scenario> scenarios(6);
    int started = 0;
    Control control;
    control.cancelled = [&] { return ++started > 2; };
    const auto results = sweep_critical_speed(scenarios, {}, control);
    CHECK(results.size() == scenarios.size());
    // the points the sweep never reached say so, rather than posing as results
    CHECK(results.back().status == CriticalSpeedStatus::cancelled);
}

TEST_CASE("cancelling an amplitude sweep marks the points it never reached") {
    std::vector<Scenario> scenarios(3);
    Control control;
    control.cancelled = [] { return true; };
    for (const AmplitudeResult& r : sweep_amplitude(scenarios, {}, control))
        CHECK(r.status == AmplitudeStatus::cancelled);
}
