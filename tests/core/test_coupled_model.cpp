// The coupled mill-bite-film model (docs/model.md §5-6), checked against independent references:
// the steady state recomputed from the bite solver and the Wilson-Walowit film, k4 by a separate
// central difference, the total-force identity of §5 written out with K_s + k4 b b^T, the closed
// forms of the squeeze / theta-dot terms of the two film models, and the exponential relaxation
// of the inlet film at the rate of eq. (11).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/coupled_model.h"
#include "core/inlet_film.h"
#include "core/roll_bite.h"
#include "core/stability.h"
#include "core/time_integration.h"

#include "support/compare.h"
#include "support/dynamics_scenarios.h"
#include "support/approx.h"

namespace {

using namespace rollgap::core;

using rollgap::test::rel;

// The inlet relaxation rate of eq. (11): theta^2 (1 - exp(-gamma (sigma - s_b))) / (6 gamma eta0),
// from the scenario's inputs alone (theta = sqrt((y1 - y2) / a) in steady state).
double relaxation_rate(const Scenario& s) {
    const double y1 = s.strip.entry_thickness, y2 = y1 * (1.0 - s.strip.reduction);
    const double theta2 = (y1 - y2) / s.rolls.radius;
    const double g = s.lubricant.pressure_viscosity;
    return theta2 * (1.0 - std::exp(-g * (s.strip.flow_stress - s.tensions.back.stress))) /
           (6.0 * g * s.lubricant.viscosity);
}

// Evaluates the rhs at enough other states that nothing of z0's evaluation can be remembered.
void visit_elsewhere(const CoupledModel& model) {
    const Eigen::VectorXd z0 = model.equilibrium();
    Eigen::VectorXd f(model.size());
    for (int k = 1; k <= 12; ++k) {
        Eigen::VectorXd z = z0;
        z(2) += 1e-8 * k;
        z(9) -= 1e-4 * k;
        z(CoupledModel::film_index) *= 1.0 + 1e-3 * k;
        model.rhs(0.0, z.data(), f.data());
    }
}

using Variant = rollgap::test::NamedScenario;
std::vector<Variant> variants() { return rollgap::test::dynamics_scenarios(); }

}  // namespace

TEST_CASE("coupled model: the equilibrium is a steady state, f(z0) = 0 component by component") {
    for (const Variant& var : variants()) {
        CAPTURE(var.name);
        const Scenario& s = var.s;
        const ReferenceState ref = reference_state(s);
        REQUIRE(ref.status == BiteStatus::ok);
        const double v = s.rolls.speed;

        // the reference film is the Wilson-Walowit film of the reference bite
        const double h00 = wilson_walowit_film(
            s.lubricant.viscosity, s.lubricant.pressure_viscosity, 0.5 * (ref.bite.entry_speed + v),
            ref.bite.inlet_angle, s.strip.flow_stress, s.tensions.back.stress);
        CHECK(rel(ref.bite.inlet_film, h00) < 1e-12);
        CHECK(rel(ref.bite.inlet_angle,
                  std::sqrt(s.strip.entry_thickness * s.strip.reduction / s.rolls.radius)) < 1e-12);

        const CoupledModel model(s, ref);
        visit_elsewhere(model);  // f(z0) must not depend on what was evaluated before
        const Eigen::VectorXd z0 = model.equilibrium();
        Eigen::VectorXd f(model.size());
        BiteResult bite;
        REQUIRE(model.rhs(0.0, z0.data(), f.data(), &bite) == DynamicsStatus::ok);

        for (int i = 0; i < 6; ++i) CHECK(f(i) == 0.0);  // q' = 0
        // m_i q''_i is a force: against the rolling force, to the bite's repeatability (1e-9)
        for (int i = 0; i < 6; ++i) {
            CAPTURE(i);
            CHECK(std::abs(s.structure.mass[static_cast<std::size_t>(i)] * f(6 + i)) <=
                  1e-9 * ref.bite.force);
        }
        // h0': against the supply term theta u1bar
        const double supply = ref.bite.inlet_angle * 0.5 * (ref.bite.entry_speed + v);
        CHECK(std::abs(f(CoupledModel::film_index)) <= 1e-9 * supply);
        // tensions: (E/L) (u1 - u1_ref) against (E/L) v
        if (model.back_tension_index() >= 0) {
            const double scale = s.strip.youngs_modulus / s.tensions.back.span_length * v;
            CHECK(std::abs(f(model.back_tension_index())) <= 1e-9 * scale);
        }
        if (model.front_tension_index() >= 0) {
            const double scale = s.strip.youngs_modulus / s.tensions.front.span_length * v;
            CHECK(std::abs(f(model.front_tension_index())) <= 1e-9 * scale);
        }
        // the bite at z0 (fixed film h00) is the steady bite (film solved inside)
        CHECK(rel(bite.force, ref.bite.force) < 1e-9);
        CHECK(std::abs(bite.entry_speed - ref.bite.entry_speed) < 1e-9 * v);
        const BiteResult fresh = solve_roll_bite(s, model.bite_state(0.0, z0.data()), {false});
        REQUIRE(fresh.status == BiteStatus::ok);
        CHECK(rel(fresh.force, ref.bite.force) < 1e-9);
    }
}

