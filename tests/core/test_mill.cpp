// The tandem mill's steady state and frozen dynamics (docs/model.md §12), against the identities
// of its specification: a mill of one stand is the single stand (state, Jacobian's eigenvalues,
// critical speed); the schedule carries one mass flow through every stand; with very long
// interstand spans the frozen mill falls apart into its stands, each with a constant front force,
// plus one near-zero root per interstand span; the assembled Jacobian is the rates' differences.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <vector>

#include "core/coupled_model.h"
#include "core/mill/mill.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_stability.h"
#include "core/stability.h"

#include "support/compare.h"
#include "support/jacobian_columns.h"
#include "tools/verify_mill/lu2019.h"
#include "tools/verify_mill/mills.h"
#include "support/approx.h"

namespace mill_test {

using namespace rollgap::core;
using rollgap::test::rel;
using rollgap::test::worst_nearest;

using rollgap::tools::mills::one_stand_mill;

TEST_CASE("mill identity: one stand with its exit held is the single stand") {
    const Scenario s;
    const Mill m = one_stand_mill(s);
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const BiteResult single = solve_roll_bite(s, steady_bite_state(s), {false});
    REQUIRE(single.status == BiteStatus::ok);
    const MillStandState& st = steady.stands.front();
    CHECK(st.roll_speed == s.rolls.speed);
    CHECK(st.force == single.force);  // the same bite, bit for bit
    CHECK(st.forward_slip == single.forward_slip);
    CHECK(steady.mass_flow ==
          rollgap::test::approx(single.exit_speed * exit_thickness(s)).epsilon(1e-15));

    // the frozen mill's Jacobian is the single stand's up to the span state's scale (T = s_b y1):
    // the same eigenvalues
    const MillStability mill = mill_frozen_stability(m);
    const SpeedStability alone = stability_at(s);
    REQUIRE(mill.frozen.status == DynamicsStatus::ok);
    REQUIRE(alone.status == DynamicsStatus::ok);
    REQUIRE(mill.frozen.eigenvalues.size() == alone.eigenvalues.size());
    const double worst = std::max(worst_nearest(mill.frozen.eigenvalues, alone.eigenvalues),
                                  worst_nearest(alone.eigenvalues, mill.frozen.eigenvalues));
    MESSAGE("one-stand mill vs single stand: worst relative eigenvalue distance " << worst);
    CHECK(worst <= 1e-9);
    CHECK(rel(mill.frozen.least_damped.frequency_Hz, alone.least_damped.frequency_Hz) <= 1e-9);

    // and its frozen critical speed is the single stand's (20.0967 m/s at 104.05 Hz)
    CriticalSpeedOptions options;
    options.stop_at_crossing = true;
    const CriticalSpeedResult a = mill_frozen_critical_speed(m, options);
    const CriticalSpeedResult b = critical_speed(s, options);
    REQUIRE(b.status == CriticalSpeedStatus::found);
    CHECK(a.status == b.status);
    MESSAGE("critical speed: mill of one stand "
            << a.critical_speed << " m/s at " << a.unstable_mode.frequency_Hz
            << " Hz, single stand " << b.critical_speed << " m/s at "
            << b.unstable_mode.frequency_Hz << " Hz");
    CHECK(rel(a.critical_speed, b.critical_speed) <= 1e-9);
    CHECK(rel(a.unstable_mode.frequency_Hz, b.unstable_mode.frequency_Hz) <= 1e-9);
}

TEST_CASE(
    "mill schedule: one mass flow through every stand, each stand's entry speed the exit "
    "speed of the stand before") {
    const Mill m = default_mill();
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    REQUIRE(steady.stands.size() == 5);
    CHECK(steady.mass_flow_residual <= 1e-10);
    CHECK(steady.stands.back().roll_speed == m.speed);
    for (int i = 0; i < 5; ++i) {
        const MillStandState& st = steady.stands[static_cast<std::size_t>(i)];
        CAPTURE(i);
        // u2 y2 = Q and, through the bite's own mass flow, u1 y1 = Q
        CHECK(rel(st.exit_speed * m.thickness[static_cast<std::size_t>(i + 1)], steady.mass_flow) <=
              1e-10);
        CHECK(rel(st.entry_speed * m.thickness[static_cast<std::size_t>(i)], steady.mass_flow) <=
              1e-10);
        if (i > 0)
            CHECK(rel(st.entry_speed, steady.stands[static_cast<std::size_t>(i - 1)].exit_speed) <=
                  1e-10);
        CHECK(st.forward_slip > 0.0);  // every stand drives its strip
        CHECK(st.back_tension == back_tension_stress(m, i));
        CHECK(st.front_tension == front_tension_stress(m, i));
        MESSAGE("stand " << i + 1 << ": roll speed " << st.roll_speed << " m/s, slip "
                         << st.forward_slip << ", force " << st.force / 1e3 << " kN, "
                         << st.bite_solves << " bite solves");
    }
    // roll speeds rise down the mill as the strip thins
    for (int i = 1; i < 5; ++i)
        CHECK(steady.stands[static_cast<std::size_t>(i)].roll_speed >
              steady.stands[static_cast<std::size_t>(i - 1)].roll_speed);
}

TEST_CASE(
    "mill schedule: a stand without a steady state is named, a description that is no mill "
    "is refused") {
    Mill m = default_mill();
    m.thickness[3] = m.thickness[2];  // stand 3 would not reduce
    CHECK(mill_steady_state(m).status == MillSteadyStatus::invalid);
    CHECK(std::string(mill_defect(m)).find("thinner") != std::string::npos);
    Mill too_many = default_mill();
    too_many.stands.resize(7);
    CHECK(mill_steady_state(too_many).status == MillSteadyStatus::invalid);

    // a very heavy first pass at very low friction skids
    Mill skid = default_mill();
    skid.stands[0].friction.model = FrictionModel::coulomb;
    skid.stands[0].friction.coulomb_coefficient = 0.005;
    const MillSteadyState st = mill_steady_state(skid);
    CHECK(st.status == MillSteadyStatus::no_steady_state);
    CHECK(st.stand == 0);
    CHECK(st.stands[0].status == BiteStatus::skidding);
}

// Stand i of `m` alone as a mill of one stand at its steady roll speed: its back side as the
// big mill's (the entry span for the first, else the constant back stress that a frozen span
// force over a fixed entry thickness is), its front side the big mill's span of the same
// length (a force T over the stand's own y2(t)) or the held exit stress for the last.
Mill stand_alone(const Mill& m, int i, double roll_speed) {
    const auto k = static_cast<std::size_t>(i);
    Mill one = m;
    one.stands = {m.stands[k]};
    one.thickness = {m.thickness[k], m.thickness[k + 1]};
    one.span_length.clear();
    one.interstand_tension.clear();
    if (i > 0) {
        one.entry = MillBoundary::constant;
        one.entry_tension = back_tension_stress(m, i);
    }
    if (i + 1 < m.size()) {
        one.exit = MillBoundary::span;
        one.exit_span_length = m.span_length[k];
        one.exit_tension = front_tension_stress(m, i);
    }
    one.speed = roll_speed;
    return one;
}

TEST_CASE("mill frozen: very long interstand spans leave the stands each with a constant force") {
    // L -> infinity: E ybar / L -> 0, the span forces stop moving, and the frozen mill falls
    // apart into its stands. A span carries a force, so a stand's front stress is still T / y2(t):
    // the stands' limit is each stand with a constant front force (the exit span of a
    // one-stand mill of the same length), not a constant front stress (docs/model.md §12.4).
    Mill m = default_mill();
    m.stands.resize(3);
    m.thickness.resize(4);
    m.span_length.assign(2, 1e7);  // E ybar / L: 5e-7 of a 5 m span's stiffness
    m.interstand_tension.resize(2);
    m.exit = MillBoundary::constant;
    const MillStability mill = mill_frozen_stability(m);
    REQUIRE(mill.frozen.status == DynamicsStatus::ok);

    std::vector<std::complex<double>> stands;
    for (int i = 0; i < m.size(); ++i) {
        const double v = mill.steady.stands[static_cast<std::size_t>(i)].roll_speed;
        const MillStability alone = mill_frozen_stability(stand_alone(m, i, v));
        REQUIRE(alone.frozen.status == DynamicsStatus::ok);
        // the same bite: the stand's steady state does not depend on its neighbours
        CHECK(rel(alone.steady.stands[0].force,
                  mill.steady.stands[static_cast<std::size_t>(i)].force) < 1e-12);
        stands.insert(stands.end(), alone.frozen.eigenvalues.begin(),
                      alone.frozen.eigenvalues.end());
    }
    // one state per stand block, the entry span, two interstand spans against the two exit spans
    REQUIRE(mill.frozen.eigenvalues.size() == stands.size());
    // The spans' own roots are near zero (a rate E ybar / L times a speed's slope in T): the
    // interstand span's feels both its stands' speeds, the exit span's one, so those two pairs
    // differ; they are counted, the stands' roots compared.
    const auto split = [](const std::vector<std::complex<double>>& roots,
                          std::vector<std::complex<double>>& stand_roots) {
        int near_zero = 0;
        for (const auto& x : roots) {
            if (std::abs(x) < 1e-2) ++near_zero;
            else stand_roots.push_back(x);
        }
        return near_zero;
    };
    std::vector<std::complex<double>> in_mill, alone;
    CHECK(split(mill.frozen.eigenvalues, in_mill) == 2);
    CHECK(split(stands, alone) == 2);
    const double worst = std::max(worst_nearest(alone, in_mill), worst_nearest(in_mill, alone));
    MESSAGE("stands alone vs the mill with 1e7 m spans: worst relative distance " << worst);
    CHECK(worst <= 1e-6);
}

TEST_CASE("mill frozen: the assembled Jacobian is the finite differences of the mill's rates") {
    const Mill m = default_mill();
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);
    const Eigen::VectorXd z0 = model.equilibrium();
    const Linearisation assembled = model.jacobian(z0, 0.0);
    const Linearisation differences = finite_difference_jacobian(model, z0, 0.0);
    REQUIRE(assembled.status == DynamicsStatus::ok);
    REQUIRE(differences.status == DynamicsStatus::ok);
    // column by column, relative to the column's size (the differences' noise ~1e-7 of it)
    const rollgap::test::ColumnDistance d =
        rollgap::test::column_distance(assembled.jacobian, differences.jacobian);
    MESSAGE("5-stand frozen Jacobian, assembled vs central differences: worst column " << d.worst);
    CHECK(d.worst < 1e-5);
    CHECK(d.nonzero_where_zero == 0);
}

}  // namespace mill_test

