// Calibration of the mill model (core/calibration_observables.h): synthetic "plant"
// observations made by the model itself at known parameter values are fitted back to those
// values — exactly without noise, within their standard errors with seeded noise; a prior
// decides a parameter no observation sees; a stiffness and a mass seen only through one
// natural frequency are reported inseparable; modes are followed by shape.

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/calibration_observables.h"
#include "core/coupled_model.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace {

double& flow_stress(Scenario& s) { return s.strip.flow_stress; }
double& asperity_factor(Scenario& s) { return s.friction.asperity_factor; }
double& rayleigh_ratio(Scenario& s) { return s.structure.rayleigh_damping_ratio; }
double& span_length(Scenario& s) { return s.tensions.back.span_length; }
double& k1(Scenario& s) { return s.structure.k1; }
double& m1(Scenario& s) { return s.structure.mass[0]; }

Scenario at_speed(double speed) {
    Scenario s;
    s.rolls.speed = speed;
    return s;
}

// Force and torque at 5 m/s, force and forward slip at 19 m/s (the asperity friction matters
// most at low speed, where the film is thin), and the damping ratio of the 201 Hz mode.
ScenarioCalibration bite_and_mode_setup() {
    ScenarioCalibration setup;
    setup.conditions = {at_speed(5.0), at_speed(19.0)};
    setup.access = {flow_stress, asperity_factor, rayleigh_ratio};
    setup.parameters = {{380e6, 100e6, 800e6}, {1.0, 0.05, 1.0}, {0.04, 0.005, 0.2}};
    setup.observations = {
        {0, Observable::roll_force, 0.0, 0.0, {}},
        {0, Observable::torque, 0.0, 0.0, {}},
        {1, Observable::roll_force, 0.0, 0.0, {}},
        {1, Observable::forward_slip, 0.0, 0.0, {}},
        {1, Observable::damping_ratio, 0.0, 0.0, {-1, 201.0}},
    };
    return setup;
}

// Sets each observation to the model's prediction at `truth`, with relative uncertainties.
void observe(ScenarioCalibration& setup, const Eigen::VectorXd& truth,
             const std::vector<double>& relative_uncertainty) {
    const auto predicted = predict_observations(setup, truth);
    for (std::size_t i = 0; i < setup.observations.size(); ++i) {
        REQUIRE_MESSAGE(std::isfinite(predicted[i].value), predicted[i].failure);
        setup.observations[i].value = predicted[i].value;
        setup.observations[i].uncertainty = relative_uncertainty[i] * std::abs(predicted[i].value);
    }
}

Eigen::VectorXd vector(std::initializer_list<double> values) {
    Eigen::VectorXd v(static_cast<Eigen::Index>(values.size()));
    Eigen::Index i = 0;
    for (const double value : values) v(i++) = value;
    return v;
}

}  // namespace

TEST_CASE(
    "noise-free plant data: flow stress, asperity factor and Rayleigh ratio come back to 1e-4") {
    ScenarioCalibration setup = bite_and_mode_setup();
    const Eigen::VectorXd truth = vector({410e6, 0.7, 0.05});
    observe(setup, truth, {0.005, 0.01, 0.005, 0.02, 0.05});
    const ScenarioCalibrationResult result = calibrate_scenario(setup);
    REQUIRE(result.fit.status == CalibrationStatus::converged);
    for (Eigen::Index j = 0; j < truth.size(); ++j) {
        CAPTURE(j);
        CHECK(std::abs(result.fit.values(j) / truth(j) - 1.0) < 1e-4);
        CHECK(std::isfinite(result.fit.standard_errors(j)));
    }
    CHECK(result.fit.chi_squared_observations < 1e-6);
    CHECK(result.fit.degrees_of_freedom == 2);
    CHECK(result.fit.inseparable.empty());
    // The asperity factor started on its bound (1) and left it.
    CHECK(result.fit.bounds[1] == BoundState::inside);
}

TEST_CASE("seeded noise: the fitted values scatter around the truth by their standard errors") {
    // 8 seeds × 3 parameters: |error| > 2 standard errors has probability 4.6 % each, so more
    // than 4 of 24 (probability 0.5 %) means the errors are too small; the mean squared
    // normalised error estimates 1 (its spread over 24 draws: ±0.3).
    ScenarioCalibration clean = bite_and_mode_setup();
    const Eigen::VectorXd truth = vector({410e6, 0.7, 0.05});
    observe(clean, truth, {0.005, 0.01, 0.005, 0.02, 0.05});
    int beyond_two = 0, count = 0;
    double sum_z2 = 0.0;
    for (unsigned seed = 1; seed <= 8; ++seed) {
        ScenarioCalibration noisy = clean;
        std::mt19937 generator(seed);
        std::normal_distribution<double> normal(0.0, 1.0);
        for (auto& o : noisy.observations) o.value += o.uncertainty * normal(generator);
        const ScenarioCalibrationResult result = calibrate_scenario(noisy);
        REQUIRE(result.fit.status == CalibrationStatus::converged);
        for (Eigen::Index j = 0; j < truth.size(); ++j) {
            const double z = (result.fit.values(j) - truth(j)) / result.fit.standard_errors(j);
            CAPTURE(seed);
            CAPTURE(j);
            CAPTURE(z);
            CHECK(std::abs(z) < 4.0);
            beyond_two += std::abs(z) > 2.0 ? 1 : 0;
            sum_z2 += z * z;
            ++count;
        }
    }
    MESSAGE(beyond_two << " of " << count
                       << " beyond 2 standard errors; mean squared normalised error "
                       << sum_z2 / count);
    CHECK(beyond_two <= 4);
    CHECK(sum_z2 / count > 0.3);
    CHECK(sum_z2 / count < 2.0);
}

