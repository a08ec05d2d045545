// The Levenberg–Marquardt core (core/calibration.h) on problems with known answers, independent
// of the mill model: NIST StRD Misra1a (certified values and standard errors), Rosenbrock as
// least squares (free and with an active bound), priors as residual rows, cancellation.

#include <doctest/doctest.h>

#include <array>
#include <atomic>
#include <cmath>

#include "core/calibration.h"
#include "support/pool_control.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace {

// NIST StRD nonlinear regression, Misra1a (lower difficulty): y = b1 (1 − exp(−b2 x)).
constexpr std::array<double, 14> misra_x{77.6,  114.9, 141.1, 190.8, 239.9, 289.0, 332.8,
                                         378.4, 434.8, 477.3, 536.8, 593.1, 689.1, 760.0};
constexpr std::array<double, 14> misra_y{10.07, 14.73, 17.94, 23.93, 29.61, 35.18, 40.02,
                                         44.82, 50.76, 55.05, 61.01, 66.40, 75.47, 81.78};

bool misra(const Eigen::VectorXd& b, Eigen::VectorXd& r, const Control&) {
    r.resize(14);
    for (std::size_t i = 0; i < 14; ++i) {
        r(static_cast<Eigen::Index>(i)) = b(0) * (1.0 - std::exp(-b(1) * misra_x[i])) - misra_y[i];
    }
    return true;
}

bool rosenbrock(const Eigen::VectorXd& x, Eigen::VectorXd& r, const Control&) {
    r.resize(2);
    r(0) = 10.0 * (x(1) - x(0) * x(0));
    r(1) = 1.0 - x(0);
    return true;
}

}  // namespace

TEST_CASE(
    "Misra1a from NIST's first start: the certified parameters, residual sum and standard errors") {
    const std::vector<CalibrationParameter> parameters{{500.0, 0.0, 1e4}, {1e-4, 0.0, 1.0}};
    const CalibrationResult fit = calibrate(parameters, 14, misra);
    REQUIRE(fit.status == CalibrationStatus::converged);
    CHECK(fit.values(0) == rollgap::test::approx(2.3894212918E+02).epsilon(1e-6));
    CHECK(fit.values(1) == rollgap::test::approx(5.5015643181E-04).epsilon(1e-6));
    CHECK(fit.chi_squared_observations == rollgap::test::approx(1.2455138894E-01).epsilon(1e-6));
    CHECK(fit.degrees_of_freedom == 12);
    // Unit weights: NIST's standard errors are ours times the residual standard deviation.
    const double s = std::sqrt(fit.chi_squared_observations / fit.degrees_of_freedom);
    CHECK(s * fit.standard_errors(0) == rollgap::test::approx(2.7070075241E+00).epsilon(1e-4));
    CHECK(s * fit.standard_errors(1) == rollgap::test::approx(7.2668688436E-06).epsilon(1e-4));
    CHECK(fit.correlation(0, 1) == rollgap::test::approx(fit.correlation(1, 0)));
    CHECK(fit.correlation(0, 0) == rollgap::test::approx(1.0));
    CHECK(fit.inseparable.empty());
}

TEST_CASE(
    "Rosenbrock as least squares: from (-1.2, 1) to (1, 1), with x1 <= 0.5 to (0.5, 0.25) on the bound") {
    const CalibrationResult free = calibrate({{-1.2, -5.0, 5.0}, {1.0, -5.0, 5.0}}, 2, rosenbrock);
    REQUIRE(free.status == CalibrationStatus::converged);
    CHECK(free.values(0) == rollgap::test::approx(1.0).epsilon(1e-8));
    CHECK(free.values(1) == rollgap::test::approx(1.0).epsilon(1e-8));
    CHECK(free.bounds[0] == BoundState::inside);

    // Constrained minimum: x2 = x1² makes r1 vanish, then (1 − x1)² is least at the bound.
    const CalibrationResult bounded =
        calibrate({{-1.2, -5.0, 0.5}, {1.0, -5.0, 5.0}}, 2, rosenbrock);
    REQUIRE(bounded.status == CalibrationStatus::converged);
    CHECK(bounded.values(0) == 0.5);
    CHECK(bounded.values(1) == rollgap::test::approx(0.25).epsilon(1e-8));
    CHECK(bounded.bounds[0] == BoundState::upper);
    CHECK(bounded.bounds[1] == BoundState::inside);
}

