// What to change (docs/model.md §13.4): the derivative of the advised speed with respect to a
// scenario number, from the implicit function theorem at the binding speed, against central
// differences of the whole speed-limit analysis (every limit re-searched, the critical speed
// refined to 1e-8) at the number ± a step.

#include <doctest/doctest.h>

#include <functional>
#include <string>
#include <vector>

#include "core/limit_sensitivity.h"
#include "core/speed_limit.h"
#include "support/pool_control.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace limit_sensitivity_test {

struct Case {
    std::string name;
    std::function<double&(Scenario&)> number;
    double difference_step;  // for the implicit derivative
    double analysis_step;    // for the whole analysis' central difference
};

std::vector<Case> cases() {
    return {
        {"viscosity", [](Scenario& s) -> double& { return s.lubricant.viscosity; }, 5e-6, 2e-5},
        {"back tension", [](Scenario& s) -> double& { return s.tensions.back.stress; }, 0.5e6, 2e6},
        {"reduction", [](Scenario& s) -> double& { return s.strip.reduction; }, 1e-3, 4e-3},
        {"roll radius", [](Scenario& s) -> double& { return s.rolls.radius; }, 1e-3, 4e-3},
    };
}

// The implicit derivatives and the whole analysis' differences for every case.
void compare(const Scenario& s, const PlantLimits& limits, SpeedLimitKind expected,
             const rollgap::test::PoolControl& pool, std::size_t count) {
    CriticalSpeedOptions search;
    search.relative_tolerance = 1e-8;
    const SpeedLimitResult base = speed_limit(s, limits, search, pool.control);
    REQUIRE(base.status == SpeedLimitStatus::ok);
    REQUIRE(base.binding_max == expected);
    std::vector<Case> all = cases();
    all.resize(count);
    std::vector<ScenarioNumber> numbers;
    for (const Case& c : all) numbers.push_back({c.number, c.difference_step});
    const BindingSensitivity sensitivity =
        binding_sensitivity(s, limits, base, numbers, pool.control);
    REQUIRE(sensitivity.ok);
    REQUIRE(sensitivity.kind == expected);
    for (std::size_t j = 0; j < all.size(); ++j) {
        const Case& c = all[j];
        CAPTURE(c.name);
        REQUIRE(sensitivity.derivatives[j].has_value());
        const auto advised = [&](double sign) {
            Scenario x = s;
            c.number(x) += sign * c.analysis_step;
            const SpeedLimitResult r = speed_limit(x, limits, search, pool.control);
            REQUIRE(r.status == SpeedLimitStatus::ok);
            REQUIRE(r.binding_max == expected);  // the same limit binds on both sides
            return r.advised_speed;
        };
        const double differences = (advised(1.0) - advised(-1.0)) / (2.0 * c.analysis_step);
        const double implicit = *sensitivity.derivatives[j];
        MESSAGE(c.name << ": implicit " << implicit << ", whole analysis " << differences
                       << " m/s per SI unit; per analysis step " << implicit * c.analysis_step
                       << " m/s");
        CHECK(implicit == rollgap::test::approx(differences).epsilon(0.01));
    }
}

}  // namespace limit_sensitivity_test

using namespace limit_sensitivity_test;

TEST_CASE("what to change: the chatter limit's derivatives equal the whole analysis' differences") {
    // The default stand with the chatter limit alone and a 10 % margin: it binds at 0.9 V_c.
    rollgap::test::PoolControl pool(2);
    PlantLimits limits;
    limits.chatter_margin = 0.1;
    compare(Scenario{}, limits, SpeedLimitKind::chatter, pool, 3);
}

TEST_CASE("what to change: a power limit's derivatives equal the whole analysis' differences") {
    // Without chatter, a drive of 4.8 MW binds the default stand (4.49 MW at 19 m/s) from above.
    rollgap::test::PoolControl pool(2);
    PlantLimits limits;
    limits.chatter = false;
    limits.max_power = 4.8e6;
    compare(Scenario{}, limits, SpeedLimitKind::power, pool, 4);
}

TEST_CASE(
    "what to change: nothing to gain where the range's end binds, no derivative for steady state") {
    PlantLimits limits;
    limits.chatter = false;
    const SpeedLimitResult open = speed_limit(Scenario{}, limits);
    REQUIRE(open.status == SpeedLimitStatus::ok);
    const std::vector<ScenarioNumber> numbers{
        {[](Scenario& s) -> double& { return s.strip.reduction; }, 1e-3}};
    const BindingSensitivity none = binding_sensitivity(Scenario{}, limits, open, numbers);
    CHECK_FALSE(none.kind.has_value());
    CHECK_FALSE(none.ok);
    CHECK_FALSE(none.derivatives[0].has_value());
}
