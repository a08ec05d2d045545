// The bite linearisation J_b and the Jacobian assembled from it (docs/model.md §6.1), checked
// against independent references: J_b by both methods (forward sensitivities, the one the
// dynamics use, and central differences) against forward and backward differences at another step
// (the derivative lies between them) and against identities of the bite (theta = sqrt((y1 -
// y2)/a), the mass flow u2 y2 = u1 y1 - x_w dyc/dt, the total stiffness k4 of reference_state()
// through the steady film); the assembled state Jacobian against central differences of the whole
// right-hand side (finite_difference_jacobian), element by element, and the eigenvalues and
// critical speeds of the two.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "core/bite_jacobian.h"
#include "core/coupled_model.h"
#include "core/roll_bite.h"
#include "core/stability.h"

#include "support/compare.h"
#include "support/dynamics_scenarios.h"
#include "support/approx.h"

namespace bite_jacobian_test {

using namespace rollgap::core;
using rollgap::test::rel;

using Named = rollgap::test::NamedScenario;

// A model as the analyses build it (docs/model.md §7.3).
struct Built {
    Scenario s;
    ReferenceState ref;
    CoupledModel model;
    explicit Built(const Scenario& scenario, Excitation excitation = {})
        : s(dynamics_scenario(scenario)), ref(reference_state(s)), model(s, ref, excitation) {}
};

double output(const BiteResult& b, BiteOutput o) {
    switch (o) {
        case BiteOutput::force: return b.force;
        case BiteOutput::entry_speed: return b.entry_speed;
        case BiteOutput::exit_speed: return b.exit_speed;
        case BiteOutput::inlet_angle: return b.inlet_angle;
        case BiteOutput::torque: break;
    }
    return b.torque;
}

double& input(BiteState& st, BiteInput i) {
    switch (i) {
        case BiteInput::entry_thickness: return st.entry_thickness;
        case BiteInput::exit_thickness: return st.exit_thickness;
        case BiteInput::gap_rate: return st.gap_rate;
        case BiteInput::inlet_film: return st.inlet_film;
        case BiteInput::back_tension: return st.back_tension;
        case BiteInput::front_tension: break;
    }
    return st.front_tension;
}

BiteResult solved(const Scenario& s, const BiteState& st) {
    const BiteResult b = solve_roll_bite(s, st, {false});
    REQUIRE(b.status == BiteStatus::ok);
    return b;
}

// J_b at the bite state of z0 with the gap moving at `gap_rate` (m/s).
struct Linearised {
    BiteState at;
    BiteResult bite;
    BiteJacobian jb;
};
// J_b's two methods (core/bite_jacobian.h): forward sensitivities, central differences
enum class Method { sensitivities, differences };
const char* name_of(Method m) {
    return m == Method::sensitivities ? "sensitivities" : "central differences";
}
BiteJacobian jacobian_by(Method m, const Scenario& s, const BiteState& at, const BiteResult& bite,
                         unsigned columns = all_bite_columns) {
    return m == Method::sensitivities ? bite_jacobian(s, at, bite, columns)
                                      : bite_jacobian_differences(s, at, bite, columns);
}

Linearised linearised_at(const Built& d, const Eigen::VectorXd& z0, double gap_rate,
                         Method method) {
    Linearised out;
    out.at = d.model.bite_state(0.0, z0.data());
    out.at.gap_rate = gap_rate;
    out.bite = solved(d.s, out.at);
    out.jb = jacobian_by(method, d.s, out.at, out.bite);
    REQUIRE(out.jb.status == BiteStatus::ok);
    return out;
}

// The same model, seen only through its right-hand side: its jacobian() is the interface's
// default, central differences of rhs() (core/dynamic_model.h), the reference the assembled
// Jacobian replaced.
class FiniteDifferenceView final : public DynamicModel {
public:
    explicit FiniteDifferenceView(const CoupledModel& m) : m_(&m) {}
    int size() const override { return m_->size(); }
    Eigen::VectorXd equilibrium() const override { return m_->equilibrium(); }
    DynamicsStatus rhs(double t, const double* z, double* zdot) const override {
        return m_->rhs(t, z, zdot);
    }
    double perturbation(int i, const Eigen::VectorXd& z) const override {
        return m_->perturbation(i, z);
    }
    double absolute_tolerance(int i) const override { return m_->absolute_tolerance(i); }
    int margin_count() const override { return m_->margin_count(); }
    void limit_margins(double t, const double* z, double* margins) const override {
        m_->limit_margins(t, z, margins);
    }
    DynamicsStatus margin_status(int i) const override { return m_->margin_status(i); }
    int stand_count() const override { return m_->stand_count(); }
    int displacement_index(int i) const override { return m_->displacement_index(i); }

private:
    const CoupledModel* m_;
};

// The stability at one speed as critical_speed() computes it (core/stability.cpp), with the
// assembled or the finite-difference Jacobian.
SpeedStability stability_with(const Scenario& base, double speed, bool with_k4, bool assembled) {
    Scenario at = base;
    at.rolls.speed = speed;
    const Scenario s = dynamics_scenario(at);
    const ReferenceState ref = reference_state(s, with_k4);
    SpeedStability out;
    out.speed = speed;
    out.steady_status = ref.status;
    if (ref.status != BiteStatus::ok) return out;
    const CoupledModel model(s, ref);
    out = assembled ? linear_stability(model) : linear_stability(FiniteDifferenceView(model));
    out.speed = speed;
    out.steady_status = ref.status;
    out.strip_stiffness = ref.strip_stiffness;
    out.force = ref.bite.force;
    return out;
}

// The largest |A - B| of a Jacobian entry relative to the FD noise scale of its entry: a
// column's difference quotient is (change of f_i) / (2 delta_j), and f_i is known to a fraction
// of the largest change any column makes in it, max_k |J_ik| delta_k. So the scale of entry (i,
// j) is max(|J_ij|, max_k |J_ik| delta_k / delta_j).
double worst_relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                                 const DynamicModel& model, const Eigen::VectorXd& z,
                                 int* worst_row = nullptr, int* worst_col = nullptr) {
    const int n = model.size();
    Eigen::VectorXd delta(n);
    for (int j = 0; j < n; ++j) delta(j) = model.perturbation(j, z);
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
        double change = 0.0;
        for (int k = 0; k < n; ++k) change = std::max(change, std::abs(b(i, k)) * delta(k));
        for (int j = 0; j < n; ++j) {
            const double scale = std::max(std::abs(b(i, j)), change / delta(j));
            if (scale == 0.0) {
                CHECK(a(i, j) == 0.0);
                continue;
            }
            const double d = std::abs(a(i, j) - b(i, j)) / scale;
            if (d > worst) {
                worst = d;
                if (worst_row) *worst_row = i;
                if (worst_col) *worst_col = j;
            }
        }
    }
    return worst;
}

