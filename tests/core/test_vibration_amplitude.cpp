// The amplitude analysis (docs/model.md §7.4) against the linear frequency response of the
// linearised model: with a small excitation, the settled response of the nonlinear model is
// |e3^T (i w I - J)^-1 B| ds, where B = df/ds_b is how the back tension the bite sees drives the
// state (in span mode, the Jacobian column of the tension state).

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/amplitude.h"
#include "core/stability.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace {

double linear_response_x3(const Scenario& s, double frequency_Hz, double excitation) {
    const CoupledModel model(s, reference_state(s));
    const Eigen::MatrixXd J = linearise(model, model.equilibrium()).jacobian;
    const Eigen::VectorXd B = J.col(model.back_tension_index());
    const int n = model.size();
    const std::complex<double> iw(0.0, 2.0 * std::numbers::pi * frequency_Hz);
    const Eigen::MatrixXcd A =
        iw * Eigen::MatrixXcd::Identity(n, n) - J.cast<std::complex<double>>();
    const Eigen::VectorXcd response =
        A.partialPivLu().solve(B.cast<std::complex<double>>() * excitation);
    return std::abs(response(2));
}

}  // namespace

TEST_CASE(
    "the settled forced response equals the linear frequency response, at resonance and off it") {
    Scenario s;
    s.rolls.speed = 10.0;  // well damped: the transient dies within the window
    for (double frequency : {0.0, 60.0}) {
        CAPTURE(frequency);
        AmplitudeOptions o;
        o.window = 1.0;
        o.excitation_frequency_Hz = frequency;
        const AmplitudeResult r = vibration_amplitude(s, o);
        REQUIRE(r.status == AmplitudeStatus::settled);
        const double linear =
            linear_response_x3(s, r.excitation_frequency_Hz, o.excitation_amplitude);
        CHECK(r.upper_roll == rollgap::test::approx(linear).epsilon(0.02));
        CHECK(r.gap > r.upper_roll);  // the lower roll moves against the upper one
    }
}

TEST_CASE(
    "the default excitation is at the least-damped eigenfrequency, where the response peaks") {
    Scenario s;
    s.rolls.speed = 10.0;
    AmplitudeOptions o;
    o.window = 1.0;
    const AmplitudeResult resonant = vibration_amplitude(s, o);
    const SpeedStability linear = stability_at(s);
    CHECK(resonant.excitation_frequency_Hz == linear.least_damped.frequency_Hz);
    o.excitation_frequency_Hz = 0.8 * resonant.excitation_frequency_Hz;
    const AmplitudeResult detuned = vibration_amplitude(s, o);
    CHECK(resonant.upper_roll > 2.0 * detuned.upper_roll);
}

TEST_CASE("small excitations respond linearly") {
    Scenario s;
    s.rolls.speed = 10.0;
    AmplitudeOptions o;
    o.window = 1.0;
    const AmplitudeResult full = vibration_amplitude(s, o);
    o.excitation_amplitude = 0.5e6;
    const AmplitudeResult half = vibration_amplitude(s, o);
    CHECK(half.upper_roll == rollgap::test::approx(0.5 * full.upper_roll).epsilon(0.01));
}

TEST_CASE("above the critical speed the response grows until a physical limit ends the run") {
    Scenario s;
    s.rolls.speed = 24.0;
    AmplitudeOptions o;
    o.window = 2.0;
    const AmplitudeResult r = vibration_amplitude(s, o);
    CHECK(r.least_damped_growth_rate > 0.0);
    CHECK(r.status == AmplitudeStatus::limit_reached);
    CHECK(r.end_time < o.window);
    CHECK((r.end_status == DynamicsStatus::slack_strip ||
           r.end_status == DynamicsStatus::contact_lost ||
           r.end_status == DynamicsStatus::skidding));
    // the windows before the limit grow
    CHECK(r.windows[1].upper_roll > r.windows[0].upper_roll);
}

TEST_CASE("a speed without a steady state is reported, not simulated") {
    Scenario s;
    s.lubricant.limiting_shear = false;
    s.rolls.speed = 30.0;  // skids (docs/model.md §4)
    const AmplitudeResult r = vibration_amplitude(s);
    CHECK(r.status == AmplitudeStatus::no_steady_state);
    CHECK(r.steady_status == BiteStatus::skidding);
}
