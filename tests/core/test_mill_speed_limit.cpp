// The speed limit of a tandem mill (core/mill/mill_speed_limit.h, docs/model.md §13.5):
// synthetic truths recovered — a stand's limit set to the figure that stand has at a chosen mill
// speed binds at that speed, named with its stand; a mill of one stand is the single stand; the
// chatter limit is the mill's headline critical speed less the margin, its stand the crossing's
// moving stand. Small mills (one and two stands, a speed range of 5-30 m/s): about 1 s here,
// under 15 s under the sanitizers.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_speed_limit.h"
#include "core/speed_limit.h"
#include "tools/verify_mill/mills.h"
#include "support/approx.h"

namespace mill_speed_limit_test {

using namespace rollgap::core;
using rollgap::tools::mills::one_stand_mill;
using rollgap::tools::mills::two_stand_mill;

CriticalSpeedOptions range() {
    CriticalSpeedOptions options;
    options.speed_min = 5.0;
    options.speed_max = 30.0;
    return options;
}

const LimitAnswer* answer_of(const SpeedLimitResult& r, SpeedLimitKind kind, int stand) {
    for (const LimitAnswer& a : r.limits)
        if (a.kind == kind && a.stand == stand) return &a;
    return nullptr;
}

TEST_CASE("mill speed limit: a stand's limit set to its figure at a mill speed binds there") {
    const Mill m = two_stand_mill(5.0);
    // stand 2's force at V = 12.3 m/s and stand 1's power at V = 21.7 m/s (between grid speeds)
    const double force_speed = 12.3, power_speed = 21.7;
    const std::vector<SteadyFigures> at_force = mill_steady_figures(m, force_speed);
    const std::vector<SteadyFigures> at_power = mill_steady_figures(m, power_speed);
    REQUIRE(at_force.size() == 2);
    REQUIRE((at_force[1].ok && at_power[0].ok));
    // the trends the ends rely on: the force falls and the power rises with the mill speed
    REQUIRE(mill_steady_figures(m, force_speed + 1.0)[1].force < at_force[1].force);
    REQUIRE(mill_steady_figures(m, power_speed + 1.0)[0].power > at_power[0].power);

    MillPlantLimits limits;
    limits.chatter = false;
    limits.stands.resize(2);
    limits.stands[1].max_force = at_force[1].force;
    limits.stands[0].max_power = at_power[0].power;
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.window.status == SpeedLimitStatus::ok);
    CHECK_FALSE(r.critical.has_value());
    CHECK(r.window.window_min == rollgap::test::approx(force_speed).epsilon(1e-8));
    CHECK(r.window.window_max == rollgap::test::approx(power_speed).epsilon(1e-8));
    REQUIRE((r.window.binding_min && r.window.binding_max));
    CHECK(*r.window.binding_min == SpeedLimitKind::force);
    CHECK(r.window.binding_min_stand == 1);
    CHECK(*r.window.binding_max == SpeedLimitKind::power);
    CHECK(r.window.binding_max_stand == 0);
    // the steady state and the two limits given, each with its stand; no other stand's
    REQUIRE(r.window.limits.size() == 3);
    CHECK(r.window.limits[0].kind == SpeedLimitKind::steady_state);
    CHECK(r.window.limits[0].stand == -1);
    CHECK(answer_of(r.window, SpeedLimitKind::force, 1) != nullptr);
    CHECK(answer_of(r.window, SpeedLimitKind::power, 0) != nullptr);
    CHECK(answer_of(r.window, SpeedLimitKind::force, 0) == nullptr);
    // the operating speed's figures are the mill's own at its speed
    const std::vector<SteadyFigures> operating = mill_steady_figures(m, m.speed);
    const LimitAnswer* force = answer_of(r.window, SpeedLimitKind::force, 1);
    CHECK(force->at_operating == rollgap::test::approx(operating[1].force).epsilon(1e-12));
    CHECK(force->utilisation == rollgap::test::approx(operating[1].force / at_force[1].force));
    CHECK(r.window.operating_permitted == (m.speed >= force_speed && m.speed <= power_speed));
}