// The test cases stay in the namespace: the suite is compiled in unity batches, and a
// using-directive at file scope would carry these names into the files after this one.

TEST_CASE("bite Jacobian: each column lies between the forward and backward differences") {
    // At the default dynamic bite (film h00 held) and at a bite with a moving gap: by the mean
    // value theorem the forward and backward differences at 3 delta are the derivative at points
    // on either side, so a derivative that is monotone over the interval lies between them; and
    // their mean, the central difference at 3 delta, agrees with J_b's to O(delta^2).
    const Built d(Scenario{});
    REQUIRE(d.ref.status == BiteStatus::ok);
    const Eigen::VectorXd z0 = d.model.equilibrium();
    for (const Method method : {Method::sensitivities, Method::differences})
        for (const double gap_rate : {0.0, 2e-3}) {
            const std::string method_name = name_of(method);
            CAPTURE(method_name);
            CAPTURE(gap_rate);
            const Linearised lin = linearised_at(d, z0, gap_rate, method);
            const BiteState& at = lin.at;
            const BiteResult& bite = lin.bite;
            const BiteJacobian& jb = lin.jb;
            CHECK(jb.columns == all_bite_columns);
            // no bite solve for the sensitivities (one dual pass), two a column for the differences
            CHECK(jb.bite_solves == (method == Method::sensitivities ? 0 : 2 * bite_input_count));
            CHECK(jb.kernel_passes == (method == Method::sensitivities ? 1 : 0));
            const BiteSteps steps;
            double worst_apart = 0.0;
            for (int j = 0; j < bite_input_count; ++j) {
                const auto in = static_cast<BiteInput>(j);
                const double delta = 3.0 * steps.step(in, at);
                BiteState lo = at, hi = at;
                input(lo, in) -= delta;
                input(hi, in) += delta;
                const BiteResult a = solved(d.s, lo), b = solved(d.s, hi);
                for (int i = 0; i < bite_output_count; ++i) {
                    const auto o = static_cast<BiteOutput>(i);
                    CAPTURE(j);
                    CAPTURE(i);
                    const double forward = (output(b, o) - output(bite, o)) / delta;
                    const double backward = (output(bite, o) - output(a, o)) / delta;
                    const double central = 0.5 * (forward + backward);
                    const double value = jb(o, in);
                    // the outputs are solved to ~1e-12 of themselves (the neutral point to 1e-14 of
                    // x_w): noise of a difference quotient ~ 1e-12 |output| / delta
                    const double noise = 1e-11 * std::abs(output(bite, o)) / delta;
                    CHECK(value >= std::min(forward, backward) - noise);
                    CHECK(value <= std::max(forward, backward) + noise);
                    // the central differences at delta and 3 delta differ by (9 - 1) delta^2 f''' /
                    // 6, of order (3 delta / L)^2 of the entry for an input whose scale is L (y1 -
                    // y2 = 0.24 mm for the thicknesses: ~1e-6; the square root theta(y2) gives
                    // exactly delta^2 / (y1 - y2)^2 = 1.7e-7, the largest seen)
                    const double apart = std::abs(value - central);
                    CHECK(apart <= 1e-6 * std::abs(central) + noise);
                    worst_apart = std::max(worst_apart, apart / std::max(std::abs(central), noise));
                }
            }
            MESSAGE(name_of(method) << ", gap rate " << gap_rate
                                    << " m/s: J_b and the central differences at 3 delta "
                                    << "differ by at most " << worst_apart << " of an entry");
        }
}

