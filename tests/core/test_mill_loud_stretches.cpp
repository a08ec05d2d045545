// The line's count with its quiet parts taken from nearby speeds (docs/model.md §12.7,
// first_any): the loud stretches (structured gain >= 0.8) at a block's two end speeds, merged,
// stand for the line's loud parts at every speed between, so a count there samples only those
// stretches. Checked on the default five-stand mill over two blocks of first_any's scan (at the
// delay-independent speed and across the first crossing): at every speed the reduced count
// equals the whole line's count, and the whole line's own loud parts at the counting threshold
// 0.9 lie inside the merged stretches (the assumption, measured).
#include <doctest/doctest.h>

#include <algorithm>
#include <numbers>
#include <vector>

#include "core/mill/mill.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_delay.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_stability.h"

namespace mill_loud_test {

using namespace rollgap::core;

TransportTransfer transfer_at(double speed) {
    Mill mill = default_mill();
    mill.speed = speed;
    const MillSteadyState steady = mill_steady_state(mill);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(mill, steady);
    const MillLinearisation lin = model.linearise(model.equilibrium());
    REQUIRE(lin.status == DynamicsStatus::ok);
    TransportTransfer transfer = transport_transfer(lin);
    REQUIRE(transfer.ok);
    return transfer;
}

bool covered(const LoudStretches& outer, double a, double b) {
    return std::any_of(outer.omega.begin(), outer.omega.end(),
                       [&](const auto& s) { return s.first <= a && b <= s.second; });
}

TEST_CASE("first_any's reduced counts equal the whole line's over a block of 16 speeds") {
    Mill mill = default_mill();
    CriticalSpeedOptions options;
    const MillCriticalSpeeds speeds = mill_critical_speeds(mill, options);
    REQUIRE(speeds.delay_independent.status == CriticalSpeedStatus::found);
    REQUIRE(speeds.first_any.status == CriticalSpeedStatus::found);
    const double step = 0.5 * speeds.first_any.lobe_period;
    REQUIRE(step > 0.0);
    int positive = 0, zero = 0;
    // the scan's first block, and a block whose middle is the first crossing
    for (const double from :
         {speeds.delay_independent.speed, speeds.first_any.speed - 8.0 * step}) {
        const LoudStretches start = loud_stretches(transfer_at(from), 0.0, 0.8);
        const LoudStretches end = loud_stretches(transfer_at(from + 16.0 * step), 0.0, 0.8);
        REQUIRE(start.ok);
        REQUIRE(end.ok);
        const LoudStretches loud = loud_union(start, end);
        REQUIRE(loud.ok);
        double width = 0.0;
        for (const auto& [a, b] : loud.omega) width += b - a;
        MESSAGE("block from " << from << " m/s: " << loud.omega.size() << " loud stretches, "
                              << width / (2.0 * std::numbers::pi) << " Hz in all");
        for (int k = 0; k < 16; ++k) {
            const double speed = from + k * step;
            CAPTURE(speed);
            const TransportTransfer transfer = transfer_at(speed);
            const DelayRootCount whole = nominal_delay_root_count(transfer, 0.0);
            const DelayRootCount reduced = nominal_delay_root_count(transfer, 0.0, loud);
            REQUIRE(whole.ok);
            REQUIRE(reduced.ok);
            CHECK(reduced.count == whole.count);
            // the whole line's grid sampled against the stretches' points only
            CHECK(2 * reduced.sampled < whole.sampled);
            if (k == 0)
                MESSAGE("at " << speed << " m/s: " << whole.sampled << " points sampled on the "
                              << "line, " << reduced.sampled << " in the stretches; "
                              << whole.evaluations << " and " << reduced.evaluations
                              << " evaluations of F");
            (whole.count > 0 ? positive : zero) += 1;
            // the assumption: at this speed the line is loud (0.9) only inside the stretches
            const LoudStretches own = loud_stretches(transfer, 0.0, 0.9);
            for (const auto& stretch : own.omega) {
                // not a structured binding: clang 14 cannot capture one in CAPTURE's lambda
                const double a = stretch.first, b = stretch.second;
                CAPTURE(a);
                CAPTURE(b);
                CHECK(covered(loud, a, b));
            }
        }
    }
    // both kinds of count were compared: stable speeds and speeds past the first crossing
    CHECK(zero > 0);
    CHECK(positive > 0);
}

}  // namespace mill_loud_test
