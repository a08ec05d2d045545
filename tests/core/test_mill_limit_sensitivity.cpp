// What to change to run a tandem mill faster (core/mill/mill_limit_sensitivity.h, docs/model.md
// §13.6): the implicit derivatives of the binding speed against central differences of the whole
// analysis — every crossing searched again (the critical speeds refined to 1e-10) or the window
// found again — with each number moved by ± a quarter of its difference step, the same limit
// binding on both sides. Not wider: the margins are curved in the lubricant (the power limit's
// end moves at 2,820 m/s per Pa.s with the viscosity 4e-5 Pa.s lower and at 1,340 with it 4e-5
// higher), and the nominal-delay critical speed is the lowest of many lobes' crossings, which a
// change of 2 % of a stand's viscosity can hand to another root (a jump, not a slope). On the
// two-stand mill: a stand's power limit at the window's top, and each of the three critical
// speeds (frozen, delay-independent, nominal-delay) found in the range.

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_limit_sensitivity.h"
#include "core/mill/mill_speed_limit.h"
#include "tools/verify_mill/mills.h"
#include "support/approx.h"

namespace mill_limit_sensitivity_test {

using namespace rollgap::core;
using rollgap::tools::mills::two_stand_mill;

struct Named {
    std::string name;
    MillNumber number;
};

// Numbers a plant sets, each with its difference step: a hundredth of its typical step, as the
// service differences them.
std::vector<Named> numbers() {
    return {
        {"span tension", {[](Mill& m, double d) { m.interstand_tension[0] += d; }, 0.05e6}},
        {"stand 2 viscosity",
         {[](Mill& m, double d) { m.stands[1].lubricant.viscosity += d; }, 1e-6}},
        {"stand 1 exit thickness", {[](Mill& m, double d) { m.thickness[1] += d; }, 2e-7}},
        {"stand 1 roll radius", {[](Mill& m, double d) { m.stands[0].rolls.radius += d; }, 1e-4}},
    };
}

std::vector<MillNumber> plain(const std::vector<Named>& named) {
    std::vector<MillNumber> out;
    for (const Named& n : named) out.push_back(n.number);
    return out;
}

CriticalSpeedOptions range(double relative_tolerance = 1e-4) {
    CriticalSpeedOptions options;
    options.speed_min = 5.0;
    options.speed_max = 30.0;
    options.relative_tolerance = relative_tolerance;
    return options;
}

const MillCrossing& crossing_of(const MillCriticalSpeeds& c, MillCrossingKind kind) {
    switch (kind) {
        case MillCrossingKind::frozen: return c.frozen;
        case MillCrossingKind::delay_independent: return c.delay_independent;
        default: return c.nominal_delay;
    }
}

TEST_CASE(
    "mill what to change: a stand's power limit at the window's top, against the window "
    "found again") {
    const Mill m = two_stand_mill(5.0);
    // stand 2's power at V = 21.7 m/s is its limit: the window's top, binding (chatter off)
    const double at = 21.7;
    MillPlantLimits limits;
    limits.chatter = false;
    limits.stands.resize(2);
    limits.stands[1].max_power = mill_steady_figures(m, at)[1].power;
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.window.status == SpeedLimitStatus::ok);
    REQUIRE(r.window.binding_max == SpeedLimitKind::power);
    REQUIRE(r.window.binding_max_stand == 1);
    const std::vector<Named> named = numbers();
    const MillBindingSensitivity s = mill_binding_sensitivity(m, limits, r, plain(named));
    REQUIRE(s.binding.ok);
    CHECK(s.binding.kind == SpeedLimitKind::power);
    CHECK(s.stand == 1);
    CHECK_FALSE(s.crossing.has_value());
    CHECK(s.binding.speed == rollgap::test::approx(at).epsilon(1e-8));
    CHECK(s.binding.margin_slope < 0.0);  // the power rises with the speed: its margin falls
    for (std::size_t j = 0; j < named.size(); ++j) {
        CAPTURE(named[j].name);
        REQUIRE(s.binding.derivatives[j].has_value());
        const double h = 0.25 * named[j].number.step;
        double top[2];
        for (const int side : {0, 1}) {
            Mill x = m;
            named[j].number.shift(x, side == 0 ? h : -h);
            const MillSpeedLimitResult moved = mill_speed_limit(x, limits, range());
            REQUIRE(moved.window.binding_max == SpeedLimitKind::power);
            top[side] = moved.window.window_max;
        }
        const double difference = (top[0] - top[1]) / (2.0 * h);
        MESSAGE(named[j].name << ": " << *s.binding.derivatives[j] << " implicit, " << difference
                              << " whole window");
        if (difference == 0.0)  // stand 1's rolls do not reach the last stand's power
            CHECK(*s.binding.derivatives[j] == 0.0);
        else CHECK(*s.binding.derivatives[j] == rollgap::test::approx(difference).epsilon(1e-3));
    }
}