TEST_CASE("mill speed limit: the steady state's end is named by the stand that loses it") {
    // Stand 2 pulled back by a 150 MPa span: as the mill speeds up its forward slip runs down
    // until its neutral point leaves the bite, and the schedule has no steady state above that.
    Mill m = two_stand_mill(5.0);
    m.interstand_tension = {150e6};
    MillPlantLimits limits;
    limits.chatter = false;
    limits.stands.resize(2);
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.window.status == SpeedLimitStatus::ok);
    const LimitAnswer& steady = r.window.limits.front();
    REQUIRE(steady.kind == SpeedLimitKind::steady_state);
    REQUIRE(steady.upper_speed.has_value());
    const double end = *steady.upper_speed;
    Mill past = m;
    past.speed = end + 1e-3;
    const MillSteadyState beyond = mill_steady_state(past);
    const std::vector<SteadyFigures> before = mill_steady_figures(m, end - 1e-3);
    const std::vector<SteadyFigures> slow = mill_steady_figures(m, 5.0);
    REQUIRE((before[1].ok && slow[1].ok));
    MESSAGE("steady state up to " << end << " m/s; beyond: " << std::string(beyond.message)
                                  << " (stand index " << beyond.stand
                                  << "); stand 2's forward slip " << slow[1].forward_slip
                                  << " at 5 m/s, " << before[1].forward_slip << " at the end");
    CHECK(beyond.status != MillSteadyStatus::ok);
    CHECK(beyond.stand == 1);
    CHECK(before[1].forward_slip < 0.1 * slow[1].forward_slip);
    // the row and the window's binding end name that stand
    CHECK(steady.stand == 1);
    CHECK(r.window.binding_max == SpeedLimitKind::steady_state);
    CHECK(r.window.binding_max_stand == 1);
    CHECK(r.window.window_max == end);
}

TEST_CASE("mill speed limit: a mill of one stand has the single stand's window") {
    const Scenario s;
    const Mill m = one_stand_mill(s);
    // the single stand's figures at 9.2 m/s (force) and 23.4 m/s (power) set the limits
    const SteadyFigures low = steady_figures(s, 9.2), high = steady_figures(s, 23.4);
    REQUIRE((low.ok && high.ok));
    PlantLimits stand;
    stand.chatter = false;
    stand.max_force = low.force;
    stand.max_power = high.power;
    stand.min_forward_slip = 0.0;
    MillPlantLimits limits;
    limits.chatter = false;
    limits.stands = {stand};
    const SpeedLimitResult single = speed_limit(s, stand, range());
    const MillSpeedLimitResult mill = mill_speed_limit(m, limits, range());
    REQUIRE(single.status == SpeedLimitStatus::ok);
    REQUIRE(mill.window.status == SpeedLimitStatus::ok);
    CHECK(mill.window.window_min == rollgap::test::approx(single.window_min).epsilon(1e-8));
    CHECK(mill.window.window_max == rollgap::test::approx(single.window_max).epsilon(1e-8));
    CHECK(mill.window.binding_min == single.binding_min);
    CHECK(mill.window.binding_max == single.binding_max);
    REQUIRE(mill.window.limits.size() == single.limits.size());
    for (std::size_t k = 0; k < single.limits.size(); ++k) {
        CAPTURE(k);
        CHECK(mill.window.limits[k].kind == single.limits[k].kind);
        CHECK(mill.window.limits[k].at_operating ==
              rollgap::test::approx(single.limits[k].at_operating).epsilon(1e-9));
    }
}

TEST_CASE("mill speed limit: chatter is the headline critical speed less the margin") {
    const Mill m = two_stand_mill(5.0);
    MillPlantLimits limits;
    limits.stands.resize(2);
    limits.chatter_margin = 0.1;
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.critical.has_value());
    const MillCriticalSpeeds& c = *r.critical;
    // the same search run on its own
    const MillCriticalSpeeds alone = mill_critical_speeds(m, range());
    REQUIRE(alone.headline == c.headline);
    const LimitAnswer* chatter =
        answer_of(r.window, SpeedLimitKind::chatter, r.window.limits.back().stand);
    REQUIRE(chatter != nullptr);
    CHECK(&*chatter == &r.window.limits.back());  // last, after the plant's limits
    if (c.headline >= 0) {
        const MillCrossing* crossings[] = {&c.frozen, &c.delay_independent, &c.nominal_delay};
        const MillCrossing& head = *crossings[c.headline];
        MESSAGE("two-stand mill: headline " << head.speed << " m/s, moving stand "
                                            << head.moving_stand + 1);
        CHECK(chatter->limit == rollgap::test::approx(0.9 * head.speed).epsilon(1e-12));
        CHECK(chatter->stand == head.moving_stand);
        CHECK(r.window.window_max == rollgap::test::approx(std::min(0.9 * head.speed, 30.0)));
        if (0.9 * head.speed < 30.0) {
            CHECK(r.window.binding_max == SpeedLimitKind::chatter);
            CHECK(r.window.binding_max_stand == head.moving_stand);
        }
        CHECK(chatter->utilisation == rollgap::test::approx(m.speed / (0.9 * head.speed)));
    } else {
        MESSAGE("two-stand mill: no crossing inside the model's range in 5-30 m/s");
        CHECK(chatter->limit == 30.0);
    }
}

}  // namespace mill_speed_limit_test