TEST_CASE("bite Jacobian: identities of the bite") {
    const Built d(Scenario{});
    REQUIRE(d.ref.status == BiteStatus::ok);
    const Eigen::VectorXd z0 = d.model.equilibrium();
    const double y1 = d.s.strip.entry_thickness;

    for (const Method method : {Method::sensitivities, Method::differences})
        for (const double gap_rate : {0.0, 2e-3, -2e-3}) {
            const std::string method_name = name_of(method);
            CAPTURE(method_name);
            CAPTURE(gap_rate);
            const Linearised lin = linearised_at(d, z0, gap_rate, method);
            const BiteState& at = lin.at;
            const BiteResult& bite = lin.bite;
            const BiteJacobian& jb = lin.jb;
            const double a = bite.roll_radius, theta = bite.inlet_angle, y2 = at.exit_thickness;
            const double xw = bite.contact_length, u1 = bite.entry_speed, u2 = bite.exit_speed;

            // theta = sqrt((y1 - y2) / a) (§1): d theta/d y2 = -1/(2 a theta) = -d theta/d y1, and
            // nothing else moves it. The sensitivities give the derivative itself (to rounding);
            // the central difference of a square root at half-step delta is the derivative times 1
            // + delta^2 / (8 (y1 - y2)^2) + O(delta^4) (2e-8 here), what is left is rounding (theta
            // to 1e-16 over a difference of 4e-4 of it: ~1e-12)
            const double delta = BiteSteps{}.exit_thickness, draft = y1 - y2;
            const double truncation =
                method == Method::sensitivities ? 1.0 : 1.0 + delta * delta / (8.0 * draft * draft);
            CHECK(jb(BiteOutput::inlet_angle, BiteInput::exit_thickness) ==
                  rollgap::test::approx(-truncation / (2.0 * a * theta)).epsilon(1e-10));
            CHECK(jb(BiteOutput::inlet_angle, BiteInput::entry_thickness) ==
                  rollgap::test::approx(truncation / (2.0 * a * theta)).epsilon(1e-10));
            for (const BiteInput in : {BiteInput::gap_rate, BiteInput::inlet_film,
                                       BiteInput::back_tension, BiteInput::front_tension})
                CHECK(jb(BiteOutput::inlet_angle, in) == 0.0);

            // mass flow (§1), u2 y2 = u1 y1 - x_w dyc/dt, x_w = sqrt(a (y1 - y2)), differentiated
            // in each input; checked relative to the size of its terms
            const double dxw_dy2 = -a / (2.0 * xw), dxw_dy1 = a / (2.0 * xw);
            auto du = [&](BiteOutput o, BiteInput in) { return jb(o, in); };
            struct Flow {
                const char* name;
                double lhs, rhs, scale;
            };
            const Flow flows[] = {
                {"y1", y2 * du(BiteOutput::exit_speed, BiteInput::entry_thickness),
                 u1 + y1 * du(BiteOutput::entry_speed, BiteInput::entry_thickness) -
                     gap_rate * dxw_dy1,
                 u1},
                {"y2", y2 * du(BiteOutput::exit_speed, BiteInput::exit_thickness) + u2,
                 y1 * du(BiteOutput::entry_speed, BiteInput::exit_thickness) - gap_rate * dxw_dy2,
                 u2},
                {"gap rate", y2 * du(BiteOutput::exit_speed, BiteInput::gap_rate),
                 y1 * du(BiteOutput::entry_speed, BiteInput::gap_rate) - xw, xw},
                {"h0", y2 * du(BiteOutput::exit_speed, BiteInput::inlet_film),
                 y1 * du(BiteOutput::entry_speed, BiteInput::inlet_film),
                 y1 * std::abs(du(BiteOutput::entry_speed, BiteInput::inlet_film))},
                {"s_b", y2 * du(BiteOutput::exit_speed, BiteInput::back_tension),
                 y1 * du(BiteOutput::entry_speed, BiteInput::back_tension),
                 y1 * std::abs(du(BiteOutput::entry_speed, BiteInput::back_tension))},
                {"s_f", y2 * du(BiteOutput::exit_speed, BiteInput::front_tension),
                 y1 * du(BiteOutput::entry_speed, BiteInput::front_tension),
                 y1 * std::abs(du(BiteOutput::entry_speed, BiteInput::front_tension))},
            };
            for (const Flow& f : flows) {
                CAPTURE(f.name);
                CHECK(std::abs(f.lhs - f.rhs) <= 1e-7 * f.scale);
            }
        }

    SUBCASE("the film-held stiffness and the steady film's give k4 of reference_state()") {
        // k4 = -dP/dy2 with the film at its steady value h00(y2) (§5) is the total derivative
        // dF/dy2 = dF/dy2|h0 + dF/dh0 dh00/dy2, with dh00/dy2 from two steady bites
        const BiteState at = d.model.bite_state(0.0, z0.data());
        const BiteJacobian jb = bite_jacobian(d.s, at, d.ref.bite);
        REQUIRE(jb.status == BiteStatus::ok);
        BiteState lo = steady_bite_state(d.s), hi = lo;
        const double step = 2e-7;
        lo.exit_thickness -= step;
        hi.exit_thickness += step;
        const double dh00_dy2 =
            (solved(d.s, hi).inlet_film - solved(d.s, lo).inlet_film) / (2.0 * step);
        const double total = jb(BiteOutput::force, BiteInput::exit_thickness) +
                             jb(BiteOutput::force, BiteInput::inlet_film) * dh00_dy2;
        MESSAGE("dF/dy2 at h0 held "
                << jb(BiteOutput::force, BiteInput::exit_thickness) << " N/m, through the film "
                << jb(BiteOutput::force, BiteInput::inlet_film) * dh00_dy2 << " N/m, k4 "
                << d.ref.strip_stiffness << " N/m");
        CHECK(-total == rollgap::test::approx(d.ref.strip_stiffness).epsilon(1e-6));

        // and J_b at the steady-film bite (h0 <= 0: h00 inside the solve) is k4 itself: by the
        // differences (the same step as reference_state(), 1e-7 m) to the noise of the solves;
        // by the sensitivities to the truncation of that central difference, O((delta /
        // (y1 - y2))^2) ~ 1e-7 of it (the first test case measures 2e-7 at 3 delta)
        const BiteJacobian steady_fd = bite_jacobian_differences(
            d.s, steady_bite_state(d.s), d.ref.bite, bite_column(BiteInput::exit_thickness));
        REQUIRE(steady_fd.status == BiteStatus::ok);
        CHECK(steady_fd.bite_solves == 2);
        CHECK(-steady_fd(BiteOutput::force, BiteInput::exit_thickness) ==
              rollgap::test::approx(d.ref.strip_stiffness).epsilon(1e-9));
        const BiteJacobian steady = bite_jacobian(d.s, steady_bite_state(d.s), d.ref.bite,
                                                  bite_column(BiteInput::exit_thickness));
        REQUIRE(steady.status == BiteStatus::ok);
        const double k4 = -steady(BiteOutput::force, BiteInput::exit_thickness);
        MESSAGE("k4 by sensitivities " << k4 << " N/m, by the differences of reference_state() "
                                       << d.ref.strip_stiffness << " N/m (relative "
                                       << rel(k4, d.ref.strip_stiffness) << ")");
        CHECK(k4 == rollgap::test::approx(d.ref.strip_stiffness).epsilon(1e-6));
        // the film column needs a given film
        const BiteJacobian no_film = bite_jacobian(d.s, steady_bite_state(d.s), d.ref.bite);
        CHECK(no_film.status != BiteStatus::ok);
    }
}