TEST_CASE(
    "a prior pulls a parameter the observations do not see to the prior, with the prior's uncertainty") {
    // The steady bite does not depend on the entry-span length (it enters the dynamics only).
    ScenarioCalibration setup;
    setup.conditions = {at_speed(5.0), at_speed(19.0)};
    setup.access = {flow_stress, span_length};
    setup.parameters = {{380e6, 100e6, 800e6}, {5.0, 1.0, 20.0, true, 7.0, 0.5}};
    setup.observations = {{0, Observable::roll_force, 0.0, 0.0, {}},
                          {1, Observable::roll_force, 0.0, 0.0, {}}};
    observe(setup, vector({410e6, 12.0}), {0.005, 0.005});
    const ScenarioCalibrationResult result = calibrate_scenario(setup);
    REQUIRE(result.fit.status == CalibrationStatus::converged);
    CHECK(result.fit.values(0) == rollgap::test::approx(410e6).epsilon(1e-6));
    CHECK(result.fit.values(1) == rollgap::test::approx(7.0).epsilon(1e-9));
    CHECK(result.fit.standard_errors(1) == rollgap::test::approx(0.5).epsilon(1e-6));
    REQUIRE(result.fit.unobservable.size() == 1);
    CHECK(result.fit.unobservable[0] == 1);
}

TEST_CASE("a stiffness and a mass seen through one natural frequency are reported inseparable") {
    ScenarioCalibration setup;
    setup.conditions = {Scenario{}};
    setup.access = {k1, m1};
    setup.parameters = {{25e9, 5e9, 100e9}, {40e3, 10e3, 100e3}};
    setup.observations = {{0, Observable::natural_frequency, 0.0, 0.0, {0, 0.0}}};
    observe(setup, vector({30e9, 45e3}), {0.002});
    const ScenarioCalibrationResult result = calibrate_scenario(setup);
    REQUIRE(result.fit.inseparable.size() == 1);
    CHECK(result.fit.inseparable[0] == std::vector<int>{0, 1});
    CHECK(result.fit.reciprocal_condition < 1e-4);
    // What the frequency does fix: the fit meets it.
    CHECK(std::abs(result.fit.residuals(0)) < 1e-3);
}

TEST_CASE("a mode is followed by its shape, not its index, through an avoided crossing") {
    // A narrow strip (a weak strip spring k4) nearly decouples the upper and the lower stack. With
    // the upper backup roll at 80 t the upper stack's mode (198.4 Hz, index 2) sits just below
    // the lower stack's (201.4 Hz, index 3); lightening the roll to 30 t lifts the upper mode to
    // 209.9 Hz, past the lower one. By index, "mode 2" would become the lower stack's mode.
    Scenario base;
    base.strip.width = 0.05;
    base.structure.mass[1] = 80e3;
    ScenarioCalibration setup;
    setup.conditions = {base};
    setup.access = {[](Scenario& s) -> double& { return s.structure.mass[1]; }};
    setup.parameters = {{80e3, 1e3, 500e3}};
    setup.observations = {{0, Observable::natural_frequency, 0.0, 1.0, {2, 0.0}},
                          {0, Observable::natural_frequency, 0.0, 1.0, {3, 0.0}}};
    const auto start = predict_observations(setup, vector({80e3}));
    const auto light = predict_observations(setup, vector({30e3}));

    Scenario lightened = base;
    lightened.structure.mass[1] = 30e3;
    const ModalAnalysis modal =
        modal_analysis(structure_matrices(lightened.structure),
                       reference_state(dynamics_scenario(lightened)).strip_stiffness);
    REQUIRE(modal.ok);
    // The upper stack's mode is now index 3, the lower stack's index 2.
    CHECK(light[0].value == rollgap::test::approx(modal.natural[3].frequency_Hz));
    CHECK(light[1].value == rollgap::test::approx(modal.natural[2].frequency_Hz));
    CHECK(light[0].value > start[0].value + 5.0);
    CHECK(light[1].value ==
          rollgap::test::approx(start[1].value).epsilon(1e-3));  // the lower stack did not change
    CHECK(light[0].mode_mac > 0.8);
    CHECK(light[1].mode_mac > 0.95);
}
