// The mill's three critical speeds (docs/model.md §12.7) on two stands (a 5-stand search costs
// tens of seconds; the benchmark reports it): the ordering the theory demands (every set of
// delays is stable below the delay-independent speed, and rho grows without bound as A0 nears
// instability), the one-span identity (the first nominal crossing of any root within one lobe
// period of the speed where rho = 1), each speed's own defining condition on either side of it
// (the nominal-delay speed's: the band count, roots inside the model's range, turns positive),
// the validity figures against the specification's, and the headline rule.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/mill/mill.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_delay.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_regenerative.h"
#include "core/scenario.h"
#include "core/stability.h"
#include "tools/verify_mill/mills.h"
#include "support/approx.h"

namespace mill_critical_speed_test {

using namespace rollgap::core;

using rollgap::tools::mills::two_stand_mill;

struct AtSpeed {
    double rho = 0.0;
    int count = -1;
    int band_count = -1;  // roots in 0 < Im s < 2 pi f_valid, Re s > 0
    double f_valid = 0.0;
    bool frozen_stable = false;
};

AtSpeed at_speed(Mill m, double speed) {
    m.speed = speed;
    AtSpeed out;
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);
    const TransportTransfer transfer = transport_transfer(model.linearise(model.equilibrium()));
    REQUIRE(transfer.ok);
    out.frozen_stable = transfer.frozen_max_real_part < 0.0;
    out.rho = regenerative_margin(transfer).margin;
    const DelayRootCount count = nominal_delay_root_count(transfer, 0.0);
    REQUIRE(count.ok);
    out.count = count.count;
    // the top of the model's range by bisection on the validity (its errors grow with f)
    double lo = 0.0, hi = 1.0;
    while (crossing_validity(m, steady, hi).valid()) {
        lo = hi;
        hi *= 2.0;
        REQUIRE(hi < 1e7);
    }
    for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (crossing_validity(m, steady, mid).valid() ? lo : hi) = mid;
    }
    out.f_valid = lo;
    if (lo > 0.0) {
        const BandRootCount band = band_root_count(transfer, 2.0 * std::numbers::pi * lo);
        REQUIRE(band.ok);
        out.band_count = band.count;
    } else {
        out.band_count = 0;
    }
    return out;
}

TEST_CASE("mill critical speeds: ordered, each on its own condition, one span within a lobe") {
    const Mill m = two_stand_mill(5.0);
    const MillCriticalSpeeds speeds = mill_critical_speeds(m);
    const MillCrossing &frozen = speeds.frozen, &di = speeds.delay_independent,
                       &nominal = speeds.nominal_delay, &any = speeds.first_any;
    for (const MillCrossing* c : {&frozen, &di, &nominal, &any}) {
        MESSAGE(std::string(to_string(c->kind))
                << ": " << std::string(to_string(c->status)) << " at " << c->speed << " m/s, "
                << c->frequency_Hz << " Hz, stand " << c->moving_stand + 1 << " moves, stand "
                << c->feeding_stand + 1 << " feeds, inside the model's range "
                << c->validity.valid());
        REQUIRE(c->status == CriticalSpeedStatus::found);
    }
    // below the delay-independent speed every set of delays is stable: no other speed lower
    CHECK(di.speed <= frozen.speed);
    CHECK(di.speed <= any.speed * (1.0 + 1e-4));
    // the first crossing of any root is no later than the first inside the model's band
    CHECK(any.speed <= nominal.speed * (1.0 + 1e-4));
    // one span: the first nominal crossing lies within one lobe period of the speed where rho = 1
    MESSAGE("lobe period " << any.lobe_period << " m/s; first crossing - delay-independent "
                           << any.speed - di.speed << " m/s");
    CHECK(any.speed - di.speed <= any.lobe_period);

    // each speed's own condition on both sides (the searches' tolerance is 1e-4 of the speed)
    const AtSpeed below_di = at_speed(m, di.speed * (1.0 - 1e-3));
    const AtSpeed above_di = at_speed(m, di.speed * (1.0 + 1e-3));
    CHECK(below_di.frozen_stable);
    CHECK(below_di.rho < 1.0);
    CHECK(above_di.rho >= 1.0);
    CHECK(below_di.count == 0);
    const AtSpeed below_any = at_speed(m, any.speed * (1.0 - 2e-4));
    const AtSpeed at_any = at_speed(m, any.speed);
    CHECK(below_any.count == 0);
    CHECK(at_any.count > 0);
    // the valid crossing: no root in the band just below it, one at it, inside the range
    const AtSpeed below_nominal = at_speed(m, nominal.speed * (1.0 - 2e-4));
    const AtSpeed at_nominal = at_speed(m, nominal.speed);
    MESSAGE("band below the valid crossing: " << below_nominal.band_count << " (valid to "
                                              << below_nominal.f_valid << " Hz); at it "
                                              << at_nominal.band_count);
    CHECK(below_nominal.band_count == 0);
    CHECK(at_nominal.band_count > 0);
    CHECK(nominal.validity.valid());
    CHECK(nominal.frequency_Hz <= at_nominal.f_valid);
    const AtSpeed below_frozen = at_speed(m, frozen.speed * (1.0 - 1e-3));
    const AtSpeed above_frozen = at_speed(m, frozen.speed * (1.0 + 1e-3));
    CHECK(below_frozen.frozen_stable);
    CHECK_FALSE(above_frozen.frozen_stable);

    // the feeding sensitivity, d Re(s)/d kappa_i of the frozen crossing root: scaling every
    // stand's J_b by (1 + kappa) at once moves the root by their sum (first order)
    {
        REQUIRE(frozen.feeding_sensitivity.size() == 2);
        Mill at = m;
        at.speed = frozen.speed;
        const MillSteadyState steady = mill_steady_state(at);
        REQUIRE(steady.status == MillSteadyStatus::ok);
        const std::complex<double> crossing{0.0, 2.0 * std::numbers::pi * frozen.frequency_Hz};
        const auto growth = [&](double gain) {
            MillModel model(at, steady);
            model.set_bite_gains({gain, gain});
            const TransportTransfer t = transport_transfer(model.linearise(model.equilibrium()));
            REQUIRE(t.ok);
            Eigen::Index best = 0;
            for (Eigen::Index k = 1; k < t.poles.size(); ++k)
                if (std::abs(t.poles(k) - crossing) < std::abs(t.poles(best) - crossing)) best = k;
            return t.poles(best).real();
        };
        const double kappa = 1e-3;
        const double together = (growth(1.0 + kappa) - growth(1.0 - kappa)) / (2.0 * kappa);
        const double sum = frozen.feeding_sensitivity[0] + frozen.feeding_sensitivity[1];
        MESSAGE("frozen crossing: d Re s / d kappa by stand "
                << frozen.feeding_sensitivity[0] << ", " << frozen.feeding_sensitivity[1]
                << " 1/s; both at once " << together);
        CHECK(std::abs(together - sum) <= 1e-3 * std::abs(together));
    }

    // participation: shares of one
    double total = 0.0;
    for (double share : nominal.participation) total += share;
    CHECK(total == rollgap::test::approx(1.0).epsilon(1e-12));

    // the headline: the lowest crossing inside the model's range, lower ones outside named
    REQUIRE(speeds.headline >= 0);
    const MillCrossing* crossings[] = {&frozen, &di, &nominal};
    const MillCrossing& headline = *crossings[speeds.headline];
    CHECK(headline.validity.valid());
    for (const MillCrossing* c : crossings) {
        if (c->speed < headline.speed) {
            CHECK_FALSE(c->validity.valid());
            CHECK(std::find(speeds.outside_range_below.begin(), speeds.outside_range_below.end(),
                            c->kind) != speeds.outside_range_below.end());
        }
    }
}