TEST_CASE("coupled model: k4 is -dP/dy2 at the steady film, about 20 GN/m at the defaults") {
    const Scenario s;
    const ReferenceState ref = reference_state(s);
    REQUIRE(ref.status == BiteStatus::ok);
    // an independent central difference with another step, the film steady (inlet_film = 0)
    const double delta = 2e-7;
    BiteState lo = steady_bite_state(s), hi = steady_bite_state(s);
    REQUIRE(lo.inlet_film == 0.0);
    lo.exit_thickness -= delta;
    hi.exit_thickness += delta;
    const BiteResult a = solve_roll_bite(s, lo, {false});
    const BiteResult b = solve_roll_bite(s, hi, {false});
    REQUIRE(a.status == BiteStatus::ok);
    REQUIRE(b.status == BiteStatus::ok);
    const double k4 = -(b.force - a.force) / (2.0 * delta);
    MESSAGE("k4 = " << ref.strip_stiffness << " N/m (independent difference " << k4 << ")");
    CHECK(ref.strip_stiffness > 0.0);
    CHECK(rel(ref.strip_stiffness, k4) < 1e-5);
    CHECK(ref.strip_stiffness > 15e9);
    CHECK(ref.strip_stiffness < 25e9);

    // with the film held at h00 instead, the bite is stiffer or softer but not the same quantity:
    // k4 is defined with the steady film (the check guards against a frozen-film k4)
    BiteState flo = lo, fhi = hi;
    flo.inlet_film = fhi.inlet_film = ref.bite.inlet_film;
    const double frozen =
        -(solve_roll_bite(s, fhi, {false}).force - solve_roll_bite(s, flo, {false}).force) /
        (2.0 * delta);
    MESSAGE("dP/dy2 with the film frozen at h00: " << -frozen << " N/m");
    CHECK(rel(frozen, ref.strip_stiffness) > 1e-3);

    // with_strip_stiffness = false skips it
    CHECK(reference_state(s, false).strip_stiffness == 0.0);
}

