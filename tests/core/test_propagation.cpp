// Uncertainty propagation (core/propagation.h, docs/model.md §13.2): the normal quantile against
// its defining identity Φ(z(p)) = p (erfc, independent of the approximation) and published
// values; linear propagation exact on a linear figure; seeded sampling reproducible and agreeing
// with it within its own sampling error, on a linear figure and on the default stand's critical
// speed (near-linear over a few per cent of viscosity and asperity factor).

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <optional>

#include <Eigen/Dense>

#include "core/propagation.h"
#include "core/scenario.h"
#include "core/stability.h"
#include "support/critical_speed_figure.h"
#include "support/pool_control.h"
#include "support/approx.h"

namespace propagation_test {

using namespace rollgap::core;

TEST_CASE("normal quantile: Phi(z(p)) = p, published values, symmetry") {
    for (const double p : {1e-12, 1e-6, 0.001, 0.02, 0.02425, 0.3, 0.5, 0.8, 0.975, 0.999999}) {
        CAPTURE(p);
        const double z = normal_quantile(p);
        const double phi = 0.5 * std::erfc(-z / std::numbers::sqrt2);
        CHECK(std::abs(phi - p) <= 1e-14 * std::max(p, 1e-300) + 1e-16);
        // symmetry where 1 - p is exact enough (1 - 1e-12 rounds by ~1e-4 of p)
        if (p >= 1e-6) CHECK(normal_quantile(1.0 - p) == rollgap::test::approx(-z).epsilon(1e-9));
    }
    CHECK(normal_quantile(0.95) == rollgap::test::approx(1.6448536269514722).epsilon(1e-15));
    CHECK(normal_quantile(0.975) == rollgap::test::approx(1.959963984540054).epsilon(1e-15));
    CHECK(normal_quantile(0.5) == 0.0);
    CHECK(std::isnan(normal_quantile(0.0)));
    CHECK(std::isnan(normal_quantile(1.0)));
}

TEST_CASE("propagation: linear is exact on a linear figure, sampling agrees within its error") {
    const Eigen::Vector3d a(2.0, -1.0, 0.5);
    const Figure f = [&a](const Eigen::VectorXd& x) -> std::optional<double> {
        return 3.0 + a.dot(x);
    };
    const Eigen::Vector3d mean(1.0, 2.0, -1.0);
    Eigen::Matrix3d covariance;
    covariance << 0.04, 0.01, 0.0, 0.01, 0.09, -0.02, 0.0, -0.02, 0.16;
    const double exact = std::sqrt(a.dot(covariance * a));
    const Propagated linear = propagate_linear(f, mean, covariance);
    REQUIRE(linear.ok);
    CHECK(linear.value == rollgap::test::approx(3.0 + a.dot(mean)).epsilon(1e-15));
    CHECK(linear.standard_deviation == rollgap::test::approx(exact).epsilon(1e-12));
    CHECK((linear.gradient - Eigen::VectorXd(a)).norm() <= 1e-12);
    CHECK(lower_bound(linear, 0.95) ==
          rollgap::test::approx(linear.value - 1.6448536269514722 * exact).epsilon(1e-14));

    const int n = 20000;
    const rollgap::test::PoolControl pool(2);
    const Propagated sampled = propagate_sampled(f, mean, covariance, n, 42, pool.control);
    REQUIRE(sampled.ok);
    CHECK(sampled.samples == n);
    // four standard errors: of the mean sigma / sqrt(n), of the sd sigma / sqrt(2 (n - 1))
    CHECK(std::abs(sampled.value - linear.value) <= 4.0 * exact / std::sqrt(n));
    CHECK(std::abs(sampled.standard_deviation / exact - 1.0) <= 4.0 / std::sqrt(2.0 * (n - 1)));
    // the draws depend on the seed alone: the same on one thread, others with another seed
    const Propagated again = propagate_sampled(f, mean, covariance, n, 42);
    CHECK(again.value == sampled.value);
    CHECK(again.standard_deviation == sampled.standard_deviation);
    const Propagated other = propagate_sampled(f, mean, covariance, n, 43);
    CHECK(other.value != sampled.value);
}

TEST_CASE("propagation: the default stand's critical speed, linear against sampled") {
    // viscosity 5.5e-4 Pa s +- 2 %, asperity factor 1 +- 3 %, correlation -0.5
    const Scenario base;
    const Figure f = rollgap::test::critical_speed_of_viscosity_and_asperity(base);
    const Eigen::Vector2d mean(base.lubricant.viscosity, base.friction.asperity_factor);
    const Eigen::Vector2d sd(0.02 * mean(0), 0.03 * mean(1));
    Eigen::Matrix2d covariance;
    covariance << sd(0) * sd(0), -0.5 * sd(0) * sd(1), -0.5 * sd(0) * sd(1), sd(1) * sd(1);
    const rollgap::test::PoolControl pool(2);
    const Propagated linear = propagate_linear(f, mean, covariance, pool.control);
    REQUIRE(linear.ok);
    const int n = 400;
    const Propagated sampled = propagate_sampled(f, mean, covariance, n, 7, pool.control);
    REQUIRE(sampled.ok);
    MESSAGE("critical speed " << linear.value << " m/s; linear sd " << linear.standard_deviation
                              << " (gradient " << linear.gradient.transpose() << "), sampled "
                              << sampled.value << " +- " << sampled.standard_deviation << " over "
                              << sampled.samples << " draws; 95 % lower bound "
                              << lower_bound(linear, 0.95));
    CHECK(sampled.samples == n);
    CHECK(linear.standard_deviation > 0.0);
    // three standard errors of a sample's sd (~10.6 % at 400 draws) and of its mean
    CHECK(std::abs(sampled.standard_deviation / linear.standard_deviation - 1.0) <=
          3.0 / std::sqrt(2.0 * (n - 1)));
    CHECK(std::abs(sampled.value - linear.value) <=
          3.0 * linear.standard_deviation / std::sqrt(n) + 1e-4 * linear.value);
}

}  // namespace propagation_test
