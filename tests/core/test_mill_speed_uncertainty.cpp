// A mill's speed limit under its stands' calibration posteriors (core/mill/mill_speed_limit.h,
// docs/model.md §13.7): the headline critical speed's sigma from the implicit gradient equals the
// sigma of the whole search differenced (core::propagate_linear over
// mill_critical_speeds), and so does each plant end's over the window found again; the chatter
// limit is (V_c − z sigma)(1 − m) and every plant end is taken at its one-sided bound. The whole
// analysis is differenced at ± a tenth of each standard error (the covariance / 100), the
// posterior small (standard errors of 0.1-0.3 %): the nominal-delay critical speed is the
// lowest of many lobes' crossings, and the whole search differenced over a wider step can
// hand the crossing to another root (tests/core/test_mill_limit_sensitivity.cpp), which the
// linear sigma, the crossing root's, does not see. The two-stand mill over 5-30 m/s.

#include <doctest/doctest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_limit_sensitivity.h"
#include "core/mill/mill_speed_limit.h"
#include "core/propagation.h"
#include "tools/verify_mill/mills.h"
#include "support/approx.h"

namespace mill_speed_uncertainty_test {

using namespace rollgap::core;
using rollgap::tools::mills::two_stand_mill;

CriticalSpeedOptions range(double relative_tolerance = 1e-10) {
    CriticalSpeedOptions options;
    options.speed_min = 5.0;
    options.speed_max = 30.0;
    options.relative_tolerance = relative_tolerance;
    return options;
}

// Stand 1's viscosity, stand 2's viscosity and asperity factor: standard errors of 0.09 %, 0.09 %
// and 0.3 %, stand 2's two correlated -0.5, the stands independent.
MillPosterior posterior() {
    MillPosterior p;
    p.numbers = {
        {[](Mill& m, double d) { m.stands[0].lubricant.viscosity += d; }, 0.0},
        {[](Mill& m, double d) { m.stands[1].lubricant.viscosity += d; }, 0.0},
        {[](Mill& m, double d) { m.stands[1].friction.asperity_factor += d; }, 0.0},
    };
    const Eigen::Vector3d sd(5e-7, 5e-7, 3e-3);
    Eigen::Matrix3d correlation = Eigen::Matrix3d::Identity();
    correlation(1, 2) = correlation(2, 1) = -0.5;
    p.covariance = sd.asDiagonal() * correlation * sd.asDiagonal();
    return p;
}

Mill moved(const Mill& m, const MillPosterior& p, const Eigen::VectorXd& x) {
    Mill out = m;
    for (std::size_t j = 0; j < p.numbers.size(); ++j)
        p.numbers[j].shift(out, x(static_cast<Eigen::Index>(j)));
    return out;
}

const MillCrossing& headline_of(const MillCriticalSpeeds& c) {
    const MillCrossing* crossings[] = {&c.frozen, &c.delay_independent, &c.nominal_delay};
    return *crossings[c.headline];
}

TEST_CASE("mill speed uncertainty: the headline's sigma is the whole search's, differenced") {
    const Mill m = two_stand_mill(5.0);
    const MillPosterior p = posterior();
    MillPlantLimits limits;
    limits.stands.resize(2);
    limits.chatter_margin = 0.05;
    limits.posterior = p;
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.critical.has_value());
    REQUIRE(r.critical->headline >= 0);
    REQUIRE(r.uncertainty.has_value());
    const MillSpeedUncertainty& u = *r.uncertainty;
    REQUIRE(u.ok);
    const MillCrossing& head = headline_of(*r.critical);
    CHECK(u.critical_speed == head.speed);
    // the whole search at the posterior's difference points: the headline crossing of the same kind
    const Figure whole = [&](const Eigen::VectorXd& x) -> std::optional<double> {
        const MillCriticalSpeeds c = mill_critical_speeds(moved(m, p, x), range());
        const MillCrossing* crossings[] = {&c.frozen, &c.delay_independent, &c.nominal_delay};
        const MillCrossing& same = *crossings[r.critical->headline];
        if (same.status != CriticalSpeedStatus::found) return std::nullopt;
        return same.speed;
    };
    // at ± a tenth of each standard error (the covariance / 100, sigma / 10): the headline is
    // curved enough in the asperity factor for the secant over ± one standard error to differ
    // from the slope by 0.3 % (1.3048 against 1.3009 m/s per unit)
    const Propagated differenced =
        propagate_linear(whole, Eigen::Vector3d::Zero(), 0.01 * p.covariance);
    REQUIRE(differenced.ok);
    MESSAGE("headline " << head.speed << " m/s: sigma " << u.standard_deviation << " m/s implicit, "
                        << 10.0 * differenced.standard_deviation << " differenced");
    CHECK(u.standard_deviation ==
          rollgap::test::approx(10.0 * differenced.standard_deviation).epsilon(1e-3));
    for (Eigen::Index j = 0; j < 3; ++j) {
        MESSAGE("dV_c/dx_" << j << ": " << u.gradient(j) << " implicit, " << differenced.gradient(j)
                           << " differenced");
        CHECK(u.gradient(j) == rollgap::test::approx(differenced.gradient(j)).epsilon(1e-3));
    }
    // the chatter limit at the one-sided bound, less the margin
    const double z = normal_quantile(0.95);
    CHECK(u.lower_bound ==
          rollgap::test::approx(head.speed - z * u.standard_deviation).epsilon(1e-12));
    const LimitAnswer& chatter = r.window.limits.back();
    REQUIRE(chatter.kind == SpeedLimitKind::chatter);
    CHECK(chatter.limit == rollgap::test::approx(0.95 * u.lower_bound).epsilon(1e-12));
    CHECK(r.window.window_max == rollgap::test::approx(0.95 * u.lower_bound).epsilon(1e-12));
    CHECK(r.window.binding_max == SpeedLimitKind::chatter);
}