TEST_CASE("bite Jacobian: at the edge of the rolling states") {
    // A gap closing fast enough has no rolling state (§1: the strip would move backwards, or the
    // bite skids). Bisect the gap rate where the default bite stops solving, and linearise just
    // inside: the bite solves, the one a gap-rate step (1e-3 m/s) closer does not.
    const Built d(Scenario{});
    REQUIRE(d.ref.status == BiteStatus::ok);
    const Eigen::VectorXd z0 = d.model.equilibrium();
    const BiteState base = d.model.bite_state(0.0, z0.data());
    auto at_rate = [&](double rate) {
        BiteState st = base;
        st.gap_rate = rate;
        return st;
    };
    double ok = 0.0, failing = -50.0;
    REQUIRE(solve_roll_bite(d.s, at_rate(failing), {false}).status != BiteStatus::ok);
    while (ok - failing > 1e-5) {
        const double mid = 0.5 * (ok + failing);
        (solve_roll_bite(d.s, at_rate(mid), {false}).status == BiteStatus::ok ? ok : failing) = mid;
    }
    const BiteState edge = at_rate(ok);
    const BiteResult bite = solved(d.s, edge);
    const BiteStatus beyond = solve_roll_bite(d.s, at_rate(ok - 1e-3), {false}).status;
    MESSAGE("the default bite stops solving at a gap rate of "
            << failing << " m/s: " << std::string(to_string(beyond)));
    REQUIRE(beyond != BiteStatus::ok);
    // The differences report the failure (the y2 step moves that edge too, by ~1e-3 m/s:
    // whichever column fails first names it). The sensitivities visit no other state: the bite
    // solves here, so it has a derivative, and they give it; it agrees with the one-sided
    // (inward) differences at the gap-rate step, to that step's truncation.
    const BiteJacobian fd = bite_jacobian_differences(d.s, edge, bite);
    CHECK(fd.status != BiteStatus::ok);
    CHECK(std::string(fd.message).find("does not solve") != std::string::npos);
    const BiteJacobian jb = bite_jacobian(d.s, edge, bite);
    REQUIRE(jb.status == BiteStatus::ok);
    {
        const double h = 1e-3;
        const BiteResult inward = solved(d.s, at_rate(ok + h));
        for (int i = 0; i < bite_output_count; ++i) {
            const auto o = static_cast<BiteOutput>(i);
            CAPTURE(i);
            const double one_sided = (output(inward, o) - output(bite, o)) / h;
            const double scale =
                std::max(std::abs(one_sided), 1e-12 * std::abs(output(bite, o)) / h);
            MESSAGE("output " << i << ": sensitivity " << jb(o, BiteInput::gap_rate)
                              << ", one-sided difference " << one_sided);
            CHECK(std::abs(jb(o, BiteInput::gap_rate) - one_sided) <= 0.05 * scale);
        }
    }

    // the state Jacobian there: the differences of the right-hand side fail, the assembled one
    // (from the sensitivities) is the derivative of a bite that solves
    Eigen::VectorXd z = z0;
    z(8) = ok;  // the gap rate is q3' - q4'
    const Linearisation a = d.model.jacobian(z, 0.0);
    const Linearisation f = finite_difference_jacobian(d.model, z, 0.0);
    CHECK(f.status != DynamicsStatus::ok);
    CHECK(a.status == DynamicsStatus::ok);

    // and a bite that is not solved is not linearised
    BiteResult failed;
    failed.status = BiteStatus::skidding;
    CHECK(bite_jacobian(d.s, base, failed).status == BiteStatus::skidding);
}

