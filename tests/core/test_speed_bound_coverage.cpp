// The 95 % lower bound on a critical speed covers the truth (issue 20, item 2; docs/model.md
// §13.2): a synthetic stand whose viscosity and asperity factor are known (6.0e-4 Pa s and 1.2,
// not the defaults the fit starts from) is observed through its roll force and forward slip at
// 10, 15 and 20 m/s with seeded Gaussian noise of the stated uncertainties (0.5 % and 2 %); each
// of 40 calibrations gives a posterior, carried linearly to the critical speed; the truth's
// critical speed must lie at or above the one-sided 95 % bound in at least 90 % of them (36 of
// 40). Cheap observables (one bite solve each) keep the 40 fits to a few seconds (~30 s under
// the sanitizers).

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "core/calibration_observables.h"
#include "core/propagation.h"
#include "core/roll_bite.h"
#include "core/scenario.h"
#include "core/stability.h"
#include "support/critical_speed_figure.h"
#include "support/pool_control.h"

namespace speed_bound_coverage_test {

using namespace rollgap::core;

TEST_CASE("coverage: the 95 % bound on the critical speed holds for >= 36 of 40 calibrations") {
    Scenario truth;
    truth.lubricant.viscosity = 6.0e-4;
    truth.friction.asperity_factor = 1.2;
    CriticalSpeedOptions search;
    search.stop_at_crossing = true;
    const CriticalSpeedResult true_speed = critical_speed(truth, search);
    REQUIRE(true_speed.status == CriticalSpeedStatus::found);

    const std::vector<double> speeds{10.0, 15.0, 20.0};
    constexpr double force_uncertainty = 0.005, slip_uncertainty = 0.02;  // relative
    std::vector<double> true_force, true_slip;
    for (double v : speeds) {
        Scenario s = truth;
        s.rolls.speed = v;
        BiteOptions options;
        options.distributions = false;
        const BiteResult bite = solve_roll_bite(s, steady_bite_state(s), options);
        REQUIRE(bite.status == BiteStatus::ok);
        true_force.push_back(bite.force);
        true_slip.push_back(bite.forward_slip);
    }

    const rollgap::test::PoolControl pool(2);
    const Scenario start;  // the defaults: 5.5e-4 Pa s, 1.0
    const Figure speed = rollgap::test::critical_speed_of_viscosity_and_asperity(start);
    int covered = 0, fitted = 0;
    double mean_sigma = 0.0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        std::mt19937_64 generator(seed);
        std::normal_distribution<double> normal;
        ScenarioCalibration setup;
        for (std::size_t c = 0; c < speeds.size(); ++c) {
            Scenario s = start;
            s.rolls.speed = speeds[c];
            setup.conditions.push_back(s);
            const double force_u = force_uncertainty * true_force[c];
            const double slip_u = slip_uncertainty * true_slip[c];
            setup.observations.push_back({static_cast<int>(c),
                                          Observable::roll_force,
                                          true_force[c] + force_u * normal(generator),
                                          force_u,
                                          {}});
            setup.observations.push_back({static_cast<int>(c),
                                          Observable::forward_slip,
                                          true_slip[c] + slip_u * normal(generator),
                                          slip_u,
                                          {}});
        }
        setup.access = {[](Scenario& s) -> double& { return s.lubricant.viscosity; },
                        [](Scenario& s) -> double& { return s.friction.asperity_factor; }};
        setup.parameters = {{start.lubricant.viscosity, 1e-4, 2e-3},
                            {start.friction.asperity_factor, 0.2, 3.0}};
        const ScenarioCalibrationResult r = calibrate_scenario(setup, pool.control);
        if (r.fit.status != CalibrationStatus::converged) continue;
        ++fitted;
        const Eigen::VectorXd x = r.fit.values;
        const Eigen::MatrixXd covariance = r.fit.standard_errors.asDiagonal() * r.fit.correlation *
                                           r.fit.standard_errors.asDiagonal();
        const Propagated p = propagate_linear(speed, x, covariance, pool.control);
        if (!p.ok) continue;
        mean_sigma += p.standard_deviation;
        if (true_speed.critical_speed >= lower_bound(p, 0.95)) ++covered;
    }
    MESSAGE("true critical speed " << true_speed.critical_speed << " m/s; " << fitted
                                   << " of 40 fits converged, mean sigma " << mean_sigma / fitted
                                   << " m/s; the 95 % bound held in " << covered << " of 40");
    CHECK(fitted == 40);
    CHECK(covered >= 36);
}

}  // namespace speed_bound_coverage_test
