// The tandem mill in the time domain (core/mill/mill_time.h; docs/model.md §12.8, the
// specification's §3, §7 and identities 7 and 8): the whole mill in CVODE with the thickness
// transport read off a history at t_d, S(t) - S(t_d) = L, against the frequency-domain analyses
// built independently of it: the rightmost root with the nominal delays (Newton on
// det(I - M(s) E(s)), core/mill/mill_delay.h) and A0's eigenvalues (transport frozen). Each case
// runs in well under a second in Release (a few seconds under the sanitizers), but the segments
// case: ~3 s (its 2.5 cm segments' strip waves hold CVODE to ~2 us steps, whatever the tolerance).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/mill/mill.h"
#include "core/mill/mill_delay.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_regenerative.h"
#include "core/mill/mill_stability.h"
#include "core/mill/mill_time.h"
#include "core/stability.h"
#include "tools/verify_mill/envelope.h"
#include "tools/verify_mill/mills.h"
#include "support/approx.h"

namespace mill_time_test {

using namespace rollgap::core;
using rollgap::tools::mills::two_stand_mill;

using rollgap::tools::envelope::decaying_case;
using rollgap::tools::envelope::Envelope;
using rollgap::tools::envelope::envelope;
using rollgap::tools::envelope::fit_kick;
using rollgap::tools::envelope::gap_series;
using rollgap::tools::envelope::grid;
using rollgap::tools::envelope::growing_case;
using rollgap::tools::envelope::KickCase;
using rollgap::tools::envelope::KickFit;
using rollgap::tools::envelope::segments_case;

// Identity 8 on one of the report's cases (tools/verify_mill/envelope.h): the root verified,
// only it and its conjugate right of Re s - separation (the rest e^-(separation from) smaller at
// the fit's start and shrinking), each stand's envelope at its rate within 2 % and its frequency
// within 0.5 %, the gap change a thousandth of the strip at most (the linear response).
KickFit check_identity_8(const KickCase& c, double separation, int min_peaks) {
    const KickFit fit = fit_kick(c);
    REQUIRE(fit.at.rightmost.found);
    REQUIRE(fit.at.rightmost.verified);
    const MillModel model(c.mill, fit.at.steady);
    const TransportTransfer transfer = transport_transfer(model.linearise(model.equilibrium()));
    REQUIRE(transfer.ok);
    const DelayRootCount right = nominal_delay_root_count(transfer, fit.root.real() - separation);
    REQUIRE(right.ok);
    REQUIRE(right.count == 2);
    REQUIRE(fit.run.status == MillTimeStatus::ok);
    REQUIRE(fit.run.max_step <= fit.run.delay[0] / 4.0);
    MESSAGE("rightmost root " << fit.root << " 1/s (" << fit.frequency << " Hz), rho "
                              << fit.at.margin.margin << ", " << fit.run.steps << " steps");
    REQUIRE(fit.stands.size() == 2);
    for (std::size_t k = 0; k < fit.stands.size(); ++k) {
        const Envelope& e = fit.stands[k];
        MESSAGE("stand " << k + 1 << ": growth " << e.growth_rate << " /s over " << e.peaks
                         << " peaks (error " << 100.0 * (e.growth_rate / fit.root.real() - 1.0)
                         << " %), frequency " << e.frequency << " Hz");
        CHECK(e.peaks >= min_peaks);
        CHECK(e.growth_rate == rollgap::test::approx(fit.root.real()).epsilon(0.02));
        CHECK(e.frequency == rollgap::test::approx(fit.frequency).epsilon(0.005));
        CHECK(fit.largest[k] < 1e-3 * c.mill.thickness[k + 1]);
    }
    return fit;
}

TEST_CASE("mill time domain: a 1e-9 m kick grows at the rightmost delay root's rate (identity 8)") {
    // two stands, a 0.05 m span at 9 m/s: ~82 /s at ~505 Hz, fitted over 0.05-0.1 s
    check_identity_8(growing_case(), 60.0, 20);
}

TEST_CASE(
    "mill time domain: a 1e-9 m kick decays at the rightmost delay root's rate (identity 8)") {
    // the same with the stands' structural damping at 0.2: rho < 1 (stable for every delay),
    // ~ -15 /s, fitted over 0.1-0.4 s (150 periods) with tolerances far below the motion
    const KickFit fit = check_identity_8(decaying_case(), 20.0, 100);
    CHECK(fit.at.delay_independent_stable);
    CHECK(fit.at.nominal_stable);
    CHECK(fit.root.real() < 0.0);
}

TEST_CASE("mill time domain: under segments a kick grows at the segments mill's rightmost root") {
    // two segments per span: the run integrates the segments' forces and the strip speed
    // between them, the root is the segments model's (~95 /s at ~513 Hz), 0.05-0.09 s
    check_identity_8(segments_case(), 60.0, 20);
}

TEST_CASE("mill time domain: before the transport arrives the mill is the frozen mill") {
    // Two stands with their 5 m span at 15 m/s: the strip takes tau = 0.37 s from stand 1 to
    // stand 2, so over a shorter run y1 of stand 2 is steady and the response started on A0's
    // least-damped mode decays at that eigenvalue's rate (the frozen mill, §12.4).
    const Mill m = two_stand_mill(5.0);
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);
    const Eigen::VectorXd z0 = model.equilibrium();
    const Linearisation lin = model.jacobian(z0, 0.0);
    REQUIRE(lin.status == DynamicsStatus::ok);
    const Eigen::VectorXcd values = balanced_eigenvalues(lin.jacobian);
    Eigen::Index best = -1;
    for (Eigen::Index j = 0; j < values.size(); ++j)
        if (values(j).imag() > 1.0 && (best < 0 || values(j).real() > values(best).real()))
            best = j;
    REQUIRE(best >= 0);
    const std::complex<double> lambda = values(best);
    REQUIRE(lambda.real() < 0.0);
    // its eigenvector by inverse iteration, turned so that the moving stand's gap is real
    const Eigen::Index n = lin.jacobian.rows();
    const Eigen::MatrixXcd shifted = lin.jacobian.cast<std::complex<double>>() -
                                     (lambda * (1.0 + 1e-10)) * Eigen::MatrixXcd::Identity(n, n);
    const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(shifted);
    Eigen::VectorXcd v = Eigen::VectorXcd::Ones(n);
    for (int k = 0; k < 4; ++k) v = lu.solve(v).normalized();
    int moving = 0;
    std::complex<double> gap[2];
    for (int k = 0; k < 2; ++k) {
        const int o = model.displacement_index(k);
        gap[k] = v(o + 2) - v(o + 3);
        if (std::abs(gap[k]) > std::abs(gap[moving])) moving = k;
    }
    v *= std::conj(gap[moving]) / std::norm(gap[moving]);  // that gap is 1
    MillKick kick;
    kick.state = 1e-8 * v.real();
    MillTimeOptions options;
    options.absolute_tolerance_scale = 1e-2;  // 1e-12 m on a motion of 1e-8 m