TEST_CASE(
    "a prior is a residual row: an unobserved parameter lands on its prior with the prior's uncertainty") {
    // y = a with one observation 3 ± 0.5; b does not enter the model at all.
    auto model = [](const Eigen::VectorXd& x, Eigen::VectorXd& r, const Control&) {
        r.resize(1);
        r(0) = (x(0) - 3.0) / 0.5;
        return true;
    };
    CalibrationParameter a{1.0, -10.0, 10.0};
    CalibrationParameter b{1.0, -10.0, 10.0, true, 2.0, 0.25};
    const CalibrationResult fit = calibrate({a, b}, 1, model);
    REQUIRE(fit.status == CalibrationStatus::converged);
    CHECK(fit.values(0) == rollgap::test::approx(3.0).epsilon(1e-9));
    CHECK(fit.values(1) == rollgap::test::approx(2.0).epsilon(1e-9));
    CHECK(fit.standard_errors(0) == rollgap::test::approx(0.5).epsilon(1e-6));
    CHECK(fit.standard_errors(1) == rollgap::test::approx(0.25).epsilon(1e-6));
    // b sits on its prior: the prior's chi-squared is zero up to the fit's rounding of b (about
    // 1e-12 of its value), i.e. ((b - 2) / 0.25)^2 below 1e-20
    CHECK(fit.chi_squared_priors < 1e-20);
    REQUIRE(fit.unobservable.size() == 1);
    CHECK(fit.unobservable[0] == 1);

    // Without the prior nothing determines b: its standard error is infinite, not noise.
    b.has_prior = false;
    const CalibrationResult bare = calibrate({a, b}, 1, model);
    CHECK(std::isinf(bare.standard_errors(1)));
    CHECK(bare.standard_errors(0) == rollgap::test::approx(0.5).epsilon(1e-6));
}

TEST_CASE("a prior and an observation of one parameter combine like two measurements") {
    // Observation 3 ± 0.5 and prior 2 ± 0.5: the weighted mean 2.5 with error 0.5/√2, and
    // χ² split 0.5 / 0.5 between the observations and the priors.
    auto model = [](const Eigen::VectorXd& x, Eigen::VectorXd& r, const Control&) {
        r.resize(1);
        r(0) = (x(0) - 3.0) / 0.5;
        return true;
    };
    const CalibrationResult fit = calibrate({{0.0, -10.0, 10.0, true, 2.0, 0.5}}, 1, model);
    REQUIRE(fit.status == CalibrationStatus::converged);
    CHECK(fit.values(0) == rollgap::test::approx(2.5).epsilon(1e-9));
    CHECK(fit.standard_errors(0) == rollgap::test::approx(0.5 / std::sqrt(2.0)).epsilon(1e-6));
    CHECK(fit.chi_squared_observations == rollgap::test::approx(1.0).epsilon(1e-8));
    CHECK(fit.chi_squared_priors == rollgap::test::approx(1.0).epsilon(1e-8));
    CHECK(fit.degrees_of_freedom == 0);
}

TEST_CASE("parameters that enter only as a product are reported inseparable") {
    // y_i = a b t_i: every observation sees a·b only.
    auto model = [](const Eigen::VectorXd& x, Eigen::VectorXd& r, const Control&) {
        r.resize(3);
        for (int i = 0; i < 3; ++i) r(i) = (x(0) * x(1) * (i + 1) - 6.0 * (i + 1)) / 0.1;
        return true;
    };
    const CalibrationResult fit = calibrate(
        {
            {1.0, 0.1, 100.0},
            {1.0, 0.1, 100.0},
        },
        3, model);
    REQUIRE(fit.inseparable.size() == 1);
    CHECK(fit.inseparable[0] == std::vector<int>{0, 1});
    CHECK(fit.reciprocal_condition < 1e-6);
    CHECK(fit.values(0) * fit.values(1) == rollgap::test::approx(6.0).epsilon(1e-8));
}

TEST_CASE("a model failure at the start is a status, a cancelled fit stops and says so") {
    auto failing = [](const Eigen::VectorXd&, Eigen::VectorXd&, const Control&) { return false; };
    CHECK(calibrate({{1.0, 0.0, 2.0}}, 1, failing).status == CalibrationStatus::model_failure);

    std::atomic<int> calls{0};
    Control control;
    control.cancelled = [&] { return calls.load() >= 3; };
    auto counting = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r, const Control& c) {
        ++calls;
        return !c.should_stop() && rosenbrock(x, r, c);
    };
    const CalibrationResult stopped =
        calibrate({{-1.2, -5.0, 5.0}, {1.0, -5.0, 5.0}}, 2, counting, {}, control);
    CHECK(stopped.status == CalibrationStatus::cancelled);
    CHECK(calls.load() <= 4);
}

TEST_CASE("the Jacobian columns in parallel give the same fit as one thread") {
    const rollgap::test::PoolControl two(2);
    const std::vector<CalibrationParameter> parameters{{500.0, 0.0, 1e4}, {1e-4, 0.0, 1.0}};
    const CalibrationResult a = calibrate(parameters, 14, misra, {});
    const CalibrationResult b = calibrate(parameters, 14, misra, {}, two.control);
    CHECK(a.values(0) == b.values(0));
    CHECK(a.values(1) == b.values(1));
    CHECK(a.iterations == b.iterations);
}