TEST_CASE("coupled model: M q'' + C q' + (K_s + k4 b b^T) q = b (P - P_ref + k4 g)") {
    for (const Variant& var : variants()) {
        CAPTURE(var.name);
        const Scenario& s = var.s;
        const ReferenceState ref = reference_state(s);
        REQUIRE(ref.status == BiteStatus::ok);
        const CoupledModel model(s, ref);
        const StructureMatrices mats = structure_matrices(s.structure);
        const double k4 = ref.strip_stiffness;
        const Matrix6 K = total_stiffness(mats, k4);
        const Vector6 b = gap_direction();

        // a small, random-looking state
        Eigen::VectorXd z = model.equilibrium();
        const double qs[6] = {0.31e-7, -0.72e-7, 1.13e-7, -0.58e-7, 0.44e-7, -0.21e-7};
        const double vs[6] = {-0.2e-4, 0.5e-4, 2.1e-4, -1.7e-4, 0.3e-4, 0.9e-4};
        for (int i = 0; i < 6; ++i) {
            z(i) = qs[i];
            z(6 + i) = vs[i];
        }
        z(CoupledModel::film_index) *= 1.013;
        if (model.back_tension_index() >= 0) z(model.back_tension_index()) += 0.17e6;
        if (model.front_tension_index() >= 0) z(model.front_tension_index()) -= 0.11e6;

        Eigen::VectorXd f(model.size());
        REQUIRE(model.rhs(0.0, z.data(), f.data()) == DynamicsStatus::ok);

        // the bite for this state, built by hand (docs/model.md §5: y2 = y2_ref + g, dyc/dt = g')
        BiteState state;
        state.exit_thickness = ref.exit_thickness + (z(2) - z(3));
        state.gap_rate = z(8) - z(9);
        state.inlet_film = z(CoupledModel::film_index);
        state.back_tension = model.back_tension_index() >= 0 ? z(model.back_tension_index())
                                                             : s.tensions.back.stress;
        state.front_tension = model.front_tension_index() >= 0 ? z(model.front_tension_index())
                                                               : s.tensions.front.stress;
        const BiteResult bite = solve_roll_bite(s, state, {false});
        REQUIRE(bite.status == BiteStatus::ok);

        const Vector6 q = z.head<6>(), qdot = z.segment<6>(6);
        const double g = q(2) - q(3);
        const double dP = bite.force - ref.bite.force + k4 * g;
        const Vector6 qddot = mats.mass.inverse() * (b * dP - mats.damping * qdot - K * q);
        for (int i = 0; i < 6; ++i) {
            CAPTURE(i);
            CHECK(f(i) == qdot(i));
            // to the bite's repeatability: 1e-9 of the rolling force on mass i
            CHECK(std::abs(f(6 + i) - qddot(i)) <=
                  1e-9 * ref.bite.force / s.structure.mass[static_cast<std::size_t>(i)]);
        }
        // the same state seen through the bite_state mapping
        const BiteState mapped = model.bite_state(0.0, z.data());
        CHECK(mapped.exit_thickness == state.exit_thickness);
        CHECK(mapped.gap_rate == state.gap_rate);
        CHECK(mapped.inlet_film == state.inlet_film);
        CHECK(mapped.back_tension == state.back_tension);
        CHECK(mapped.front_tension == state.front_tension);

        // k4 cancels: a model built with any other k4 has the same right-hand side
        ReferenceState other = ref;
        other.strip_stiffness = 3.7 * k4;
        const CoupledModel model2(s, other);
        Eigen::VectorXd f2(model.size());
        REQUIRE(model2.rhs(0.0, z.data(), f2.data()) == DynamicsStatus::ok);
        CHECK((f2 - f).cwiseAbs().maxCoeff() <= 1e-12 * f.cwiseAbs().maxCoeff());

        // the film and tension rows from the same hand-built bite
        InletFilmInputs in;
        in.inlet_film = state.inlet_film;
        in.inlet_angle = bite.inlet_angle;
        in.gap_rate = state.gap_rate;
        in.inlet_angle_rate = -state.gap_rate / (2.0 * s.rolls.radius * bite.inlet_angle);
        in.mean_inlet_speed = 0.5 * (bite.entry_speed + s.rolls.speed);
        in.roll_radius = s.rolls.radius;
        in.viscosity = s.lubricant.viscosity;
        in.pressure_viscosity = s.lubricant.pressure_viscosity;
        in.flow_stress = s.strip.flow_stress;
        in.back_tension = state.back_tension;
        const double film_rate = inlet_film_rate(s.inlet_film, in);
        CHECK(std::abs(f(CoupledModel::film_index) - film_rate) <=
              1e-9 * in.inlet_angle * in.mean_inlet_speed);
        if (model.back_tension_index() >= 0) {
            const double expected = s.strip.youngs_modulus / s.tensions.back.span_length *
                                    (bite.entry_speed - ref.bite.entry_speed);
            CHECK(std::abs(f(model.back_tension_index()) - expected) <=
                  1e-9 * s.strip.youngs_modulus / s.tensions.back.span_length * s.rolls.speed);
        }
        if (model.front_tension_index() >= 0) {
            const double expected = s.strip.youngs_modulus / s.tensions.front.span_length *
                                    (ref.bite.exit_speed - bite.exit_speed);
            CHECK(std::abs(f(model.front_tension_index()) - expected) <=
                  1e-9 * s.strip.youngs_modulus / s.tensions.front.span_length * s.rolls.speed);
        }
    }
}