    const double frequency = lambda.imag() / (2.0 * std::numbers::pi);
    const double end = 0.3;
    const MillTimeResult run =
        mill_time_domain(m, steady, kick, grid(1.0 / (60.0 * frequency), end), options);
    REQUIRE(run.status == MillTimeStatus::ok);
    REQUIRE(run.delay[0] > end);
    // the transport has not arrived: stand 2 sees the steady strip throughout
    bool steady_entry = true, delayed = true;
    for (const MillTimeSample& s : run.samples) {
        steady_entry = steady_entry && s.stands[1].entry_thickness == m.thickness[1];
        delayed = delayed && std::abs(s.transport_time[0] / run.delay[0] - 1.0) < 1e-3;
    }
    CHECK(steady_entry);
    CHECK(delayed);
    std::vector<double> t, g;
    gap_series(run, moving, t, g);
    const Envelope e = envelope(t, g, 0.05, end);
    MESSAGE("frozen least-damped " << lambda << " 1/s; time domain " << e.growth_rate << " /s ("
                                   << 100.0 * (e.growth_rate / lambda.real() - 1.0) << " %), "
                                   << e.frequency << " Hz against " << frequency << "; "
                                   << run.steps << " steps");
    CHECK(e.peaks > 20);
    CHECK(e.growth_rate == rollgap::test::approx(lambda.real()).epsilon(0.02));
    CHECK(e.frequency == rollgap::test::approx(frequency).epsilon(0.005));
}