TEST_CASE("assembled Jacobian: equal to central differences of the right-hand side") {
    for (const Named& v : rollgap::test::dynamics_scenarios(/*more=*/true)) {
        CAPTURE(v.name);
        const Built d(v.s);
        REQUIRE(d.ref.status == BiteStatus::ok);
        const Eigen::VectorXd z0 = d.model.equilibrium();
        const long before = d.model.bite_solves();
        const Linearisation assembled = d.model.jacobian(z0, 0.0);
        const long solves = d.model.bite_solves() - before;
        const Linearisation fd = finite_difference_jacobian(d.model, z0, 0.0);
        REQUIRE(assembled.status == DynamicsStatus::ok);
        REQUIRE(fd.status == DynamicsStatus::ok);
        REQUIRE(assembled.jacobian.rows() == d.model.size());
        REQUIRE(assembled.jacobian.cols() == d.model.size());
        // no bite solve beyond the reference one (the memo): J_b by sensitivities
        CHECK(solves == 0);
        int row = -1, col = -1;
        const double worst =
            worst_relative_difference(assembled.jacobian, fd.jacobian, d.model, z0, &row, &col);
        MESSAGE(v.name << ": worst |J_assembled - J_fd| / FD scale = " << worst << " at (" << row
                       << ", " << col << "); " << solves << " bite solves");
        CHECK(worst <= 1e-6);

        // the same at a state away from z0, with the gap moving (theta' != 0) and the film off
        // its steady value, and at a time where an excitation shifts the back tension
        Eigen::VectorXd z = z0;
        z(2) += 2e-7;
        z(8) += 3e-3;
        z(9) -= 1e-3;
        z(CoupledModel::film_index) *= 1.02;
        const Built excited(v.s, Excitation{1e6, 104.0});
        for (const CoupledModel* m : {&d.model, &excited.model}) {
            const Linearisation a = m->jacobian(z, 1.7e-3);
            const Linearisation f = finite_difference_jacobian(*m, z, 1.7e-3);
            REQUIRE(a.status == DynamicsStatus::ok);
            REQUIRE(f.status == DynamicsStatus::ok);
            const double w = worst_relative_difference(a.jacobian, f.jacobian, *m, z, &row, &col);
            MESSAGE(v.name << (m == &d.model ? std::string() : std::string(", excited"))
                           << ", moving gap: worst = " << w << " at (" << row << ", " << col
                           << ")");
            CHECK(w <= 1e-6);
        }
    }
}