TEST_CASE("coupled model: state size and indices follow the tension modes") {
    struct Case {
        TensionMode back, front;
        int size, back_index, front_index;
    };
    const Case cases[] = {
        {TensionMode::span, TensionMode::constant, 14, 13, -1},
        {TensionMode::span, TensionMode::span, 15, 13, 14},
        {TensionMode::constant, TensionMode::constant, 13, -1, -1},
        {TensionMode::constant, TensionMode::span, 14, -1, 13},
        {TensionMode::sinusoid, TensionMode::constant, 13, -1, -1},
    };
    for (const Case& c : cases) {
        Scenario s;
        s.tensions.back.mode = c.back;
        s.tensions.front.mode = c.front;
        s.tensions.front.stress = 4e6;
        const ReferenceState ref = reference_state(s, false);
        REQUIRE(ref.status == BiteStatus::ok);
        const CoupledModel model(s, ref);
        CHECK(model.size() == c.size);
        CHECK(model.back_tension_index() == c.back_index);
        CHECK(model.front_tension_index() == c.front_index);
        CHECK(CoupledModel::film_index == 12);
        const Eigen::VectorXd z0 = model.equilibrium();
        REQUIRE(z0.size() == c.size);
        CHECK(z0.head<12>().isZero(0.0));
        CHECK(z0(12) == ref.bite.inlet_film);
        if (c.back_index >= 0) CHECK(z0(c.back_index) == s.tensions.back.stress);
        if (c.front_index >= 0) CHECK(z0(c.front_index) == s.tensions.front.stress);
    }
    // the default scenario: back span, constant front
    const Scenario s;
    const CoupledModel model(s, reference_state(s, false));
    CHECK(model.size() == 14);
    CHECK(model.back_tension_index() == 13);
}

TEST_CASE("coupled model: a slack strip or an opened gap is a status, never a crash") {
    Scenario s;
    s.tensions.front.mode = TensionMode::span;
    s.tensions.front.stress = 3e6;
    const ReferenceState ref = reference_state(s);
    REQUIRE(ref.status == BiteStatus::ok);
    const CoupledModel model(s, ref);
    const Eigen::VectorXd z0 = model.equilibrium();
    Eigen::VectorXd f(model.size());

    for (double sb : {0.0, -1e6}) {
        Eigen::VectorXd z = z0;
        z(model.back_tension_index()) = sb;
        CHECK(model.rhs(0.0, z.data(), f.data()) == DynamicsStatus::slack_strip);
    }
    {
        Eigen::VectorXd z = z0;
        z(model.front_tension_index()) = -1e5;
        CHECK(model.rhs(0.0, z.data(), f.data()) == DynamicsStatus::slack_strip);
    }
    // the gap opens beyond the entry thickness: g > y1 - y2_ref
    const double draft = s.strip.entry_thickness - ref.exit_thickness;
    for (double factor : {1.01, 1.5, 3.0}) {
        CAPTURE(factor);
        Eigen::VectorXd z = z0;
        z(2) = 0.6 * factor * draft;
        z(3) = -0.4 * factor * draft;
        CHECK(model.rhs(0.0, z.data(), f.data()) == DynamicsStatus::contact_lost);
    }
    // large but physical excursions return some status and finite rates when ok
    for (double factor : {-0.5, 0.5, 0.99}) {
        CAPTURE(factor);
        Eigen::VectorXd z = z0;
        z(2) = factor * draft;
        const DynamicsStatus status = model.rhs(0.0, z.data(), f.data());
        if (status == DynamicsStatus::ok) CHECK(f.allFinite());
    }
    // and the model still gives f(z0) = 0 afterwards
    REQUIRE(model.rhs(0.0, z0.data(), f.data()) == DynamicsStatus::ok);
    CHECK(std::abs(f(CoupledModel::film_index)) <= 1e-9 * ref.bite.inlet_angle * s.rolls.speed);
}