TEST_CASE(
    "mill what to change: each critical speed's derivatives against the crossing searched "
    "again") {
    const Mill m = two_stand_mill(5.0);
    const MillCriticalSpeeds base = mill_critical_speeds(m, range(1e-10));
    const std::vector<Named> named = numbers();
    int checked = 0;
    for (const MillCrossingKind kind :
         {MillCrossingKind::frozen, MillCrossingKind::delay_independent,
          MillCrossingKind::nominal_delay}) {
        const MillCrossing& c = crossing_of(base, kind);
        const std::string name = to_string(kind);
        CAPTURE(name);
        if (c.status != CriticalSpeedStatus::found) {
            MESSAGE(name << ": not found in 5-30 m/s");
            continue;
        }
        const ImplicitDerivatives d = mill_crossing_derivatives(m, c, plain(named));
        REQUIRE(d.ok);
        CHECK(d.margin_slope < 0.0);  // stable below the crossing: the margin falls through 0
        for (std::size_t j = 0; j < named.size(); ++j) {
            CAPTURE(named[j].name);
            REQUIRE(d.derivatives[j].has_value());
            const double h = 0.25 * named[j].number.step;
            double speed[2];
            for (const int side : {0, 1}) {
                Mill x = m;
                named[j].number.shift(x, side == 0 ? h : -h);
                const MillCriticalSpeeds again = mill_critical_speeds(x, range(1e-10));
                const MillCrossing& moved = crossing_of(again, kind);
                REQUIRE(moved.status == CriticalSpeedStatus::found);
                speed[side] = moved.speed;
            }
            const double difference = (speed[0] - speed[1]) / (2.0 * h);
            MESSAGE(name << " at " << c.speed << " m/s, " << named[j].name << ": "
                         << *d.derivatives[j] << " implicit, " << difference << " searched again");
            CHECK(*d.derivatives[j] == rollgap::test::approx(difference).epsilon(1e-3));
        }
        ++checked;
    }
    CHECK(checked >= 2);
}

TEST_CASE(
    "mill what to change: the chatter limit's derivatives are the headline crossing's "
    "times (1 - margin)") {
    const Mill m = two_stand_mill(5.0);
    MillPlantLimits limits;
    limits.stands.resize(2);
    limits.chatter_margin = 0.1;
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.critical.has_value());
    REQUIRE(r.critical->headline >= 0);
    REQUIRE(r.window.binding_max == SpeedLimitKind::chatter);
    const std::vector<Named> named = numbers();
    const MillBindingSensitivity s = mill_binding_sensitivity(m, limits, r, plain(named));
    REQUIRE(s.binding.ok);
    const MillCrossing* crossings[] = {&r.critical->frozen, &r.critical->delay_independent,
                                       &r.critical->nominal_delay};
    const MillCrossing& head = *crossings[r.critical->headline];
    CHECK(s.crossing == head.kind);
    CHECK(s.stand == head.moving_stand);
    CHECK(s.binding.speed == head.speed);
    const ImplicitDerivatives d = mill_crossing_derivatives(m, head, plain(named));
    for (std::size_t j = 0; j < named.size(); ++j) {
        REQUIRE((s.binding.derivatives[j] && d.derivatives[j]));
        CHECK(*s.binding.derivatives[j] ==
              rollgap::test::approx(0.9 * *d.derivatives[j]).epsilon(1e-12));
    }
}

TEST_CASE("mill what to change: nothing to gain where the range's top binds") {
    const Mill m = two_stand_mill(5.0);
    MillPlantLimits limits;
    limits.chatter = false;
    limits.stands.resize(2);
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.window.status == SpeedLimitStatus::ok);
    const MillBindingSensitivity s = mill_binding_sensitivity(m, limits, r, plain(numbers()));
    CHECK_FALSE(s.binding.kind.has_value());
    CHECK_FALSE(s.binding.ok);
    for (const auto& d : s.binding.derivatives) CHECK_FALSE(d.has_value());
}

}  // namespace mill_limit_sensitivity_test
