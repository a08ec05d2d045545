// The `segments` span model (docs/model.md §12.1) against identity 6 of the mill's specification:
// a span with both ends held at their speeds vibrates at the lumped chain's frequencies, whose
// first tends to the string's c / 2L (within 1 % from 10 segments); one segment is the spring
// law; and the segments fall back onto the spring law as omega L / c -> 0 (the strip's mass made
// negligible). Two-stand mills only: each case costs a few bite Jacobians (well under a second
// under ASan).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/mill/mill.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_stability.h"
#include "core/stability.h"
#include "support/compare.h"
#include "support/jacobian_columns.h"

#include "tools/verify_mill/mills.h"

namespace mill_segments_test {

using namespace rollgap::core;
using rollgap::test::worst_nearest;
using rollgap::tools::mills::two_stand_mill;

Mill with_segments(Mill m, int n) {
    m.span_model = SpanModel::segments;
    m.span_segments = n;
    return m;
}

// The assembled A0 of a mill at its steady state.
Eigen::MatrixXd frozen_jacobian(const Mill& m) {
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);
    const Linearisation lin = model.jacobian(model.equilibrium(), 0.0);
    REQUIRE(lin.status == DynamicsStatus::ok);
    return lin.jacobian;
}

TEST_CASE("mill segments: the held span's modes are the chain's, the first c / 2L within 1 %") {
    // The span's own block of A0 is the span with both ends held at their speeds (the stands'
    // speeds enter through other columns). A chain of n segments (stiffness k = E ybar n / L)
    // between held ends with n - 1 nodes of mass m = rho ybar L / n has the modes
    // omega_j = 2 sqrt(k / m) sin(j pi / 2n) = 2 (n c / L) sin(j pi / 2n), the first tending to
    // the string's pi c / L (c / 2L in Hz) as n grows, from below.
    const double length = 5.0;
    for (const int n : {2, 10, 20, 50}) {
        const Mill m = with_segments(two_stand_mill(length), n);
        const MillSteadyState steady = mill_steady_state(m);
        REQUIRE(steady.status == MillSteadyStatus::ok);
        const MillModel model(m, steady);
        const MillLinearisation lin = model.linearise(model.equilibrium(), false);
        REQUIRE(lin.status == DynamicsStatus::ok);
        const MillModel::SpanStates span = model.span_states(1);  // between stands 1 and 2
        REQUIRE(span.segments == n);
        REQUIRE(span.count == 2 * n - 1);
        Eigen::MatrixXd block = lin.jacobian.block(span.first, span.first, span.count, span.count);
        // Inside the span's block the stands appear only as their speeds' slopes in the end
        // forces they see: T_1' = k (v_1 - du2_1) with du2_1 / dT_1 the upstream stand's exit
        // speed slope (the linearisation's exit-speed row), and T_n' = k (du1_2 - v_{n-1}) with
        // du1_2 / dT_n < 0 (more back tension, slower entry). Holding both ends' speeds removes
        // exactly those two entries.
        const int last = n - 1;
        const double k = m.youngs_modulus * m.thickness[1] * n / length;
        CHECK(std::abs(block(0, 0) + k * lin.exit_speed(0, span.first)) <=
              1e-12 * std::abs(block(0, 0)));
        CHECK(block(last, last) < 0.0);
        block(0, 0) = 0.0;
        block(last, last) = 0.0;
        // Forces and speeds lie ~1e10 apart in the block (k ~ 1e8, 1/m ~ 0.04): in the
        // energy-balanced variables T / sqrt(k m) and v (a similarity, the same eigenvalues) it
        // is skew-symmetric and its eigenvalues are accurate to rounding.
        const double mass = m.strip_density * m.thickness[1] * length / n;
        Eigen::VectorXd scale = Eigen::VectorXd::Ones(span.count);
        scale.head(n).setConstant(std::sqrt(k * mass));
        const Eigen::MatrixXd balanced =
            scale.cwiseInverse().asDiagonal() * block * scale.asDiagonal();
        const Eigen::VectorXcd values = balanced.eigenvalues();
        std::vector<double> omega;
        for (Eigen::Index k = 0; k < values.size(); ++k) {
            // undamped: on the imaginary axis to rounding, with one zero (the span's mean force)
            CHECK(std::abs(values(k).real()) <= 1e-9 * std::max(1.0, std::abs(values(k))));
            if (values(k).imag() > 1e-6) omega.push_back(values(k).imag());
        }
        std::sort(omega.begin(), omega.end());
        REQUIRE(static_cast<int>(omega.size()) == n - 1);
        const double c = std::sqrt(m.youngs_modulus / m.strip_density);
        for (int j = 1; j < n; ++j) {
            const double chain = 2.0 * n * c / length * std::sin(j * std::numbers::pi / (2.0 * n));
            CHECK(std::abs(omega[static_cast<std::size_t>(j - 1)] - chain) <= 1e-9 * chain);
        }
        const double first_Hz = omega.front() / (2.0 * std::numbers::pi);
        const double string_Hz = c / (2.0 * length);
        const double error = std::abs(first_Hz / string_Hz - 1.0);
        MESSAGE("n = " << n << ": first mode " << first_Hz << " Hz against c/2L = " << string_Hz
                       << " Hz, " << 100.0 * error << " %");
        if (n >= 10) CHECK(error < 0.01);
        else CHECK(error > 0.01);  // two segments are too coarse: sqrt(8)/pi, 10 % low
    }
}