TEST_CASE("assembled Jacobian: a perturbed state that fails is the status the differences give") {
    // a span tension within its step (1 kPa) of zero: the finite differences visit a slack strip
    Scenario s;
    s.tensions.back.stress = 500.0;
    const Built d(s);
    REQUIRE(d.ref.status == BiteStatus::ok);
    const Eigen::VectorXd z0 = d.model.equilibrium();
    const Linearisation a = d.model.jacobian(z0, 0.0);
    const Linearisation f = finite_difference_jacobian(d.model, z0, 0.0);
    CHECK(f.status == DynamicsStatus::slack_strip);
    CHECK(a.status == f.status);
}

TEST_CASE("assembled Jacobian: the eigenvalues equal those of the finite differences") {
    for (const Named& v : rollgap::test::dynamics_scenarios(/*more=*/true)) {
        CAPTURE(v.name);
        const Built d(v.s);
        REQUIRE(d.ref.status == BiteStatus::ok);
        const SpeedStability a = linear_stability(d.model);
        const SpeedStability f = linear_stability(FiniteDifferenceView(d.model));
        REQUIRE(a.status == DynamicsStatus::ok);
        REQUIRE(f.status == DynamicsStatus::ok);
        REQUIRE(a.eigenvalues.size() == f.eigenvalues.size());
        // pair each eigenvalue with the nearest of the other set
        double worst = 0.0;
        for (const auto& lf : f.eigenvalues) {
            double nearest = std::abs(a.eigenvalues.front() - lf);
            for (const auto& la : a.eigenvalues) nearest = std::min(nearest, std::abs(la - lf));
            worst = std::max(worst, nearest / std::abs(lf));
        }
        MESSAGE(v.name << ": worst |lambda_assembled - lambda_fd| / |lambda| = " << worst);
        CHECK(worst <= 1e-6);
        CHECK(a.stable == f.stable);
        CHECK(rel(a.least_damped.eigenvalue.real(), f.least_damped.eigenvalue.real()) <= 1e-6);
        CHECK(rel(a.least_damped.frequency_Hz, f.least_damped.frequency_Hz) <= 1e-6);
    }
}

