// The speed limit of one stand (core/speed_limit.h, docs/model.md §13): synthetic truths
// recovered — a limit set to the figure the stand has at a chosen speed binds at that speed
// (to the bisection's 1e-9), on the side the figure's trend over the range says; the window is
// the intersection of every limit's permitted speeds; a limit not given is not checked; the
// chatter limit is the critical search's speed less the margin.

#include <doctest/doctest.h>

#include <cmath>
#include <optional>
#include <string>

#include "core/speed_limit.h"
#include "core/stability.h"
#include "support/pool_control.h"
#include "support/approx.h"

namespace speed_limit_test {

using namespace rollgap::core;

// The figure of `kind` in a steady state.
double figure(const SteadyFigures& f, SpeedLimitKind kind) {
    switch (kind) {
        case SpeedLimitKind::force: return f.force;
        case SpeedLimitKind::torque: return f.torque;
        case SpeedLimitKind::power: return f.power;
        case SpeedLimitKind::skid: return f.forward_slip;
        default: return 0.0;
    }
}

const LimitAnswer* answer_of(const SpeedLimitResult& r, SpeedLimitKind kind) {
    for (const LimitAnswer& a : r.limits)
        if (a.kind == kind) return &a;
    return nullptr;
}

TEST_CASE("speed limit: only the limits given are checked, the steady state always is") {
    const Scenario s;
    PlantLimits none;
    none.chatter = false;
    const SpeedLimitResult r = speed_limit(s, none);
    REQUIRE(r.status == SpeedLimitStatus::ok);
    REQUIRE(r.limits.size() == 1);
    CHECK(r.limits[0].kind == SpeedLimitKind::steady_state);
    CHECK(r.operating_permitted);
    // the default stand has a steady state over the whole range: nothing binds
    CHECK(r.window_min == CriticalSpeedOptions{}.speed_min);
    CHECK(r.window_max == CriticalSpeedOptions{}.speed_max);
    CHECK_FALSE(r.binding_min.has_value());
    CHECK_FALSE(r.binding_max.has_value());
    CHECK(r.chatter.scan.empty());
}

TEST_CASE("speed limit: a plant limit set to the stand's figure at a speed binds at that speed") {
    const Scenario s;
    const double target = 12.3;  // between grid speeds (0.5 m/s)
    const SteadyFigures at = steady_figures(s, target);
    REQUIRE(at.ok);
    const SteadyFigures slower = steady_figures(s, target - 1.0);
    const SteadyFigures faster = steady_figures(s, target + 1.0);
    REQUIRE(slower.ok);
    REQUIRE(faster.ok);
    const rollgap::test::PoolControl pool(2);
    for (const SpeedLimitKind kind : {SpeedLimitKind::force, SpeedLimitKind::torque,
                                      SpeedLimitKind::power, SpeedLimitKind::skid}) {
        CAPTURE(to_string(kind));
        PlantLimits limits;
        limits.chatter = false;
        const double value = figure(at, kind);
        switch (kind) {
            case SpeedLimitKind::force: limits.max_force = value; break;
            case SpeedLimitKind::torque: limits.max_torque = value; break;
            case SpeedLimitKind::power: limits.max_power = value; break;
            default: limits.min_forward_slip = value; break;
        }
        const SpeedLimitResult r = speed_limit(s, limits, {}, pool.control);
        REQUIRE(r.status == SpeedLimitStatus::ok);
        const LimitAnswer* a = answer_of(r, kind);
        REQUIRE(a != nullptr);
        // which side the limit permits follows the figure's trend near the target: a maximum
        // on a falling figure (or a minimum on a rising one) permits the faster speeds
        const bool rising = figure(faster, kind) > figure(slower, kind);
        const bool is_minimum = kind == SpeedLimitKind::skid;
        const bool lower_bound = rising == is_minimum;
        MESSAGE(std::string(to_string(kind))
                << ": " << figure(slower, kind) << " -> " << value << " -> " << figure(faster, kind)
                << std::string(lower_bound ? ", a lower bound" : ", an upper bound"));
        const std::optional<double> end = lower_bound ? a->lower_speed : a->upper_speed;
        REQUIRE(end.has_value());
        CHECK(std::abs(*end - target) <= 1e-8 * target);
        // at that end the figure equals the limit
        const SteadyFigures there = steady_figures(s, *end);
        CHECK(std::abs(figure(there, kind) - value) <= 1e-6 * std::abs(value));
        // and it is the window's end, named by the limit
        if (lower_bound) {
            CHECK(r.window_min == *end);
            CHECK(r.binding_min == kind);
        } else {
            CHECK(r.window_max == *end);
            CHECK(r.binding_max == kind);
            CHECK(r.advised_speed == *end);
        }
        // the margin at the operating speed (19 m/s) is the figure's against the limit
        const SteadyFigures operating = steady_figures(s, s.rolls.speed);
        const double expected =
            is_minimum ? value / figure(operating, kind) : figure(operating, kind) / value;
        CHECK(a->utilisation == rollgap::test::approx(expected).epsilon(1e-12));
        CHECK(a->met_at_operating == (expected <= 1.0));
        CHECK(r.operating_permitted == a->met_at_operating);
    }
}

TEST_CASE("speed limit: the chatter limit is the critical speed less the margin") {
    const Scenario s;
    const rollgap::test::PoolControl pool(2);
    CriticalSpeedOptions search;
    search.stop_at_crossing = true;
    const CriticalSpeedResult critical = critical_speed(s, search, pool.control);
    REQUIRE(critical.status == CriticalSpeedStatus::found);
    PlantLimits limits;
    limits.chatter_margin = 0.1;
    const SpeedLimitResult r = speed_limit(s, limits, {}, pool.control);
    REQUIRE(r.status == SpeedLimitStatus::ok);
    const double limit = 0.9 * critical.critical_speed;
    CHECK(r.chatter.critical_speed == critical.critical_speed);
    CHECK(r.window_max == limit);
    CHECK(r.binding_max == SpeedLimitKind::chatter);
    const LimitAnswer* a = answer_of(r, SpeedLimitKind::chatter);
    REQUIRE(a != nullptr);
    CHECK(a->limit == limit);
    CHECK(a->utilisation == rollgap::test::approx(s.rolls.speed / limit).epsilon(1e-15));
    // with the critical speed's uncertainty: the one-sided 95 % bound, less the margin
    limits.chatter_sigma = 0.36;
    const SpeedLimitResult sure = speed_limit(s, limits, {}, pool.control);
    const double bound = (critical.critical_speed - 1.6448536269514722 * 0.36) * 0.9;
    CHECK(sure.window_max == rollgap::test::approx(bound).epsilon(1e-14));
    CHECK(sure.binding_max == SpeedLimitKind::chatter);
    limits.confidence = 0.5;  // the median: the critical speed itself
    CHECK(speed_limit(s, limits, {}, pool.control).window_max == limit);
    MESSAGE("default stand: critical " << critical.critical_speed << " m/s, limit " << limit
                                       << ", running at " << 100.0 * a->utilisation << " %");
}

TEST_CASE("speed limit: the window is the intersection, and empty when the limits exclude all") {
    const Scenario s;
    const rollgap::test::PoolControl pool(2);
    // a force limit that binds below and a power limit that binds above: both ends named
    const SteadyFigures low = steady_figures(s, 8.0);
    const SteadyFigures high = steady_figures(s, 16.0);
    REQUIRE(low.ok);
    REQUIRE(high.ok);
    REQUIRE(high.force < low.force);  // the force falls with speed here
    REQUIRE(high.power > low.power);
    PlantLimits limits;
    limits.chatter = false;
    limits.max_force = low.force;
    limits.max_power = high.power;
    const SpeedLimitResult r = speed_limit(s, limits, {}, pool.control);
    REQUIRE(r.status == SpeedLimitStatus::ok);
    CHECK(r.window_min == rollgap::test::approx(8.0).epsilon(1e-8));
    CHECK(r.window_max == rollgap::test::approx(16.0).epsilon(1e-8));
    CHECK(r.binding_min == SpeedLimitKind::force);
    CHECK(r.binding_max == SpeedLimitKind::power);
    CHECK_FALSE(r.operating_permitted);  // 19 m/s is above the power limit
    // swapped: the force permits only above 16 m/s, the power only below 8 m/s
    limits.max_force = high.force;
    limits.max_power = low.power;
    const SpeedLimitResult none = speed_limit(s, limits, {}, pool.control);
    CHECK(none.status == SpeedLimitStatus::no_window);
    const LimitAnswer* force = answer_of(none, SpeedLimitKind::force);
    const LimitAnswer* power = answer_of(none, SpeedLimitKind::power);
    REQUIRE(force != nullptr);
    REQUIRE(power != nullptr);
    REQUIRE(force->lower_speed.has_value());
    REQUIRE(power->upper_speed.has_value());
    CHECK(*force->lower_speed == rollgap::test::approx(16.0).epsilon(1e-8));
    CHECK(*power->upper_speed == rollgap::test::approx(8.0).epsilon(1e-8));
}

}  // namespace speed_limit_test