TEST_CASE("the band's screen: below it no root can cross the axis inside the band, for any delay") {
    // docs/model.md §12.7: a root on the axis at i omega needs rho(M E) = 1 there, bounded by the
    // structured gain at omega for every set of delays; the screen is the first speed where the
    // gain over the band reaches 0.9. Checked here on a grid ten times finer than the screen's
    // (and A0's resonances), with the optimised bound, and by the band count at speeds between
    // the delay-independent speed and the screen.
    const Mill m = two_stand_mill(5.0);
    CriticalSpeedOptions options;
    options.stop_at_crossing = true;
    const MillCriticalSpeeds speeds = mill_critical_speeds(m, options);
    REQUIRE(speeds.delay_independent.status == CriticalSpeedStatus::found);
    REQUIRE(speeds.nominal_delay.status == CriticalSpeedStatus::found);
    const double start = speeds.delay_independent.speed;
    const double screen = mill_band_screen_speed(m, start, options);
    MESSAGE("delay-independent " << start << " m/s, band's screen " << screen
                                 << " m/s, nominal-delay " << speeds.nominal_delay.speed << " m/s");
    CHECK(screen >= start);
    CHECK(screen <= speeds.nominal_delay.speed);
    REQUIRE(screen > start * 1.01);  // the screen skips something on this mill

    // the largest optimised structured bound over the band, on 2,000 frequencies
    const auto band_gain = [&](double speed) {
        Mill at = m;
        at.speed = speed;
        const MillSteadyState steady = mill_steady_state(at);
        REQUIRE(steady.status == MillSteadyStatus::ok);
        const MillModel model(at, steady);
        const TransportTransfer transfer = transport_transfer(model.linearise(model.equilibrium()));
        REQUIRE(transfer.ok);
        REQUIRE(transfer.frozen_max_real_part < 0.0);
        const double f_valid = at_speed(m, speed).f_valid;
        std::vector<double> frequencies;
        for (int k = 0; k <= 2000; ++k)
            frequencies.push_back(1e-2 * std::pow(f_valid / 1e-2, k / 2000.0));
        for (Eigen::Index k = 0; k < transfer.poles.size(); ++k) {  // the resonances' peaks
            const double f = transfer.poles(k).imag() / (2.0 * std::numbers::pi);
            if (f > 1e-2 && f < f_valid) frequencies.push_back(f);
        }
        double largest = 0.0;
        for (double f : frequencies)
            largest =
                std::max(largest, structured_bound(transfer.at({0.0, 2.0 * std::numbers::pi * f})));
        return largest;
    };
    for (double x : {0.0, 0.25, 0.5, 0.75, 0.995}) {
        const double speed = start + x * (screen - start);
        const double gain = band_gain(speed);
        const AtSpeed at = at_speed(m, speed);
        MESSAGE(speed << " m/s: band's gain " << gain << ", roots in the band " << at.band_count);
        CHECK(gain < 0.9);
        CHECK(at.band_count == 0);
    }
    CHECK(band_gain(screen * (1.0 + 1e-3)) >= 0.9);
}

