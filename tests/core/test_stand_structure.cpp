// The six-mass mill stack (paper eq. 37, docs/model.md §5), checked against independent references:
// closed-form natural frequencies of uniform spring-mass chains, the defining identity of
// Rayleigh damping, the classical-damping identity for proportional damping, and the matrices
// written out by hand, row by row, from eq. (37).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/stand_structure.h"

#include "support/compare.h"
#include "support/approx.h"

namespace {

using namespace rollgap::core;
using rollgap::test::rel;

// A mill with every mass m and every spring k, no damping at all.
StandStructure uniform_structure(double m, double k) {
    StandStructure mill;
    mill.mass = {m, m, m, m, m, m};
    mill.k1 = mill.k2 = mill.k3 = mill.k5 = mill.k6 = mill.k7 = k;
    mill.c1 = mill.c2 = 0.0;
    mill.rayleigh = false;
    return mill;
}

std::vector<double> natural_omegas(const ModalAnalysis& modes) {
    std::vector<double> out;
    for (const auto& n : modes.natural) out.push_back(2.0 * std::numbers::pi * n.frequency_Hz);
    return out;
}

// Distinct, random-ish values so that a swapped index cannot go unnoticed.
StandStructure irregular_structure() {
    StandStructure mill;
    mill.mass = {41.3e3, 57.9e3, 10.7e3, 12.2e3, 63.1e3, 38.5e3};
    mill.k1 = 23.7e9;
    mill.k2 = 31.9e9;
    mill.k3 = 36.4e9;
    mill.k5 = 33.1e9;
    mill.k6 = 28.6e9;
    mill.k7 = 26.2e9;
    mill.c1 = 1.7e6;
    mill.c2 = 0.13e6;
    mill.rayleigh = false;
    return mill;
}

}  // namespace

TEST_CASE(
    "mill structure: uniform fixed-fixed chain of six masses has the closed-form frequencies") {
    // All m and k equal, strip spring k4 = k: a chain of N = 6 equal masses between two walls,
    // omega_j = 2 sqrt(k/m) sin(j pi / (2 (N + 1))).
    const double m = 17.0e3, k = 29.0e9;
    const StructureMatrices mats = structure_matrices(uniform_structure(m, k));
    const ModalAnalysis modes = modal_analysis(mats, k);
    REQUIRE(modes.ok);
    const std::vector<double> omega = natural_omegas(modes);
    REQUIRE(omega.size() == 6);
    const int N = 6;
    for (int j = 1; j <= N; ++j) {
        const double expected =
            2.0 * std::sqrt(k / m) * std::sin(j * std::numbers::pi / (2.0 * (N + 1)));
        CHECK(rel(omega[static_cast<std::size_t>(j - 1)], expected) < 1e-10);
    }
    // undamped: every eigenvalue of the first-order system is purely imaginary at the same omegas
    REQUIRE(modes.damped.size() == 6);
    for (int j = 0; j < N; ++j) {
        CHECK(std::abs(modes.damped[static_cast<std::size_t>(j)].eigenvalue.real()) <
              1e-9 * omega[static_cast<std::size_t>(j)]);
        CHECK(rel(2.0 * std::numbers::pi * modes.damped[static_cast<std::size_t>(j)].frequency_Hz,
                  omega[static_cast<std::size_t>(j)]) < 1e-10);
    }
    // mass-normalised shapes: phi^T M phi = 1; sine shapes: |phi_i| proportional to |sin(i j pi/7)|
    for (int j = 1; j <= N; ++j) {
        const Vector6& phi = modes.natural[static_cast<std::size_t>(j - 1)].shape;
        CHECK(std::abs(phi.dot(mats.mass * phi) - 1.0) < 1e-12);
        Vector6 sine;
        for (int i = 1; i <= N; ++i) sine(i - 1) = std::sin(i * j * std::numbers::pi / (N + 1));
        sine *= std::sqrt(2.0 / ((N + 1) * m));  // mass-normalised sine mode
        CHECK((phi.cwiseAbs() - sine.cwiseAbs()).norm() < 1e-9 * sine.norm());
    }
}

TEST_CASE("mill structure: k4 = 0 splits the stack into two fixed-free three-mass chains") {
    // Without the strip the upper stack (ground-k1-m1-k2-m2-k3-m3, m3 free) and its mirror image
    // are identical fixed-free chains of N = 3: omega_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2N +
    // 1))), each frequency twice.
    const double m = 11.0e3, k = 35.0e9;
    const ModalAnalysis modes = modal_analysis(structure_matrices(uniform_structure(m, k)), 0.0);
    REQUIRE(modes.ok);
    const std::vector<double> omega = natural_omegas(modes);
    REQUIRE(omega.size() == 6);
    const int N = 3;
    for (int j = 1; j <= N; ++j) {
        const double expected = 2.0 * std::sqrt(k / m) *
                                std::sin((2.0 * j - 1.0) * std::numbers::pi / (2.0 * (2 * N + 1)));
        CHECK(rel(omega[static_cast<std::size_t>(2 * j - 2)], expected) < 1e-10);
        CHECK(rel(omega[static_cast<std::size_t>(2 * j - 1)], expected) < 1e-10);
    }
}

