// The critical-speed search that stops at its first crossing (CriticalSpeedOptions::
// stop_at_crossing, docs/model.md §7.3): whatever the thread count, and so whatever block of
// grid speeds it scans at a time, its outcome is the full scan's — the same status, the
// bit-identical critical speed and crossing eigenvalue — and the speeds it did scan are the full
// scan's first ones, value for value. It scans fewer speeds when the crossing is inside the range.

#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>
#include <string>

#include "core/stability.h"
#include "support/pool_control.h"

using namespace rollgap::core;

namespace {

void check_same_outcome(const Scenario& s, const CriticalSpeedOptions& options,
                        CriticalSpeedStatus expected) {
    const CriticalSpeedResult full = critical_speed(s, options);
    REQUIRE(full.status == expected);
    CriticalSpeedOptions to_crossing = options;
    to_crossing.stop_at_crossing = true;
    for (const std::size_t workers : {std::size_t{1}, std::size_t{2}}) {
        CAPTURE(workers);
        const rollgap::test::PoolControl pool(workers);
        const CriticalSpeedResult r = critical_speed(s, to_crossing, pool.control);
        CHECK(r.status == full.status);
        CHECK(r.critical_speed == full.critical_speed);  // bit-identical
        CHECK(r.unstable_mode.eigenvalue == full.unstable_mode.eigenvalue);
        CHECK(r.unstable_mode.frequency_Hz == full.unstable_mode.frequency_Hz);
        REQUIRE(r.scan.size() <= full.scan.size());
        for (std::size_t i = 0; i < r.scan.size(); ++i) {
            CHECK(r.scan[i].speed == full.scan[i].speed);
            CHECK(r.scan[i].max_real_part == full.scan[i].max_real_part);
            CHECK(r.scan[i].steady_status == full.scan[i].steady_status);
        }
        if (expected == CriticalSpeedStatus::found) {
            // It stopped within one block (at most max(2, threads) speeds) past the crossing.
            std::size_t crossing = 0;
            while (crossing < full.scan.size() && full.scan[crossing].speed < full.critical_speed)
                ++crossing;
            CHECK(r.scan.size() < full.scan.size());
            CHECK(r.scan.size() <= crossing + std::max<std::size_t>(2, workers));
            MESSAGE("scanned " << r.scan.size() << " of " << full.scan.size()
                               << " speeds to the crossing at " << full.critical_speed << " m/s");
        }
        if (expected == CriticalSpeedStatus::stable_in_range ||
            expected == CriticalSpeedStatus::no_steady_state) {
            CHECK(r.scan.size() == full.scan.size());  // no crossing: the whole range
        }
    }
}

}  // namespace

TEST_CASE("critical speed to the first crossing: the full scan's outcome, fewer speeds") {
    Scenario s;
    CriticalSpeedOptions options;
    SUBCASE("found") { check_same_outcome(s, options, CriticalSpeedStatus::found); }
    SUBCASE("stable in range: a range below the crossing") {
        options.speed_max = 5.0;
        check_same_outcome(s, options, CriticalSpeedStatus::stable_in_range);
    }
    SUBCASE("unstable at the lower bound: a range above the crossing") {
        const CriticalSpeedResult full = critical_speed(s, options);
        REQUIRE(full.status == CriticalSpeedStatus::found);
        options.speed_min = full.critical_speed + 1.0;
        options.speed_max = full.critical_speed + 6.0;
        check_same_outcome(s, options, CriticalSpeedStatus::unstable_at_lower_bound);
    }
    SUBCASE("found below the skid onset, with speeds without a steady state above it") {
        s.lubricant.limiting_shear = false;  // docs/model.md §4: it skids at speed
        check_same_outcome(s, options, critical_speed(s, options).status);
    }
    SUBCASE("no steady state anywhere: a skidding range") {
        s.lubricant.limiting_shear = false;  // docs/model.md §4: it skids at speed
        options.speed_min = 30.0;
        options.speed_max = 40.0;
        check_same_outcome(s, options, CriticalSpeedStatus::no_steady_state);
    }
}