TEST_CASE(
    "mill speed uncertainty: each plant end's sigma is the window's, found again, and the "
    "window takes the ends at their bounds") {
    const Mill m = two_stand_mill(5.0);
    const MillPosterior p = posterior();
    MillPlantLimits limits;
    limits.chatter = false;
    limits.stands.resize(2);
    limits.stands[1].max_power = mill_steady_figures(m, 21.7)[1].power;  // the top
    limits.stands[1].max_force = mill_steady_figures(m, 9.3)[1].force;   // the bottom
    const MillSpeedLimitResult plain = mill_speed_limit(m, limits, range());
    REQUIRE(plain.window.binding_max == SpeedLimitKind::power);
    REQUIRE(plain.window.binding_min == SpeedLimitKind::force);
    limits.posterior = p;
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    CHECK_FALSE(r.uncertainty.has_value());  // no chatter limit
    const LimitAnswer *power = nullptr, *force = nullptr;
    for (const LimitAnswer& a : r.window.limits) {
        if (a.kind == SpeedLimitKind::power && a.stand == 1) power = &a;
        if (a.kind == SpeedLimitKind::force && a.stand == 1) force = &a;
    }
    REQUIRE((power != nullptr && force != nullptr));
    REQUIRE((power->upper_speed_sd && force->lower_speed_sd));
    // the ends found again at the posterior's difference points (no posterior there)
    MillPlantLimits again = limits;
    again.posterior.reset();
    const auto end = [&](bool top) {
        return [&, top](const Eigen::VectorXd& x) -> std::optional<double> {
            const MillSpeedLimitResult w = mill_speed_limit(moved(m, p, x), again, range());
            return top ? w.window.window_max : w.window.window_min;
        };
    };
    const Propagated top =
        propagate_linear(end(true), Eigen::Vector3d::Zero(), 0.01 * p.covariance);
    const Propagated bottom =
        propagate_linear(end(false), Eigen::Vector3d::Zero(), 0.01 * p.covariance);
    REQUIRE((top.ok && bottom.ok));
    MESSAGE("power end " << *power->upper_speed << " m/s: sigma " << *power->upper_speed_sd
                         << " implicit, " << 10.0 * top.standard_deviation
                         << " found again; force end " << *force->lower_speed << ": "
                         << *force->lower_speed_sd << ", " << 10.0 * bottom.standard_deviation);
    CHECK(*power->upper_speed_sd ==
          rollgap::test::approx(10.0 * top.standard_deviation).epsilon(1e-3));
    CHECK(*force->lower_speed_sd ==
          rollgap::test::approx(10.0 * bottom.standard_deviation).epsilon(1e-3));
    const double z = normal_quantile(0.95);
    CHECK(r.window.window_max ==
          rollgap::test::approx(*power->upper_speed - z * *power->upper_speed_sd).epsilon(1e-12));
    CHECK(r.window.window_min ==
          rollgap::test::approx(*force->lower_speed + z * *force->lower_speed_sd).epsilon(1e-12));
    CHECK(r.window.advised_speed == r.window.window_max);
}