TEST_CASE("assembled Jacobian: the suite's critical speeds equal those of the finite differences") {
    // the scenarios test_stability.cpp searches: defaults (found), constant back tension (stable),
    // eulerian film (unstable from the start), no limiting shear (a crossing below the skid onset)
    std::vector<Named> searched;
    searched.push_back({"defaults", Scenario{}});
    Scenario c;
    c.tensions.back.mode = TensionMode::constant;
    searched.push_back({"constant back tension", c});
    Scenario e;
    e.inlet_film = InletFilmModel::eulerian;
    searched.push_back({"eulerian film", e});
    Scenario l;
    l.lubricant.limiting_shear = false;
    searched.push_back({"no limiting shear", l});
    for (const Named& v : searched) {
        CAPTURE(v.name);
        const CriticalSpeedResult production = critical_speed(v.s);
        const auto search = [&](bool assembled) {
            return critical_speed_search([&](double speed, bool with_k4) {
                return stability_with(v.s, speed, with_k4, assembled);
            });
        };
        const CriticalSpeedResult a = search(true), f = search(false);
        // the test's own search with the assembled Jacobian is the production one
        CHECK(production.status == a.status);
        CHECK(production.critical_speed == a.critical_speed);
        CHECK(a.status == f.status);
        REQUIRE(a.scan.size() == f.scan.size());
        double worst = 0.0;
        for (std::size_t i = 0; i < a.scan.size(); ++i) {
            CHECK(a.scan[i].status == f.scan[i].status);
            CHECK(a.scan[i].stable == f.scan[i].stable);
            if (a.scan[i].status == DynamicsStatus::ok)
                worst = std::max(worst, rel(a.scan[i].max_real_part, f.scan[i].max_real_part));
        }
        MESSAGE(v.name << ": " << std::string(to_string(a.status)) << ", critical speed "
                       << a.critical_speed << " (assembled) / " << f.critical_speed
                       << " m/s (differences), relative difference "
                       << (a.critical_speed > 0.0 ? rel(a.critical_speed, f.critical_speed) : 0.0)
                       << "; worst relative change of the largest real part over the scan "
                       << worst);
        if (a.status == CriticalSpeedStatus::found) {
            CHECK(rel(a.critical_speed, f.critical_speed) <= 1e-6);
            CHECK(rel(a.unstable_mode.frequency_Hz, f.unstable_mode.frequency_Hz) <= 1e-6);
        }
    }
}

}  // namespace bite_jacobian_test
