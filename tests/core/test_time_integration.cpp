// CVODE time integration of the nonlinear coupled model against its linearisation (docs/model.md
// §6, §7.3): started along the least-damped eigenvector, the gap oscillates at the eigenfrequency
// and its envelope grows or decays at the eigenvalue's real part, below and above the critical
// speed.

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/time_integration.h"
#include "support/least_damped_mode.h"
#include "support/approx.h"

using namespace rollgap;
using namespace rollgap::core;

namespace {

struct Measured {
    double growth_rate;  // 1/s, least squares on the log of the positive gap peaks
    double frequency;    // Hz, from upward zero crossings
    DynamicsStatus status;
};

Measured run_along_least_damped_mode(double speed, double amplitude, double duration) {
    Scenario s;
    s.rolls.speed = speed;
    const ReferenceState ref = reference_state(s);
    REQUIRE(ref.status == BiteStatus::ok);
    const CoupledModel model(s, ref);
    const test::Eigenpair mode = test::least_damped_mode(model);
    Eigen::VectorXd direction = mode.vector.real();
    direction /= std::abs(direction(2) - direction(3));  // unit gap amplitude
    Eigen::VectorXd z = model.equilibrium() + amplitude * direction;

    const double dt = 1.0 / 20000.0;
    std::vector<double> times;
    for (int i = 1; i * dt <= duration + 1e-12; ++i) times.push_back(i * dt);
    std::vector<double> t, g;
    const IntegrationResult run = integrate(model, z, 0.0, times, [&](const Sample& sample) {
        t.push_back(sample.t);
        g.push_back(sample.z(2) - sample.z(3));
    });

    // Fit after 0.1 s: the other modes, excited by the nonlinearity only, have died out.
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int peaks = 0;
    std::vector<double> crossings;
    for (std::size_t i = 1; i + 1 < g.size(); ++i) {
        if (t[i] < 0.1) continue;
        if (g[i] > 0 && g[i] > g[i - 1] && g[i] >= g[i + 1]) {
            const double y = std::log(g[i]);
            sx += t[i];
            sy += y;
            sxx += t[i] * t[i];
            sxy += t[i] * y;
            ++peaks;
        }
        if (g[i - 1] < 0 && g[i] >= 0)
            crossings.push_back(t[i - 1] + dt * (-g[i - 1]) / (g[i] - g[i - 1]));
    }
    const double slope = (peaks * sxy - sx * sy) / (peaks * sxx - sx * sx);
    const double frequency = (crossings.size() - 1) / (crossings.back() - crossings.front());
    return {slope, frequency, run.status};
}

}  // namespace

TEST_CASE("below the critical speed the nonlinear response decays at the least-damped eigenvalue") {
    Scenario s;
    s.rolls.speed = 19.0;
    const test::Eigenpair mode = test::least_damped_mode(CoupledModel(s, reference_state(s)));
    REQUIRE(mode.value.real() < 0.0);
    const Measured m = run_along_least_damped_mode(19.0, 1e-7, 1.0);
    CHECK(m.status == DynamicsStatus::ok);
    CHECK(m.growth_rate == rollgap::test::approx(mode.value.real()).epsilon(0.03));
    CHECK(m.frequency ==
          rollgap::test::approx(mode.value.imag() / (2 * std::numbers::pi)).epsilon(0.005));
}

TEST_CASE("above the critical speed the nonlinear response grows at the least-damped eigenvalue") {
    Scenario s;
    s.rolls.speed = 21.0;
    const test::Eigenpair mode = test::least_damped_mode(CoupledModel(s, reference_state(s)));
    REQUIRE(mode.value.real() > 0.0);
    const Measured m = run_along_least_damped_mode(21.0, 1e-7, 1.0);
    CHECK(m.status == DynamicsStatus::ok);
    CHECK(m.growth_rate == rollgap::test::approx(mode.value.real()).epsilon(0.03));
    CHECK(m.frequency ==
          rollgap::test::approx(mode.value.imag() / (2 * std::numbers::pi)).epsilon(0.005));
}

TEST_CASE("at the equilibrium the model stays put: z0 is a fixed point of the integration") {
    const Scenario s;
    const CoupledModel model(s, reference_state(s));
    Eigen::VectorXd z = model.equilibrium();
    const Eigen::VectorXd z0 = z;
    const IntegrationResult run = integrate(model, z, 0.0, {0.01, 0.02}, nullptr);
    REQUIRE(run.status == DynamicsStatus::ok);
    CHECK(std::abs(z(2) - z0(2)) < 1e-12);
    CHECK(std::abs(z(CoupledModel::film_index) - z0(CoupledModel::film_index)) <
          1e-6 * z0(CoupledModel::film_index));
}

TEST_CASE("cancellation stops the integration at the next output") {
    const Scenario s;
    const CoupledModel model(s, reference_state(s));
    Eigen::VectorXd z = model.equilibrium();
    int outputs = 0;
    Control control;
    control.cancelled = [&] { return outputs >= 3; };
    const IntegrationResult run = integrate(
        model, z, 0.0, {1e-4, 2e-4, 3e-4, 4e-4, 5e-4}, [&](const Sample&) { ++outputs; }, {},
        control);
    CHECK(run.status == DynamicsStatus::cancelled);
    CHECK(outputs == 3);
}