TEST_CASE("mill segments: one segment is the spring law exactly") {
    const Mill spring = two_stand_mill(5.0);
    const Eigen::MatrixXd a = frozen_jacobian(spring);
    const Eigen::MatrixXd b = frozen_jacobian(with_segments(spring, 1));
    REQUIRE(a.rows() == b.rows());
    CHECK((a - b).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("mill segments: the assembled Jacobian and inputs are the differences of the rates") {
    const Mill m = with_segments(two_stand_mill(5.0), 4);
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);
    const Eigen::VectorXd z0 = model.equilibrium();
    // every state at rest: the rates vanish at the steady state, node speeds included
    Eigen::VectorXd rates(model.size());
    REQUIRE(model.rhs(0.0, z0.data(), rates.data()) == DynamicsStatus::ok);
    for (int k = 0; k < model.size(); ++k)
        CHECK(std::abs(rates(k)) <= 1e-9 * std::max(1.0, std::abs(z0(k))));
    const Linearisation assembled = model.jacobian(z0, 0.0);
    const Linearisation differences = finite_difference_jacobian(model, z0, 0.0);
    REQUIRE(assembled.status == DynamicsStatus::ok);
    REQUIRE(differences.status == DynamicsStatus::ok);
    const rollgap::test::ColumnDistance d =
        rollgap::test::column_distance(assembled.jacobian, differences.jacobian);
    MESSAGE("2 stands, 4 segments a span: assembled vs differences, worst column " << d.worst);
    CHECK(d.worst < 1e-5);
    CHECK(d.nonzero_where_zero == 0);
    // the stands see the end segments: the delayed input enters at the span's far end only
    const MillLinearisation lin = model.linearise(z0);
    REQUIRE(lin.status == DynamicsStatus::ok);
    const MillModel::SpanStates span = model.span_states(1);
    CHECK(lin.input(span.first + span.segments - 1, 0) != 0.0);  // T_n: stand 2's u1 moves
    for (int k = 0; k + 1 < span.segments; ++k) CHECK(lin.input(span.first + k, 0) == 0.0);
    CHECK(model.back_span(1) == span.first + span.segments - 1);
    CHECK(model.front_span(0) == span.first);
}

TEST_CASE("mill segments: segments fall back onto the spring law as omega L / c -> 0") {
    // The spring law neglects the strip's mass: its stiffness error is 1 - x / tan x ~ x^2 / 3
    // at x = omega L / c. Lowering the density 100-fold moves c up 10-fold and x^2 down 100-fold
    // at every frequency (the spring law does not see the density), so the segments' roots must
    // approach the spring's by about that factor. Compared: every root of the spring mill with
    // its nearest root of the segments mill (the segments' own span waves, above c / 2L, have no
    // counterpart and are not compared).
    const Mill spring = two_stand_mill(5.0);
    const MillStability reference = mill_frozen_stability(spring);
    REQUIRE(reference.frozen.status == DynamicsStatus::ok);
    std::vector<double> distance;
    std::vector<double> growth;
    for (const double density_factor : {1.0, 0.01}) {
        Mill m = with_segments(spring, 10);
        m.strip_density *= density_factor;
        const MillStability seg = mill_frozen_stability(m);
        REQUIRE(seg.frozen.status == DynamicsStatus::ok);
        // 2 stand blocks + 3 spans of 19 states against 3 of 1
        CHECK(seg.frozen.eigenvalues.size() == reference.frozen.eigenvalues.size() + 3 * 18);
        distance.push_back(worst_nearest(reference.frozen.eigenvalues, seg.frozen.eigenvalues));
        growth.push_back(seg.frozen.max_real_part);
        MESSAGE("density x" << density_factor << ": worst relative root distance "
                            << distance.back() << ", rightmost real part "
                            << seg.frozen.max_real_part << " /s at "
                            << seg.frozen.least_damped.frequency_Hz << " Hz (spring "
                            << reference.frozen.max_real_part << " /s)");
    }
    CHECK(distance[1] < distance[0] / 30.0);
    CHECK(distance[1] < 1e-3);
}

}  // namespace mill_segments_test