TEST_CASE(
    "mill time domain: a thickness step entering a stand moves its back stress at once, "
    "not the span's force (identity 7)") {
    const Mill m = two_stand_mill(5.0);
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);

    // on the model: sigma_b = T / y1, T the span's state
    const Eigen::VectorXd z0 = model.equilibrium();
    const double dy = 1e-7;
    const BiteState before = model.bite_state(1, z0.data());
    const BiteState after = model.bite_state(1, z0.data(), dy);
    const double y1 = before.entry_thickness;
    CHECK(after.entry_thickness - y1 == rollgap::test::approx(dy).epsilon(1e-9));
    // -sigma dy / y to first order; the exact T/(y + dy) - T/y differs by dy/y = 7e-5 of it
    CHECK(after.back_tension - before.back_tension ==
          rollgap::test::approx(-before.back_tension * dy / y1).epsilon(2.0 * dy / y1));

    // in time: stand 1's gap opened by dy at t = 0 reaches stand 2 when S(t) - S(0) = L, a step
    // in y1 there; sampled every 10 ns across the arrival
    const double tau = model.span_length(0) / model.stand(0).reference().bite.exit_speed;
    std::vector<double> times = grid(1e-3, tau - 1e-5);
    for (double t = tau - 1e-5; t <= tau + 1e-5; t += 1e-8) times.push_back(t);
    MillKick kick;
    kick.stand = 0;
    kick.gap = dy;
    MillTimeOptions options;
    options.absolute_tolerance_scale = 1e-2;
    const MillTimeResult run = mill_time_domain(m, steady, kick, times, options);
    REQUIRE(run.status == MillTimeStatus::ok);
    REQUIRE(run.samples.size() == times.size());
    const double steady_y1 = run.samples.front().stands[1].entry_thickness;
    std::size_t k = 0;
    while (k < run.samples.size() &&
           run.samples[k].stands[1].entry_thickness - steady_y1 < 0.5 * dy)
        ++k;
    REQUIRE(k < run.samples.size());
    REQUIRE(run.samples[k - 1].t > tau - 1e-5);  // inside the fine window
    const MillTimeSample& a = run.samples[k - 1];
    const MillTimeSample& b = run.samples[k];
    MESSAGE("the step arrives at " << b.t << " s (tau " << tau << " s)");
    // it is the strip that left stand 1 at the kick: departures t - (t - t_d) either side of 0
    CHECK(a.t - a.transport_time[0] < 0.0);
    CHECK(b.t - b.transport_time[0] >= 0.0);
    // the step is the kick: y2 of stand 1 just after t = 0 (at rest: it moves as t^2)
    const double step = b.stands[1].entry_thickness - a.stands[1].entry_thickness;
    CHECK(step == rollgap::test::approx(dy).epsilon(1e-3));
    // sigma_b,2 = T / y1 jumps by -sigma dy / y; T is a state, continuous: over the 10 ns it
    // moves by its rate alone (~1 % of the jump per microsecond, here 1e-4)
    const double jump = b.stands[1].back_tension - a.stands[1].back_tension;
    const double expected = -a.stands[1].back_tension * step / b.stands[1].entry_thickness;
    CHECK(jump == rollgap::test::approx(expected).epsilon(1e-3));
    CHECK(std::abs(b.span_force[1] - a.span_force[1]) <
          1e-3 * std::abs(expected) * b.stands[1].entry_thickness);
    // and stand 1's front stress, T / y2 of stand 1, does not see the step
    CHECK(std::abs(b.stands[0].front_tension - a.stands[0].front_tension) < 1e-3 * std::abs(jump));
}