namespace mill_test {

TEST_CASE("mill transport inputs: B and B' are the differences of the rates in y1 and y1'") {
    const Mill m = default_mill();
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);
    const Eigen::VectorXd z0 = model.equilibrium();
    const MillLinearisation lin = model.linearise(z0);
    REQUIRE(lin.status == DynamicsStatus::ok);
    const int n = model.size(), p = m.size() - 1;
    REQUIRE(lin.input.rows() == n);
    REQUIRE(lin.input.cols() == p);
    REQUIRE(lin.output.rows() == p);
    CHECK((lin.jacobian - model.jacobian(z0, 0.0).jacobian).norm() == 0.0);

    const auto rates = [&](int stand, double dy1, double dy1_rate) {
        std::vector<double> deviation(static_cast<std::size_t>(m.size()), 0.0);
        std::vector<double> rate(deviation);
        deviation[static_cast<std::size_t>(stand)] = dy1;
        rate[static_cast<std::size_t>(stand)] = dy1_rate;
        Eigen::VectorXd zdot(n);
        REQUIRE(model.rhs_with_transport(0.0, z0.data(), deviation.data(), rate.data(),
                                         zdot.data()) == DynamicsStatus::ok);
        return zdot;
    };
    double worst_b = 0.0, worst_rate = 0.0;
    for (int i = 0; i < p; ++i) {
        // central differences in the entering thickness of stand i + 1, 1e-7 m as q's
        const double h = 1e-7;
        const Eigen::VectorXd b = (rates(i + 1, h, 0.0) - rates(i + 1, -h, 0.0)) / (2.0 * h);
        worst_b = std::max(worst_b, (lin.input.col(i) - b).norm() / b.norm());
        // only stand i + 1's block and the spans it touches move
        for (int s = 0; s < m.size(); ++s) {
            if (s == i + 1) continue;
            CHECK(lin.input.col(i).segment(model.displacement_index(s), 13).norm() == 0.0);
        }
        // y1' enters the film equation linearly (theta' = (y1' - y2') / (2 a theta))
        const double r = 1e-3;
        const Eigen::VectorXd b_rate = (rates(i + 1, 0.0, r) - rates(i + 1, 0.0, -r)) / (2.0 * r);
        worst_rate = std::max(worst_rate, (lin.input_rate.col(i) - b_rate).norm() / b_rate.norm());
        // C picks stand i's exit thickness y2 = y2_ref + q3 - q4; the delay is L / u2
        const BiteState state = model.bite_state(i, z0.data());
        Eigen::VectorXd dz = Eigen::VectorXd::Zero(n);
        dz(model.displacement_index(i) + 2) = 1e-6;
        CHECK(lin.output.row(i).dot(dz) == rollgap::test::approx(1e-6).epsilon(1e-12));
        CHECK(rel(lin.delay[static_cast<std::size_t>(i)] *
                      steady.stands[static_cast<std::size_t>(i)].exit_speed,
                  m.span_length[static_cast<std::size_t>(i)]) < 1e-7);
        CHECK(state.exit_thickness > 0.0);
    }
    MESSAGE("B against differences: worst column " << worst_b << "; B' " << worst_rate);
    CHECK(worst_b < 1e-5);
    CHECK(worst_rate < 1e-9);
}

}  // namespace mill_test