TEST_CASE(
    "mill structure: Rayleigh coefficients give exactly the damping ratio at both frequencies") {
    struct Case {
        double zeta, f1, f2;
    };
    for (const Case c : {Case{0.04, 100.0, 400.0}, Case{0.02, 35.0, 2500.0}, Case{0.1, 7.5, 8.5}}) {
        const RayleighCoefficients r = rayleigh_coefficients(c.zeta, c.f1, c.f2);
        CHECK(r.alpha > 0.0);
        CHECK(r.beta > 0.0);
        for (const double f : {c.f1, c.f2}) {
            const double w = 2.0 * std::numbers::pi * f;
            const double zeta = r.alpha / (2.0 * w) + r.beta * w / 2.0;
            CHECK(std::abs(zeta - c.zeta) <=
                  1e-14 * c.zeta * 4);  // a few roundings of a 0.04-sized sum
        }
        // between the two frequencies the Rayleigh curve dips below zeta (its minimum is at sqrt(w1
        // w2))
        const double wm = 2.0 * std::numbers::pi * std::sqrt(c.f1 * c.f2);
        CHECK(r.alpha / (2.0 * wm) + r.beta * wm / 2.0 < c.zeta);
    }
}

TEST_CASE(
    "mill structure: proportional damping gives zeta_n = alpha/(2 w_n) + beta w_n/2 for every mode") {
    // With c1 = c2 = 0 and no strip spring, C = alpha M + beta K_s is proportional to the stiffness
    // of the modal problem, so the modes decouple (classical damping) and each damped eigenvalue
    // is lambda = -zeta_n w_n + i w_n sqrt(1 - zeta_n^2), |lambda| = w_n.
    StandStructure
        symmetric;  // docs/model.md §8 defaults (a symmetric stack: modes in degenerate pairs)
    StandStructure irregular = irregular_structure();
    for (StandStructure mill : {symmetric, irregular}) {
        mill.c1 = mill.c2 = 0.0;
        mill.rayleigh = true;
        const StructureMatrices mats = structure_matrices(mill);
        const double alpha = mats.rayleigh.alpha, beta = mats.rayleigh.beta;
        REQUIRE(alpha > 0.0);
        REQUIRE(beta > 0.0);
        const ModalAnalysis modes = modal_analysis(mats, 0.0);
        REQUIRE(modes.ok);
        REQUIRE(modes.natural.size() == 6);
        REQUIRE(modes.damped.size() == 6);  // every mode underdamped here (zeta_n < 0.2)
        for (int n = 0; n < 6; ++n) {
            const double wn =
                2.0 * std::numbers::pi * modes.natural[static_cast<std::size_t>(n)].frequency_Hz;
            const double zeta = alpha / (2.0 * wn) + beta * wn / 2.0;
            // pair each natural mode with the damped eigenvalue of nearest modulus (damped modes
            // are sorted by damped frequency, which can reorder near-degenerate pairs)
            const DampedMode* best = nullptr;
            for (const auto& d : modes.damped) {
                if (!best || std::abs(std::abs(d.eigenvalue) - wn) <
                                 std::abs(std::abs(best->eigenvalue) - wn))
                    best = &d;
            }
            REQUIRE(best != nullptr);
            CHECK(rel(std::abs(best->eigenvalue), wn) < 1e-8);
            CHECK(std::abs(best->damping_ratio - zeta) < 1e-8);
            CHECK(rel(best->eigenvalue.imag(), wn * std::sqrt(1.0 - zeta * zeta)) < 1e-8);
        }
    }
}