TEST_CASE("mill time domain: a span going slack ends the run with the span and the time") {
    // The unstable mill of identity 8 with a low interstand set point (5 MPa): the regenerative
    // oscillation grows until the span's force reaches zero
    Mill m = two_stand_mill(0.05);
    m.speed = 9.0;
    m.interstand_tension = {5e6};
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    MillKick kick;
    kick.stand = 0;
    kick.gap = 1e-6;
    const double end = 0.2;
    const MillTimeResult run = mill_time_domain(m, steady, kick, grid(1e-4, end));
    MESSAGE(std::string(to_string(run.status)) << " at " << run.end_time << " s, span " << run.span
                                               << ": " << std::string(run.message));
    CHECK(run.status == MillTimeStatus::slack_span);
    CHECK(run.span == 1);  // between stands 1 and 2
    CHECK(run.stand == -1);
    CHECK(run.end_time > 0.0);
    CHECK(run.end_time < end);
    REQUIRE_FALSE(run.samples.empty());
    CHECK(run.samples.back().t <= run.end_time);
    double lowest = run.samples.front().span_force[1];
    for (const MillTimeSample& s : run.samples) lowest = std::min(lowest, s.span_force[1]);
    CHECK(lowest > 0.0);
    // the last outputs were near it: the force had fallen to a fraction of its set point
    CHECK(lowest < 0.5 * 5e6 * m.thickness[1]);

    // a kick that closes stand 2's gap by 30 um pulls the strip out of a 1 MPa span at once
    m = two_stand_mill(5.0);
    m.interstand_tension = {1e6};
    const MillSteadyState light = mill_steady_state(m);
    REQUIRE(light.status == MillSteadyStatus::ok);
    kick.stand = 1;
    kick.gap = -3e-5;
    const MillTimeResult sudden = mill_time_domain(m, light, kick, grid(1e-4, 0.01));
    CHECK(sudden.status == MillTimeStatus::slack_span);
    CHECK(sudden.span == 1);
    CHECK(sudden.end_time < 1e-3);
}

TEST_CASE("mill time domain: what the run cannot take is a status, and cancellation stops it") {
    const Mill m = two_stand_mill(5.0);
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    CHECK(mill_time_domain(m, steady, {}, {0.02, 0.01}).status == MillTimeStatus::invalid);
    MillKick wrong;
    wrong.stand = 2;
    CHECK(mill_time_domain(m, steady, wrong, {0.01}).status == MillTimeStatus::invalid);
    wrong.stand = -1;
    wrong.state = Eigen::VectorXd::Zero(3);
    CHECK(mill_time_domain(m, steady, wrong, {0.01}).status == MillTimeStatus::invalid);
    CHECK(mill_time_domain(m, MillSteadyState{}, {}, {0.01}).status == MillTimeStatus::invalid);

    // z0 is a fixed point: without a kick nothing moves
    const MillTimeResult still = mill_time_domain(m, steady, {}, {0.005, 0.01});
    REQUIRE(still.status == MillTimeStatus::ok);
    REQUIRE(still.samples.size() == 2);
    for (const MillStandSample& s : still.samples.back().stands) CHECK(std::abs(s.gap) < 1e-15);

    // cancellation is polled before each output
    int polls = 0;
    Control control;
    control.cancelled = [&] { return ++polls > 3; };
    MillKick kick;
    kick.stand = 1;
    kick.gap = 1e-8;
    const MillTimeResult cancelled =
        mill_time_domain(m, steady, kick, grid(1e-4, 1e-3), {}, control);
    CHECK(cancelled.status == MillTimeStatus::cancelled);
    CHECK(cancelled.samples.size() == 3);

    // a mill of one stand has no transport and no step limit of its own
    Mill one = m;
    one.stands.resize(1);
    one.thickness.resize(2);
    one.span_length.clear();
    one.interstand_tension.clear();
    one.exit_tension = default_mill().interstand_tension[3];
    const MillSteadyState single = mill_steady_state(one);
    REQUIRE(single.status == MillSteadyStatus::ok);
    kick.stand = 0;
    const MillTimeResult alone = mill_time_domain(one, single, kick, grid(1e-3, 0.01));
    CHECK(alone.status == MillTimeStatus::ok);
    CHECK(alone.delay.empty());
    CHECK(alone.samples.size() == 10);
}

}  // namespace mill_time_test