namespace mill_test {

TEST_CASE("Lu et al. 2019: the published schedule's own mass flow and forward slips") {
    // Not a test of the model (docs/mill-verification.md compares it): the published entry
    // speeds times entry thicknesses carry one mass flow, and every stand's exit speed (the next
    // stand's entry speed) exceeds its roll speed.
    namespace lu = rollgap::tools::lu2019;
    double lo = 1e300, hi = 0.0;
    for (int i = 0; i < lu::stands; ++i) {
        const double q = lu::entry_speed[i] * lu::thickness_mm[i];
        lo = std::min(lo, q);
        hi = std::max(hi, q);
    }
    MESSAGE("published u1 h1 from " << lo << " to " << hi << " mm m/s: spread "
                                    << (hi - lo) / hi * 100.0 << " %");
    CHECK((hi - lo) / hi < 5e-3);
    for (int i = 0; i + 1 < lu::stands; ++i) {
        const double slip = lu::entry_speed[i + 1] / lu::roll_speed[i] - 1.0;
        MESSAGE("stand " << i + 1 << ": published forward slip " << slip * 100.0 << " %");
        CHECK(slip > 0.0);
    }
}

}  // namespace mill_test

namespace mill_test {

// The default mill's first three stands (2.80 -> 2.25 -> 1.88 -> 1.60 mm) with interstand set
// points of its own, not the default's.
Mill three_stands() {
    Mill m = default_mill();
    m.stands.resize(3);
    m.thickness.resize(4);
    m.span_length.resize(2);
    m.interstand_tension = {80e6, 95e6};
    m.exit_tension = 60e6;
    m.speed = 8.0;
    return m;
}

// The mill in speeds mode at the roll speeds `steady` solved, its interstand tensions started
// from `guess` (the truth forgotten).
Mill in_speeds_mode(Mill m, const MillSteadyState& steady, std::vector<double> guess) {
    m.mode = MillMode::speeds;
    for (int i = 0; i < m.size(); ++i)
        m.stands[static_cast<std::size_t>(i)].rolls.speed =
            steady.stands[static_cast<std::size_t>(i)].roll_speed;
    m.interstand_tension = std::move(guess);
    return m;
}

TEST_CASE("mill speeds: a schedule's roll speeds given back recover its tensions and its state") {
    // A synthetic truth: the schedule mode solves the roll speeds that carry one mass flow at
    // the set points; given those speeds, speeds mode must find the same tensions from a
    // different start, the same bites, and a frozen mill with the same eigenvalues.
    // Three stands with their own set points, then the default five (four spans coupled
    // through the last stand's flow), each from a start the truth is not.
    for (const bool five : {false, true}) {
        const Mill truth = five ? default_mill() : three_stands();
        const MillSteadyState schedule = mill_steady_state(truth);
        REQUIRE(schedule.status == MillSteadyStatus::ok);
        const Mill m = in_speeds_mode(
            truth, schedule, five ? std::vector<double>(4, 90e6) : std::vector<double>{60e6, 60e6});
        const auto start = std::chrono::steady_clock::now();
        const MillSteadyState speeds = mill_steady_state(m);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        REQUIRE(speeds.status == MillSteadyStatus::ok);
        double tension = 0.0, force = 0.0;
        for (int i = 0; i < m.size(); ++i) {
            const auto k = static_cast<std::size_t>(i);
            tension = std::max(
                {tension, rel(speeds.stands[k].back_tension, schedule.stands[k].back_tension),
                 rel(speeds.stands[k].front_tension, schedule.stands[k].front_tension)});
            force = std::max(force, rel(speeds.stands[k].force, schedule.stands[k].force));
            CHECK(speeds.stands[k].roll_speed == schedule.stands[k].roll_speed);
        }
        MESSAGE("speeds mode, " << m.size() << " stands: " << ms << " ms, "
                                << speeds.newton_iterations << " Newton steps, "
                                << speeds.stands.front().bite_solves
                                << " bite solves; worst tension " << tension << ", force " << force
                                << " relative; mass-flow residual " << speeds.mass_flow_residual);
        CHECK(tension < 1e-7);
        CHECK(force < 1e-7);
        CHECK(speeds.mass_flow_residual <= 1e-10);
        CHECK(rel(speeds.mass_flow, schedule.mass_flow) < 1e-10);
        // the dynamics run on the solved tensions: the frozen mill is the schedule's
        const MillStability a = mill_frozen_stability(truth);
        const MillStability b = mill_frozen_stability(m);
        REQUIRE(a.frozen.status == DynamicsStatus::ok);
        REQUIRE(b.frozen.status == DynamicsStatus::ok);
        const double worst = std::max(worst_nearest(a.frozen.eigenvalues, b.frozen.eigenvalues),
                                      worst_nearest(b.frozen.eigenvalues, a.frozen.eigenvalues));
        MESSAGE("frozen eigenvalues, schedule vs speeds mode: worst relative distance " << worst);
        CHECK(worst < 1e-6);
    }
}

TEST_CASE("mill speeds: a span the speeds would compress is named, as is a stand that skids") {
    const Mill truth = three_stands();
    const MillSteadyState schedule = mill_steady_state(truth);
    REQUIRE(schedule.status == MillSteadyStatus::ok);
    // stand 2 3 % slower than the flow from stand 1 needs: span 1 (stands 1-2) would push
    Mill slow = in_speeds_mode(truth, schedule, truth.interstand_tension);
    slow.stands[1].rolls.speed *= 0.97;
    const MillSteadyState slack = mill_steady_state(slow);
    CHECK(slack.status == MillSteadyStatus::no_steady_state);
    CHECK(slack.span == 1);
    CHECK(slack.stand == -1);
    // stand 2 10 % fast: it delivers more than stand 3 takes, span 2 (stands 2-3) would push
    Mill fast = in_speeds_mode(truth, schedule, truth.interstand_tension);
    fast.stands[1].rolls.speed *= 1.10;
    const MillSteadyState pushed = mill_steady_state(fast);
    CHECK(pushed.status == MillSteadyStatus::no_steady_state);
    CHECK(pushed.span == 2);
    // the last stand 10 % fast: span 2's tension rises until a bite can no longer carry it
    Mill pulling = in_speeds_mode(truth, schedule, truth.interstand_tension);
    pulling.stands[2].rolls.speed *= 1.10;
    pulling.speed *= 1.10;
    const MillSteadyState pulled = mill_steady_state(pulling);
    MESSAGE("the last stand 10 % fast: " << std::string(pulled.message) << ", stand "
                                         << pulled.stand << ", span " << pulled.span);
    CHECK(pulled.status == MillSteadyStatus::no_steady_state);
    REQUIRE(pulled.stand >= 0);
    CHECK(pulled.stands[static_cast<std::size_t>(pulled.stand)].status != BiteStatus::ok);
    // a stand without its roll speed is no description of a speeds-mode mill
    Mill missing = in_speeds_mode(truth, schedule, truth.interstand_tension);
    missing.stands[0].rolls.speed = 0.0;
    CHECK(mill_steady_state(missing).status == MillSteadyStatus::invalid);
}

}  // namespace mill_test
