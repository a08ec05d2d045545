// Coil-by-coil adaptation (docs/model.md §11.6): three calibrations in sequence, each with the
// previous posterior as a joint Gaussian prior (full covariance, JointPrior), end where one
// joint fit of all the observations ends, to within the linearisation. A synthetic stand
// (viscosity 6.0e-4 Pa s, asperity factor 1.2) is observed through its roll force and forward
// slip, one coil at 10, one at 15 and one at 20 m/s, with seeded noise of 0.5 % and 2 %. Cheap
// observables: one bite solve each.

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "core/calibration_observables.h"
#include "core/speed_limit.h"
#include "core/scenario.h"
#include "support/pool_control.h"
#include "support/approx.h"

namespace sequential_calibration_test {

using namespace rollgap::core;

struct Measurement {
    double speed;
    double force, slip;  // observed
    double force_u, slip_u;
};
// A coil: force and slip measured at two speeds of its run (threading and full speed), so that
// each coil alone separates the viscosity from the asperity factor.
using Coil = std::vector<Measurement>;

std::vector<Coil> coils() {
    Scenario truth;
    truth.lubricant.viscosity = 6.0e-4;
    truth.friction.asperity_factor = 1.2;
    std::mt19937_64 generator(20);
    std::normal_distribution<double> normal;
    std::vector<Coil> out;
    for (const auto& [low, high] :
         {std::pair{6.0, 14.0}, std::pair{8.0, 17.0}, std::pair{10.0, 20.0}}) {
        Coil coil;
        for (const double v : {low, high}) {
            const SteadyFigures bite = steady_figures(truth, v);
            REQUIRE(bite.ok);
            const double force_u = 0.005 * bite.force, slip_u = 0.02 * bite.forward_slip;
            coil.push_back({v, bite.force + force_u * normal(generator),
                            bite.forward_slip + slip_u * normal(generator), force_u, slip_u});
        }
        out.push_back(coil);
    }
    return out;
}

// A fit of the viscosity and the asperity factor to these coils, from `start`, with `prior`.
ScenarioCalibrationResult fit(const std::vector<Coil>& coils, const Eigen::Vector2d& start,
                              const std::optional<JointPrior>& prior,
                              const rollgap::test::PoolControl& pool) {
    ScenarioCalibration setup;
    std::vector<Measurement> observed;
    for (const Coil& coil : coils) observed.insert(observed.end(), coil.begin(), coil.end());
    for (std::size_t c = 0; c < observed.size(); ++c) {
        Scenario s;
        s.rolls.speed = observed[c].speed;
        s.lubricant.viscosity = start(0);
        s.friction.asperity_factor = start(1);
        setup.conditions.push_back(s);
        setup.observations.push_back({static_cast<int>(c),
                                      Observable::roll_force,
                                      observed[c].force,
                                      observed[c].force_u,
                                      {}});
        setup.observations.push_back({static_cast<int>(c),
                                      Observable::forward_slip,
                                      observed[c].slip,
                                      observed[c].slip_u,
                                      {}});
    }
    setup.access = {[](Scenario& s) -> double& { return s.lubricant.viscosity; },
                    [](Scenario& s) -> double& { return s.friction.asperity_factor; }};
    setup.parameters = {{start(0), 1e-4, 2e-3}, {start(1), 0.2, 3.0}};
    setup.joint_prior = prior;
    setup.options.step_tolerance = 1e-12;
    setup.options.cost_tolerance = 1e-15;
    return calibrate_scenario(setup, pool.control);
}

Eigen::Matrix2d covariance(const CalibrationResult& r) {
    return r.standard_errors.asDiagonal() * r.correlation * r.standard_errors.asDiagonal();
}

}  // namespace sequential_calibration_test

using namespace sequential_calibration_test;

TEST_CASE(
    "adaptation: three sequential fits with the previous posterior as prior = one joint fit") {
    const rollgap::test::PoolControl pool(2);
    const std::vector<Coil> all = coils();
    const Eigen::Vector2d defaults{5.5e-4, 1.0};

    // Coil after coil: the first without a prior, each next one from the last posterior.
    Eigen::Vector2d mean = defaults;
    std::optional<JointPrior> prior;
    std::vector<CalibrationResult> steps;
    for (const Coil& coil : all) {
        const ScenarioCalibrationResult r = fit({coil}, mean, prior, pool);
        REQUIRE(r.fit.status == CalibrationStatus::converged);
        steps.push_back(r.fit);
        mean = r.fit.values;
        prior = JointPrior{{0, 1}, mean, covariance(r.fit)};
        MESSAGE("after the coil at " << coil.back().speed << " m/s: viscosity " << mean(0) << " ± "
                                     << r.fit.standard_errors(0) << " Pa s, asperity factor "
                                     << mean(1) << " ± " << r.fit.standard_errors(1)
                                     << ", correlation " << r.fit.correlation(0, 1));
    }
    const CalibrationResult& sequential = steps.back();

    const ScenarioCalibrationResult joint = fit(all, defaults, std::nullopt, pool);
    REQUIRE(joint.fit.status == CalibrationStatus::converged);
    const CalibrationResult& j = joint.fit;
    MESSAGE("joint: viscosity " << j.values(0) << " ± " << j.standard_errors(0)
                                << " Pa s, asperity factor " << j.values(1) << " ± "
                                << j.standard_errors(1) << ", correlation " << j.correlation(0, 1));

    // The same values, standard errors and correlation to within the linearisation: each
    // step's Gaussian prior is the previous fit's linearised likelihood, so the two differ only
    // by the model's curvature over the posterior's width.
    for (int k = 0; k < 2; ++k) {
        CAPTURE(k);
        CHECK(std::abs(sequential.values(k) - j.values(k)) < 0.02 * j.standard_errors(k));
        CHECK(sequential.standard_errors(k) ==
              rollgap::test::approx(j.standard_errors(k)).epsilon(0.01));
    }
    CHECK(std::abs(sequential.correlation(0, 1) - j.correlation(0, 1)) < 0.005);

    // The prior keeps the last coil from being overfitted: its fit alone lands farther from
    // the joint answer than the sequential one, by its own larger standard errors.
    const ScenarioCalibrationResult alone = fit({all.back()}, defaults, std::nullopt, pool);
    REQUIRE(alone.fit.status == CalibrationStatus::converged);
    for (int k = 0; k < 2; ++k) {
        CHECK(alone.fit.standard_errors(k) > 1.3 * sequential.standard_errors(k));
    }
}

TEST_CASE(
    "adaptation: a joint prior's rows are whitened, so its chi-squared is the Mahalanobis distance") {
    // No observations that move the parameters away from where the prior sits would let the
    // prior residual vanish; with the start at the prior's mean and one observation the fit
    // only moves as far as the observation asks: χ²_prior = (x − μ)ᵀ Σ⁻¹ (x − μ).
    const rollgap::test::PoolControl pool(2);
    const std::vector<Coil> all = coils();
    const Eigen::Vector2d mu{5.8e-4, 1.1};
    Eigen::Matrix2d sigma;
    sigma << 2.5e-11, -1.0e-8, -1.0e-8, 1.0e-2;  // correlation −0.632
    const ScenarioCalibrationResult r = fit({all.front()}, mu, JointPrior{{0, 1}, mu, sigma}, pool);
    REQUIRE(r.fit.status == CalibrationStatus::converged);
    const Eigen::Vector2d d = r.fit.values - mu;
    CHECK(r.fit.chi_squared_priors ==
          rollgap::test::approx(d.dot(sigma.inverse() * d)).epsilon(1e-9));
}