TEST_CASE("mill structure: matrices are eq. (37) row by row") {
    const StandStructure mill = irregular_structure();
    const double k1 = mill.k1, k2 = mill.k2, k3 = mill.k3, k5 = mill.k5, k6 = mill.k6, k7 = mill.k7;
    const double k4 = 21.9e9, c1 = mill.c1, c2 = mill.c2;
    const StructureMatrices mats = structure_matrices(mill);

    // M: diagonal, positive, m1..m6 in order
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            if (i == j) {
                CHECK(mats.mass(i, i) == mill.mass[static_cast<std::size_t>(i)]);
                CHECK(mats.mass(i, i) > 0.0);
            } else {
                CHECK(mats.mass(i, j) == 0.0);
            }
        }
    }

    // K of eq. (37), typed from the paper:
    //   m1: (k1 + k2) x1 - k2 x2
    //   m2: -k2 x1 + (k2 + k3) x2 - k3 x3
    //   m3: -k3 x2 + (k3 + k4) x3 - k4 x4
    //   m4: -k4 x3 + (k4 + k5) x4 - k5 x5
    //   m5: -k5 x4 + (k5 + k6) x5 - k6 x6
    //   m6: -k6 x5 + (k6 + k7) x6
    Matrix6 K37;
    // clang-format off
    K37 <<  k1 + k2,     -k2,      0.0,      0.0,      0.0,      0.0,
                -k2, k2 + k3,      -k3,      0.0,      0.0,      0.0,
                0.0,     -k3,  k3 + k4,      -k4,      0.0,      0.0,
                0.0,     0.0,      -k4,  k4 + k5,      -k5,      0.0,
                0.0,     0.0,      0.0,      -k5,  k5 + k6,      -k6,
                0.0,     0.0,      0.0,      0.0,      -k6,  k6 + k7;
    // C of eq. (37): c1 between m1 and m2, c2 between m3 and m4
    Matrix6 C37;
    C37 <<  c1, -c1, 0.0, 0.0, 0.0, 0.0,
           -c1,  c1, 0.0, 0.0, 0.0, 0.0,
           0.0, 0.0,  c2, -c2, 0.0, 0.0,
           0.0, 0.0, -c2,  c2, 0.0, 0.0,
           0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
           0.0, 0.0, 0.0, 0.0, 0.0, 0.0;
    // clang-format on
    const Matrix6 K = total_stiffness(mats, k4);
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            CAPTURE(i);
            CAPTURE(j);
            CHECK(K(i, j) == rollgap::test::approx(K37(i, j)).epsilon(1e-15));
            CHECK(mats.damping(i, j) == rollgap::test::approx(C37(i, j)).epsilon(1e-15));
        }
    }
    // the right-hand side of eq. (37): +dP on m3, -dP on m4
    const Vector6 b = gap_direction();
    Vector6 expected_b;
    expected_b << 0, 0, 1, -1, 0, 0;
    CHECK(b == expected_b);

    // K_s is K of eq. (37) with k4 = 0 and total_stiffness adds exactly k4 b b^T
    const Matrix6& Ks = mats.structural_stiffness;
    CHECK((K - Ks - k4 * b * b.transpose()).cwiseAbs().maxCoeff() <= 1e-15 * k4);
    CHECK((total_stiffness(mats, 0.0) - Ks).cwiseAbs().maxCoeff() == 0.0);

    // K_s symmetric positive definite; K_s 1 = the ground springs only (k1 on m1, k7 on m6)
    CHECK((Ks - Ks.transpose()).cwiseAbs().maxCoeff() == 0.0);
    Eigen::LLT<Matrix6> llt(Ks);
    CHECK(llt.info() == Eigen::Success);
    const Vector6 row_sums = Ks * Vector6::Ones();
    Vector6 ground;
    ground << k1, 0, 0, 0, 0, k7;
    CHECK((row_sums - ground).cwiseAbs().maxCoeff() <= 1e-15 * k3);
    // and with the strip: a rigid gap-closing motion b stretches only k3, k4, k5
    const Vector6 Kb = K * b;
    Vector6 expected_Kb;
    expected_Kb << 0, -k3, k3 + 2 * k4, -(2 * k4 + k5), k5, 0;
    CHECK((Kb - expected_Kb).cwiseAbs().maxCoeff() <= 1e-15 * (k3 + k4 + k5) * 4);
}

TEST_CASE("mill structure: Rayleigh damping is added as alpha M + beta K_s, never with k4") {
    StandStructure mill = irregular_structure();
    mill.rayleigh = true;
    const StructureMatrices with = structure_matrices(mill);
    mill.rayleigh = false;
    const StructureMatrices without = structure_matrices(mill);
    const RayleighCoefficients r = rayleigh_coefficients(0.04, 100.0, 400.0);
    CHECK(with.rayleigh.alpha == r.alpha);
    CHECK(with.rayleigh.beta == r.beta);
    const Matrix6 expected =
        without.damping + r.alpha * without.mass + r.beta * without.structural_stiffness;
    CHECK((with.damping - expected).cwiseAbs().maxCoeff() <=
          1e-15 * expected.cwiseAbs().maxCoeff());
    // the damping matrix is symmetric positive semi-definite (Rayleigh part positive definite)
    CHECK((with.damping - with.damping.transpose()).cwiseAbs().maxCoeff() == 0.0);
    Eigen::LLT<Matrix6> llt(with.damping);
    CHECK(llt.info() == Eigen::Success);
}