TEST_CASE("chatter type by shape: a one-stand mill's crossing is typed as the single stand's") {
    // docs/model.md §12.7: a crossing's type is its moving stand's six masses classified as a
    // single stand's mode is; a mill of one stand (exit held) is the single stand, so its frozen
    // crossing must carry the single stand's classification, shape measures and all
    const Scenario s;
    const Mill m = rollgap::tools::mills::one_stand_mill(s);
    CriticalSpeedOptions options;
    options.stop_at_crossing = true;
    const MillCriticalSpeeds mill = mill_critical_speeds(m, options);
    const CriticalSpeedResult single = critical_speed(s, options);
    REQUIRE(mill.frozen.status == CriticalSpeedStatus::found);
    REQUIRE(single.status == CriticalSpeedStatus::found);
    const ChatterClassification &a = mill.frozen.chatter, &b = single.unstable_mode.chatter;
    MESSAGE("one-stand mill: " << std::string(to_string(a.type)) << " (gap opening "
                               << a.shape.gap_opening << ", work rolls " << a.shape.work_roll_motion
                               << ", back-up follows " << a.shape.backup_follow
                               << "); single stand: " << std::string(to_string(b.type)) << " ("
                               << b.shape.gap_opening << ", " << b.shape.work_roll_motion << ", "
                               << b.shape.backup_follow << ")");
    CHECK(a.type == b.type);
    CHECK(a.band == b.band);
    CHECK(a.shape.gap_opening == rollgap::test::approx(b.shape.gap_opening).epsilon(1e-6));
    CHECK(a.shape.work_roll_motion ==
          rollgap::test::approx(b.shape.work_roll_motion).epsilon(1e-6));
    CHECK(a.shape.backup_follow == rollgap::test::approx(b.shape.backup_follow).epsilon(1e-6));

    // two stands: the in-band crossing near 107 Hz is the stand's gap mode, third octave by its
    // shape as by its band (the regenerative path acts on the third-octave mode, TANDEM §6)
    const MillCriticalSpeeds two = mill_critical_speeds(two_stand_mill(5.0), options);
    REQUIRE(two.nominal_delay.status == CriticalSpeedStatus::found);
    MESSAGE("two stands, nominal-delay crossing at "
            << two.nominal_delay.frequency_Hz
            << " Hz: " << std::string(to_string(two.nominal_delay.chatter.type)));
    CHECK(two.nominal_delay.chatter.band == ChatterType::third_octave);
    CHECK(two.nominal_delay.chatter.type == ChatterType::third_octave);
}

TEST_CASE(
    "crossing validity: the spring law's error and the bite's transit against their formulas") {
    Mill m = two_stand_mill(5.0);
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    // TANDEM: 14 % at 105 Hz on 5 m (c = sqrt(E / rho) = 5172 m/s), published to the percent:
    // 1 - x / tan x at x = 0.6378 is 13.94 %
    const CrossingValidity at_105 = crossing_validity(m, steady, 105.0);
    REQUIRE(at_105.spring_law_error.size() == 1);
    MESSAGE("spring-law error at 105 Hz: " << at_105.spring_law_error[0]);
    CHECK(std::round(100.0 * at_105.spring_law_error[0]) == 14.0);
    CHECK(at_105.spring_law_valid);
    // x = omega L / c = pi / 4: 1 - (pi / 4) / tan(pi / 4)
    const double c = std::sqrt(m.youngs_modulus / m.strip_density);
    const double f = (std::numbers::pi / 4.0) * c / (2.0 * std::numbers::pi * 5.0);
    CHECK(crossing_validity(m, steady, f).spring_law_error[0] ==
          rollgap::test::approx(1.0 - std::numbers::pi / 4.0).epsilon(1e-12));
    // the span's first mode with both ends held, c / 2L = 517 Hz, is far outside
    CHECK_FALSE(crossing_validity(m, steady, c / 10.0).spring_law_valid);
    // transit: x_w / u1 times f, per stand
    const double ratio = steady.stands[0].bite.contact_length / steady.stands[0].entry_speed;
    CHECK(at_105.bite_transit_ratio[0] == rollgap::test::approx(ratio * 105.0).epsilon(1e-12));
    CHECK(crossing_validity(m, steady, 0.21 / ratio).quasi_static_bite_valid == false);
}

}  // namespace mill_critical_speed_test