TEST_CASE(
    "mill speed uncertainty: the seeded draws' headline speeds are the whole search's second-order "
    "expansion, draw by draw") {
    // The posterior is small enough for the headline to stay one root (the linear regime): the
    // whole search at each draw x then follows V_c + g·x + ½ xᵀHx, so the draws' mean and spread
    // equal that expansion's at the same draws (the same seed draws the same x), whatever the
    // sampling noise of 24 draws. The spread is the linear sigma's; the mean is shifted from V_c by
    // the curvature, ½ tr(HΣ), which the linear sigma does not carry: H by second differences of
    // the whole search over one standard error.
    const Mill m = two_stand_mill(5.0);
    const MillPosterior p = posterior();
    MillPlantLimits limits;
    limits.stands.resize(2);
    limits.posterior = p;
    limits.samples = 24;
    limits.seed = 11;
    const MillSpeedLimitResult r = mill_speed_limit(m, limits, range());
    REQUIRE(r.uncertainty.has_value());
    const MillSpeedUncertainty& u = *r.uncertainty;
    REQUIRE(u.ok);
    REQUIRE(u.sampled.has_value());
    const Propagated& sampled = *u.sampled;
    REQUIRE(sampled.ok);
    CHECK(sampled.samples == 24);
    CHECK(sampled.failed_samples == 0);

    const MillCrossingKind kind = headline_of(*r.critical).kind;
    const auto whole = [&](const Eigen::Vector3d& x) {
        const MillCriticalSpeeds c = mill_critical_speeds(moved(m, p, x), range());
        REQUIRE(c.headline >= 0);
        CHECK(headline_of(c).kind == kind);
        return headline_of(c).speed;
    };
    const Eigen::Vector3d h = p.covariance.diagonal().cwiseSqrt();
    const auto at = [&](int j, double sj, int k = 0, double sk = 0.0) {
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        x(j) += sj * h(j);
        x(k) += sk * h(k);
        return whole(x);
    };
    Eigen::Matrix3d H;
    for (int j = 0; j < 3; ++j) {
        H(j, j) = (at(j, 1.0) + at(j, -1.0) - 2.0 * u.critical_speed) / (h(j) * h(j));
        for (int k = 0; k < j; ++k)
            H(j, k) = H(k, j) = (at(j, 1.0, k, 1.0) - at(j, 1.0, k, -1.0) - at(j, -1.0, k, 1.0) +
                                 at(j, -1.0, k, -1.0)) /
                                (4.0 * h(j) * h(k));
    }
    const Figure linear = [&](const Eigen::VectorXd& x) -> std::optional<double> {
        return u.critical_speed + u.gradient.dot(x);
    };
    const Figure quadratic = [&](const Eigen::VectorXd& x) -> std::optional<double> {
        return u.critical_speed + u.gradient.dot(x) + 0.5 * x.dot(H * x);
    };
    const Propagated first =
        propagate_sampled(linear, Eigen::Vector3d::Zero(), p.covariance, 24, 11);
    const Propagated second =
        propagate_sampled(quadratic, Eigen::Vector3d::Zero(), p.covariance, 24, 11);
    REQUIRE((first.ok && second.ok));
    MESSAGE("headline " << u.critical_speed << " m/s, linear sigma " << u.standard_deviation
                        << ", ½ tr(HΣ) " << 0.5 * (H * p.covariance).trace() << "; 24 draws: mean "
                        << sampled.value << ", sd " << sampled.standard_deviation
                        << "; at the same draws V_c + g·x: mean " << first.value << ", sd "
                        << first.standard_deviation << "; + ½ xᵀHx: mean " << second.value
                        << ", sd " << second.standard_deviation);
    // the spread is the linear one's to 1 % (the curvature's share of it is smaller still)
    CHECK(sampled.standard_deviation ==
          rollgap::test::approx(first.standard_deviation).epsilon(0.01));
    // the mean's shift from the linear prediction is the curvature's, to a tenth of it
    const double shift = sampled.value - first.value;
    MESSAGE("the draws' mean less the linear prediction's "
            << shift << " m/s, less the second-order " << sampled.value - second.value);
    CHECK(std::abs(sampled.value - second.value) < 0.1 * std::abs(shift));
    CHECK(std::abs(sampled.value - second.value) < 0.01 * u.standard_deviation);
}

}  // namespace mill_speed_uncertainty_test