TEST_CASE("coupled model: the film models differ only in the squeeze / theta-dot terms") {
    // d(h0')/d(g'): the common part theta/2 du1/dg' (continuity moves u1 with the gap rate) plus
    //   paper:    -theta^2 h0 I2 d(theta')/dg' = theta h0 I2 / (2a)   (theta' = -g' / (2 a theta))
    //   eulerian: -1/2                                                 (uniform squeeze)
    Scenario paper;
    Scenario eulerian;
    eulerian.inlet_film = InletFilmModel::eulerian;
    const ReferenceState ref = reference_state(paper);
    REQUIRE(ref.status == BiteStatus::ok);
    const CoupledModel mp(paper, ref), me(eulerian, ref);
    const Linearisation jp = linearise(mp, mp.equilibrium());
    const Linearisation je = linearise(me, me.equilibrium());
    REQUIRE(jp.status == DynamicsStatus::ok);
    REQUIRE(je.status == DynamicsStatus::ok);

    const double a = paper.rolls.radius, theta = ref.bite.inlet_angle, h0 = ref.bite.inlet_film;
    const double I2 = inlet_integral_I2(a, theta, h0);
    const double paper_term = theta * h0 * I2 / (2.0 * a);
    MESSAGE("I2 = " << I2 << ", theta h0 I2 / (2a) = " << paper_term);
    CHECK(I2 > 8.0e4);  // docs/model.md §2: I2 ~ 8.77e4 at the defaults
    CHECK(I2 < 9.5e4);

    // the common part from independent bite solves at another step
    const double d = 4e-4;
    BiteState lo = mp.bite_state(0.0, mp.equilibrium().data()), hi = lo;
    lo.gap_rate = -d;
    hi.gap_rate = +d;
    const BiteResult bl = solve_roll_bite(paper, lo, {false}),
                     bh = solve_roll_bite(paper, hi, {false});
    REQUIRE(bl.status == BiteStatus::ok);
    REQUIRE(bh.status == BiteStatus::ok);
    const double common = 0.5 * theta * (bh.entry_speed - bl.entry_speed) / (2.0 * d);
    MESSAGE("d(h0')/dg': paper " << jp.jacobian(12, 8) << ", eulerian " << je.jacobian(12, 8)
                                 << ", common part " << common);

    const int q3dot = 8, q4dot = 9;
    CHECK(jp.jacobian(12, q3dot) == rollgap::test::approx(common + paper_term).epsilon(1e-6));
    CHECK(je.jacobian(12, q3dot) == rollgap::test::approx(common - 0.5).epsilon(1e-6));
    CHECK(jp.jacobian(12, q4dot) == rollgap::test::approx(-(common + paper_term)).epsilon(1e-6));
    CHECK(je.jacobian(12, q4dot) == rollgap::test::approx(-(common - 0.5)).epsilon(1e-6));
    // the difference alone: the same bites enter both, so only the closed-form terms remain
    CHECK(std::abs((je.jacobian(12, q3dot) - jp.jacobian(12, q3dot)) - (-0.5 - paper_term)) < 1e-9);

    // docs/model.md §2: the eulerian squeeze term is a negative damping of order
    // |dP/dh0| h0 / (2 theta u1bar) ~ 1.8 MN s/m at the defaults (dP/dh0 by an independent
    // difference)
    BiteState flo = mp.bite_state(0.0, mp.equilibrium().data()), fhi = flo;
    flo.inlet_film *= 1.0 - 3e-6;
    fhi.inlet_film *= 1.0 + 3e-6;
    const double dP_dh0 =
        (solve_roll_bite(paper, fhi, {false}).force - solve_roll_bite(paper, flo, {false}).force) /
        (fhi.inlet_film - flo.inlet_film);
    const double u1bar = 0.5 * (ref.bite.entry_speed + paper.rolls.speed);
    const double squeeze_damping = std::abs(dP_dh0) * h0 / (2.0 * theta * u1bar);
    MESSAGE("dP/dh0 = " << dP_dh0 << " N/m; |dP/dh0| h0 / (2 theta u1bar) = " << squeeze_damping
                        << " N s/m");
    CHECK(dP_dh0 < 0.0);  // a thicker film lowers the asperity friction and the force
    CHECK(squeeze_damping ==
          rollgap::test::approx(1.8e6).epsilon(0.05 / 1.8));  // "1.8 MN s/m", to its two digits

    // every other entry of the h0 row, and every other row, is the same for both models
    const double row_scale = jp.jacobian.row(12).cwiseAbs().maxCoeff();
    for (int j = 0; j < mp.size(); ++j) {
        if (j == q3dot || j == q4dot) continue;
        CAPTURE(j);
        CHECK(std::abs(jp.jacobian(12, j) - je.jacobian(12, j)) <= 1e-9 * row_scale);
    }
    for (int i = 0; i < mp.size(); ++i) {
        if (i == 12) continue;
        CAPTURE(i);
        const double scale = std::max(1e-300, jp.jacobian.row(i).cwiseAbs().maxCoeff());
        CHECK((jp.jacobian.row(i) - je.jacobian.row(i)).cwiseAbs().maxCoeff() <= 1e-9 * scale);
    }
}

TEST_CASE(
    "coupled model: with the structure still, h0 relaxes to Wilson-Walowit at the rate of eq. (11)") {
    // Structure held still by huge masses, constant tension, h0(0) = 2 h00, CVODE. CVODE's error
    // on h0 is set by the model document's absolute tolerance 1e-12 m (h0 ~ 3.4e-6 m, so the
    // relative tolerance does not bind): the trajectories are compared to 30 x that tolerance, a
    // global error budget for ~50-200 steps. (Observed: 1.5e-11 m, the same for rtol 1e-8 ...
    // 1e-11.)
    const double huge = 1e30;
    const double h0_tolerance = 30 * 1e-12;
    IntegrationOptions options;
    options.relative_tolerance = 1e-9;

    SUBCASE("coulomb friction: u1 does not depend on h0, so the decay is exactly exponential") {
        // h0' = theta u1bar - r h0 with u1bar constant: h0(t) = h00 (1 + e^{-r t})
        Scenario s;
        s.friction.model = FrictionModel::coulomb;
        s.tensions.back.mode = TensionMode::constant;
        s.structure.mass = {huge, huge, huge, huge, huge, huge};
        const ReferenceState ref = reference_state(s, false);
        REQUIRE(ref.status == BiteStatus::ok);
        const CoupledModel model(s, ref);
        const double h00 = ref.bite.inlet_film, r = relaxation_rate(s);
        MESSAGE("relaxation rate theta^2 F / (6 gamma eta0) = " << r << " 1/s, h00 = " << h00);
        Eigen::VectorXd z = model.equilibrium();
        z(CoupledModel::film_index) = 2.0 * h00;
        std::vector<double> times;
        for (int k = 1; k <= 40; ++k) times.push_back(k * 0.5e-6);  // 20 us ~ 3 time constants
        double worst = 0.0, at5 = 0.0, at15 = 0.0;
        const IntegrationResult run = integrate(
            model, z, 0.0, times,
            [&](const Sample& smp) {
                const double h0 = smp.z(CoupledModel::film_index);
                worst = std::max(worst, std::abs(h0 - h00 * (1.0 + std::exp(-r * smp.t))));
                if (std::abs(smp.t - 5e-6) < 1e-12) at5 = h0 - h00;
                if (std::abs(smp.t - 15e-6) < 1e-12) at15 = h0 - h00;
            },
            options);
        REQUIRE(run.status == DynamicsStatus::ok);
        MESSAGE("coulomb: max |h0 - h00 (1 + e^{-rt})| = "
                << worst << " m (" << worst / h00 << " of h00), " << run.steps << " steps");
        CHECK(worst < h0_tolerance);
        REQUIRE(at5 > 0.0);
        REQUIRE(at15 > 0.0);
        const double measured = std::log(at5 / at15) / 10e-6;
        MESSAGE("coulomb: decay rate " << measured << " 1/s");
        CHECK(measured == rollgap::test::approx(r).epsilon(2e-4));
    }

    SUBCASE("mixed friction: the decay rate is eq. (11)'s plus the feedback of h0 on u1") {
        Scenario s;
        s.tensions.back.mode = TensionMode::constant;
        s.structure.mass = {huge, huge, huge, huge, huge, huge};
        const ReferenceState ref = reference_state(s, false);
        REQUIRE(ref.status == BiteStatus::ok);
        const CoupledModel model(s, ref);
        const double h00 = ref.bite.inlet_film, r = relaxation_rate(s);
        const double theta = ref.bite.inlet_angle, v = s.rolls.speed;

        // an independent scalar reference: h0' = theta (u1(h0) + v) / 2 - r h0, with u1(h0) from
        // the bite at the fixed film h0, integrated by classical RK4 (r dt = 0.02)
        const BiteState base = steady_bite_state(s);
        auto scalar_rate = [&](double h0) {
            BiteState st = base;
            st.inlet_film = h0;
            const BiteResult b = solve_roll_bite(s, st, {false});
            REQUIRE(b.status == BiteStatus::ok);
            return theta * 0.5 * (b.entry_speed + v) - r * h0;
        };
        const double dt = 0.125e-6;
        std::vector<double> times, reference;
        double h = 2.0 * h00;
        for (int k = 1; k <= 480; ++k) {  // 60 us
            const double k1 = scalar_rate(h), k2 = scalar_rate(h + 0.5 * dt * k1),
                         k3 = scalar_rate(h + 0.5 * dt * k2), k4 = scalar_rate(h + dt * k3);
            h += dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0;
            if (k % 8 == 0) {
                times.push_back(k * dt);
                reference.push_back(h);
            }
        }
        const std::size_t compared = times.size();
        times.push_back(200e-6);  // ~30 time constants: settled
        Eigen::VectorXd z = model.equilibrium();
        z(CoupledModel::film_index) = 2.0 * h00;
        std::vector<double> h0s;
        const IntegrationResult run = integrate(
            model, z, 0.0, times,
            [&](const Sample& smp) { h0s.push_back(smp.z(CoupledModel::film_index)); }, options);
        REQUIRE(run.status == DynamicsStatus::ok);
        REQUIRE(h0s.size() == times.size());
        double worst = 0.0;
        for (std::size_t i = 0; i < compared; ++i)
            worst = std::max(worst, std::abs(h0s[i] - reference[i]));
        MESSAGE("mixed: max |h0_cvode - h0_rk4| = " << worst << " m (" << worst / h00
                                                    << " of h00)");
        CHECK(worst < h0_tolerance);
        // it ends at the Wilson-Walowit film
        CHECK(std::abs(h0s.back() - h00) < h0_tolerance);
        // the structure did not move
        CHECK(z.head<12>().cwiseAbs().maxCoeff() < 1e-15);

        // late decay rate = r - theta/2 du1/dh0 (the feedback by independent bite solves); measured
        // on the RK4 reference between 40 and 60 us, where h0 - h00 ~ 1e-3 h00 (linear regime)
        const double eps = 1e-4 * h00;
        BiteState lo = base, hi = base;
        lo.inlet_film = h00 - eps;
        hi.inlet_film = h00 + eps;
        const double du1 = (solve_roll_bite(s, hi, {false}).entry_speed -
                            solve_roll_bite(s, lo, {false}).entry_speed) /
                           (2.0 * eps);
        const double expected_rate = r - 0.5 * theta * du1;
        const double measured =
            std::log((reference[compared - 21] - h00) / (reference[compared - 1] - h00)) / 20e-6;
        REQUIRE(std::abs(times[compared - 21] - 40e-6) < 1e-12);
        MESSAGE("decay rate: measured " << measured << " 1/s, eq. (11) alone " << r
                                        << ", with the u1 feedback " << expected_rate
                                        << " (du1/dh0 = " << du1 << " 1/s)");
        CHECK(measured == rollgap::test::approx(expected_rate).epsilon(1e-3));
        // and the Jacobian's film entry is the same rate
        const Linearisation lin = linearise(model, model.equilibrium());
        REQUIRE(lin.status == DynamicsStatus::ok);
        CHECK(-lin.jacobian(12, 12) == rollgap::test::approx(expected_rate).epsilon(1e-4));
    }
}
