// Christensen's roughness model (paper eqs. 19-26, docs/model.md §3), checked against independent
// references: adaptive quadrature of the definitions (19), (20), (24) and a bisection inverse
// built on that quadrature, never against the implementation's own output.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/christensen_contact.h"
#include "support/compare.h"
#include "support/quadrature.h"
#include "support/approx.h"

namespace {

using namespace rollgap::core;
using rollgap::test::bisect;
using rollgap::test::integrate;
using rollgap::test::integrate_to_infinity;
using rollgap::test::QuadratureOptions;

using rollgap::test::unit_roundoff;  // unit roundoff

QuadratureOptions tight() {
    QuadratureOptions o;
    o.rel_tol = 1e-14;
    o.abs_tol = 0.0;
    return o;
}

// Eq. (19): Christensen's height density, support |z| <= 3 Rq, written as printed.
struct Density {
    double rq;
    double operator()(double z) const {
        if (std::abs(z) > 3.0 * rq) return 0.0;
        const double s = z / rq;
        const double w = 1.0 - s * s / 9.0;
        return 35.0 / (96.0 * rq) * w * w * w;
    }
};

// The same density as a function of the depth below the top of its support, w = 3Rq - z:
// 1 - (z/Rq)^2/9 = w (6Rq - w) / (9Rq^2). The references below integrate in w. Evaluating the
// printed form at z = 3Rq - w cancels near the top edge (relative error ~u 3Rq / w), which
// near Z = -1 (H_t) and Z = +1 (A) would make the integrand noisier than the 1e-14 the
// quadrature is asked for; in w it is exact to a few ulp.
struct DensityFromTop {
    double rq;
    double operator()(double w) const {
        const double c = 3.0 * rq;
        if (w < 0.0 || w > 2.0 * c) return 0.0;
        const double b = w * (2.0 * c - w) / (c * c);
        return 35.0 / (96.0 * rq) * b * b * b;
    }
};

// Eqs. (20)-(22): H_t(Z) = h_t / Rq with h_t = int_{-h}^{inf} (h + z) f(z) dz, h = 3 Rq Z.
// f vanishes above z = 3Rq, so with z = 3Rq - w:
//   h_t = int_0^{min(3Rq + h, 6Rq)} (3Rq + h - w) f(3Rq - w) dw.
double ref_film_ratio(double Z, double rq = 2e-6) {
    if (Z <= -1.0) return 0.0;
    const DensityFromTop f{rq};
    const double c = 3.0 * rq;
    const double h_plus_c = c * (1.0 + Z);  // 1 + Z is exact near Z = -1
    const double wmax = std::min(h_plus_c, 2.0 * c);
    const auto r = integrate([&](double w) { return (h_plus_c - w) * f(w); }, 0.0, wmax, tight());
    REQUIRE(r.converged);
    return r.value / rq;
}

// Eq. (24): A(Z) = int_h^inf f(z) dz = int_0^{min(3Rq - h, 6Rq)} f(3Rq - w) dw.
double ref_contact_of_separation(double Z, double rq = 2e-6) {
    if (Z >= 1.0) return 0.0;
    const DensityFromTop f{rq};
    const double c = 3.0 * rq;
    const double wmax = std::min(c * (1.0 - Z), 2.0 * c);  // 1 - Z is exact near Z = 1
    const auto r = integrate(f, 0.0, wmax, tight());
    REQUIRE(r.converged);
    return r.value;
}

// The exact inverse by bisection on the quadrature H_t (monotone on [-1, 1]).
double ref_separation(double Ht) {
    if (Ht <= 0.0) return -1.0;
    if (Ht >= 3.0) return Ht / 3.0;
    return bisect([&](double Z) { return ref_film_ratio(Z) - Ht; }, -1.0, 1.0);
}

double ref_contact_of_film(double Ht) { return ref_contact_of_separation(ref_separation(Ht)); }

// Eq. (26) as printed in the paper (reference = the paper's text), before clamping.
double fit_branch1(double H) {
    return 1.0 - 2.4398 * H + 6.2049 * std::pow(H, 2) - 11.8410 * std::pow(H, 3) +
           12.5350 * std::pow(H, 4) - 6.6134 * std::pow(H, 5) + 1.3618 * std::pow(H, 6);
}
double fit_branch2(double H) {
    return 0.8855 - 1.1982 * H + 0.7614 * std::pow(H, 2) - 0.3394 * std::pow(H, 3) +
           0.1116 * std::pow(H, 4) - 0.0220 * std::pow(H, 5) + 0.0018 * std::pow(H, 6);
}
double ref_paper_fit(double H) {
    double A;
    if (H < 0.5) {
        A = 1.0;
    } else if (H <= 1.5) {
        A = fit_branch1(H);
    } else if (H <= 3.0) {
        A = fit_branch2(H);
    } else {
        A = 0.0;
    }
    return std::clamp(A, 0.0, 1.0);
}

// Forward rounding bound of the degree-8 polynomial (23) evaluated by Horner:
// |error| <= gamma_16 * sum |c_k| |Z|^k, with sum |c_k||Z|^k <= 3 (35 + 128|Z| + 140 Z^2 + 70 Z^4
// + 28 Z^6 + 5 Z^8) / 256 (= 4.76 at |Z| = 1).
double film_ratio_rounding_bound(double Z) {
    const double z = std::abs(Z);
    const double z2 = z * z;
    const double s =
        3.0 * (35 + 128 * z + 140 * z2 + 70 * z2 * z2 + 28 * z2 * z2 * z2 + 5 * z2 * z2 * z2 * z2) /
        256.0;
    return 16.0 * unit_roundoff * s;
}

std::vector<double> separation_grid() {
    std::vector<double> zs;
    for (int k = 0; k <= 40; ++k) zs.push_back(-1.0 + 0.05 * k);  // 41 points on [-1, 1]
    for (double e : {1e-4, 1e-3, 1e-2, 3e-2, 0.1}) {
        zs.push_back(-1.0 + e);
        zs.push_back(1.0 - e);
    }
    zs.push_back(0.0564196955448166);  // H_t ~ 0.5
    return zs;
}

}  // namespace

TEST_SUITE("christensen_contact") {
    TEST_CASE("reference: Christensen's density (19) integrates to 1") {
        for (double rq : {2e-6, 6e-6, 1.0}) {
            const Density f{rq};
            // over its support
            const auto r = integrate(f, -3.0 * rq, 3.0 * rq, tight());
            CHECK(r.converged);
            CHECK(std::abs(r.value - 1.0) <= 1e-14);
            // and over the whole line, through the semi-infinite quadrature (f is only C^2 at
            // |z| = 3 Rq, so this path converges more slowly; 1e-12 is what it is asked for)
            QuadratureOptions o;
            o.rel_tol = 1e-12;
            const auto right = integrate_to_infinity(f, 0.0, rq, o);
            const auto left = integrate_to_infinity([&](double z) { return f(-z); }, 0.0, rq, o);
            CHECK(right.converged);
            CHECK(left.converged);
            CHECK(std::abs(right.value + left.value - 1.0) <= 1e-11);
            // the depth form used by the references is the same function
            const DensityFromTop g{rq};
            CHECK(std::abs(integrate(g, 0.0, 6.0 * rq, tight()).value - 1.0) <= 1e-14);
            for (int k = 0; k <= 60; ++k) {
                const double z = -3.0 * rq + 0.1 * rq * k;
                CHECK(std::abs(g(3.0 * rq - z) - f(z)) <= 1e-13 * 35.0 / (96.0 * rq));
            }
        }
    }

    TEST_CASE("H_t(Z) of (23) and A(Z) of corrected (25) agree with quadrature of (20) and (24)") {
        // Absolute agreement 1e-10 on 41 + 11 separations, for two roughness scales (the
        // dimensionless result must not depend on Rq).
        double max_dh = 0.0;
        double max_da = 0.0;
        for (double rq : {2e-6, 1.0}) {
            for (double Z : separation_grid()) {
                CAPTURE(Z);
                CAPTURE(rq);
                const double h_ref = ref_film_ratio(Z, rq);
                const double a_ref = ref_contact_of_separation(Z, rq);
                const double dh = std::abs(christensen_film_ratio(Z) - h_ref);
                const double da = std::abs(christensen_contact_ratio_of_separation(Z) - a_ref);
                max_dh = std::max(max_dh, dh);
                max_da = std::max(max_da, da);
                CHECK(dh <= 1e-10);
                CHECK(da <= 1e-10);
            }
        }
        MESSAGE("max |H_t - quadrature| = " << max_dh << ", max |A - quadrature| = " << max_da);
    }

    TEST_CASE("the printed -5Z of (25) is a typo: the quadrature of (24) pins the 35Z term") {
        // A(1) must vanish; with -5Z it would be 30/32. Quadrature is the witness.
        CHECK(std::abs(ref_contact_of_separation(1.0 - 1e-9)) <= 1e-12);
        CHECK(std::abs(christensen_contact_ratio_of_separation(1.0)) <= 1e-15);
        // the coefficient of Z: dA/dZ(0) = -35/32 (from -f at z = 0 times 3Rq). Central difference
        // with d = 1e-5: truncation d^2/6 |A'''(0)| = 1e-10 * 6.56 / 6, rounding ~1e-16 / d.
        const double d = 1e-5;
        const double slope =
            (ref_contact_of_separation(d) - ref_contact_of_separation(-d)) / (2 * d);
        CHECK(std::abs(slope + 35.0 / 32.0) <= 1e-9);
        const double slope_impl = (christensen_contact_ratio_of_separation(d) -
                                   christensen_contact_ratio_of_separation(-d)) /
                                  (2 * d);
        CHECK(std::abs(slope_impl + 35.0 / 32.0) <= 1e-9);
    }

    TEST_CASE("dH_t/dZ = 3 (1 - A) by central differences") {
        // Central difference of H_t with step d: truncation <= d^2/6 max|H'''| with
        // H''' = -(315/16) Z (1 - Z^2)^2, max|H'''| = (315/16)(0.2862) = 5.64 on [-1, 1] (0
        // outside); rounding <= 2 * (Horner bound 8.5e-15) / (2d). With d = 2e-5: 3.8e-10 + 4.3e-10
        // ~ 8e-10; the check uses that bound.
        const double d = 2e-5;
        const double trunc = d * d / 6.0 * 5.64;
        double max_err = 0.0;
        for (int k = 0; k <= 40; ++k) {
            const double Z = -1.0 + 0.05 * k;
            CAPTURE(Z);
            const double fd =
                (christensen_film_ratio(Z + d) - christensen_film_ratio(Z - d)) / (2 * d);
            const double tol = trunc + 2.0 * film_ratio_rounding_bound(Z) / (2 * d) + 1e-14;
            const double want_ref = 3.0 * (1.0 - ref_contact_of_separation(Z));
            const double want_impl = 3.0 * (1.0 - christensen_contact_ratio_of_separation(Z));
            max_err = std::max(max_err, std::abs(fd - want_ref));
            CHECK(std::abs(fd - want_ref) <= tol);
            CHECK(std::abs(fd - want_impl) <= tol + 1e-10);
        }
        MESSAGE("max |FD dH_t/dZ - 3(1-A_ref)| = " << max_err);
    }

    TEST_CASE("limits and the range beyond [-1, 1]") {
        CHECK(std::abs(christensen_film_ratio(-1.0)) <= 1e-15);
        CHECK(std::abs(christensen_film_ratio(1.0) - 3.0) <= 1e-15);
        CHECK(std::abs(christensen_contact_ratio_of_separation(-1.0) - 1.0) <= 1e-15);
        CHECK(std::abs(christensen_contact_ratio_of_separation(1.0)) <= 1e-15);
        for (double Z : {1.0 + 1e-12, 1.001, 1.5, 2.0, 10.0, 1e6}) {
            CAPTURE(Z);
            CHECK(christensen_film_ratio(Z) == rollgap::test::approx(3.0 * Z).epsilon(1e-15));
            CHECK(christensen_contact_ratio_of_separation(Z) == 0.0);
            // and the quadrature of the definitions says the same
            CHECK(std::abs(ref_film_ratio(Z) - 3.0 * Z) <= 1e-12 * Z);
            CHECK(ref_contact_of_separation(Z) == 0.0);
        }
        for (double Z : {-1.0 - 1e-12, -1.001, -2.0, -1e6}) {
            CAPTURE(Z);
            CHECK(christensen_film_ratio(Z) == 0.0);
            CHECK(christensen_contact_ratio_of_separation(Z) == 1.0);
        }
        // the order of contact at Z = -1 that makes the inverse ill-conditioned there:
        // H_t = (21/16) eps^5 (1 - eps + O(eps^2)), eps = 1 + Z (quadrature and implementation)
        for (double eps : {1e-1, 1e-2, 1e-3}) {
            CAPTURE(eps);
            const double lead = 21.0 / 16.0 * std::pow(eps, 5);
            CHECK(std::abs(ref_film_ratio(-1.0 + eps) / lead - 1.0) <= 1.1 * eps);
            // (the implementation may evaluate (23) as printed, accurate only to dH absolute)
            CHECK(std::abs(christensen_film_ratio(-1.0 + eps) / lead - 1.0) <=
                  1.1 * eps + film_ratio_rounding_bound(-1.0 + eps) / lead);
            // and 1 - A = (35/16) eps^4 (1 - (6/5) eps + O(eps^2)); 1 - A(Z) = A(-Z) since f is
            // even, which the quadrature evaluates without cancellation
            const double one_minus_a = ref_contact_of_separation(1.0 - eps);
            CHECK(std::abs(one_minus_a / (35.0 / 16.0 * std::pow(eps, 4)) - 1.0) <= 1.3 * eps);
            CHECK(std::abs(1.0 - ref_contact_of_separation(-1.0 + eps) - one_minus_a) <= 1e-15);
        }
        // inverse outside [0, 3]
        CHECK(christensen_separation(0.0) == -1.0);
        CHECK(christensen_separation(-0.5) == -1.0);
        CHECK(christensen_separation(3.0) == rollgap::test::approx(1.0).epsilon(1e-15));
        for (double H : {3.0 + 1e-12, 3.5, 7.0, 1e3}) {
            CAPTURE(H);
            CHECK(christensen_separation(H) == rollgap::test::approx(H / 3.0).epsilon(1e-15));
            CHECK(christensen_contact_ratio(H) == 0.0);
        }
        CHECK(christensen_contact_ratio(0.0) == 1.0);
        CHECK(christensen_contact_ratio(-1.0) == 1.0);
        CHECK(std::abs(christensen_contact_ratio(3.0)) <= 1e-15);
    }

    TEST_CASE("inverse round trip Z -> H_t -> Z, with a tolerance from the conditioning") {
        // Conditioning. Near Z = -1, with eps = 1 + Z: 1 - A = (35/16) eps^4 + O(eps^5), so
        // dH_t/dZ = 3(1 - A) ~ (105/16) eps^4 and H_t ~ (21/16) eps^5. H_t(Z) is computed with an
        // absolute error dH <= gamma_16 sum|c_k||Z|^k (~8.5e-15 at |Z| ~ 1, Horner bound), both by
        // the test's forward call and inside the solver, so the best attainable round-trip error is
        //   |dZ| <= 2 dH / H_t'(Z)     (5e-15 at Z = 0.9, 3e-14 at Z = -0.5, 2e-11 at Z = -0.9,
        //                               3e-7 at Z = -0.99)
        // i.e. the inverse is ill-conditioned like eps^-4. The forward check uses
        //   tol(Z) = 1e-12 + 2 dH / H_t'(Z - eps/10)
        // (H_t' evaluated 10 % closer to -1 so that it bounds H_t' over the interval reached), and
        // is made only where tol(Z) < eps/10 (otherwise H_t itself is at rounding level, e.g.
        // H_t(-1 + 1e-3) = 1.3e-15, and only the backward error means anything). The backward error
        // |H_t_ref(Z*) - H_t| <= 2 dH + 1e-12 H_t'(Z) is checked everywhere.
        double max_fwd = 0.0;
        double max_fwd_scaled = 0.0;  // |dZ| / tol
        double max_bwd = 0.0;
        int forward_checked = 0;
        for (double Z : separation_grid()) {
            if (Z <= -1.0) continue;  // (-1, 1]
            CAPTURE(Z);
            const double H = christensen_film_ratio(Z);
            const double Zs = christensen_separation(H);
            CAPTURE(H);
            CAPTURE(Zs);
            const double eps = 1.0 + Z;
            const double dH = film_ratio_rounding_bound(Z);
            const double slope_lo = 3.0 * (1.0 - ref_contact_of_separation(Z - 0.1 * eps));
            const double tol = 1e-12 + 2.0 * dH / slope_lo;
            CHECK(Zs >= -1.0);
            CHECK(Zs <= 1.0);
            if (tol < 0.1 * eps) {
                ++forward_checked;
                const double err = std::abs(Zs - Z);
                max_fwd = std::max(max_fwd, err);
                max_fwd_scaled = std::max(max_fwd_scaled, err / tol);
                CHECK(err <= tol);  // tol(Z) < 1.03e-12 for Z >= -0.5
            }
            const double slope = 3.0 * (1.0 - ref_contact_of_separation(Z));
            const double bwd = std::abs(ref_film_ratio(Zs) - H);
            max_bwd = std::max(max_bwd, bwd);
            CHECK(bwd <= 2.0 * dH + 1e-12 * slope);
        }
        CHECK(forward_checked >= 45);
        MESSAGE("round trip: max |Z* - Z| = " << max_fwd << " (max ratio to tol " << max_fwd_scaled
                                              << "), max backward |H_t(Z*) - H_t| = " << max_bwd);
    }

    TEST_CASE("A(H_t) = christensen_contact_ratio against the quadrature inverse") {
        // A(H_t) is well-conditioned even where Z(H_t) is not: dA/dH_t = -g(Z) / (3 (1 - A)) with
        // g = (35/32)(1 - Z^2)^3 ~ (35/4) eps^3, so |dA/dH_t| ~ 4 / (3 eps) (~350 at H_t = 1e-12,
        // eps = 3.8e-3), and |dA| <= 350 * 2 * 8.5e-15 < 1e-11. The check uses 1e-10 everywhere.
        std::vector<double> hs = {1e-12, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2};
        for (int k = 1; k < 60; ++k) hs.push_back(0.05 * k);
        hs.push_back(3.0 - 1e-9);
        double max_err = 0.0;
        for (double H : hs) {
            CAPTURE(H);
            const double a_ref = ref_contact_of_film(H);
            const double a = christensen_contact_ratio(H);
            max_err = std::max(max_err, std::abs(a - a_ref));
            CHECK(std::abs(a - a_ref) <= 1e-10);
            CHECK(a >= 0.0);
            CHECK(a <= 1.0);
        }
        MESSAGE("max |A(H_t) - quadrature inverse| = " << max_err);
    }

    TEST_CASE("christensen_contact_ratio is monotone decreasing from 1 at H_t = 0 to 0 at 3") {
        double prev = christensen_contact_ratio(0.0);
        CHECK(prev == 1.0);
        for (int k = 1; k <= 3000; ++k) {
            const double H = 1e-3 * k;
            const double a = christensen_contact_ratio(H);
            CAPTURE(H);
            CHECK(a <= prev);
            if (H < 2.9) CHECK(a < prev);  // strictly: the steps are >> rounding here
            prev = a;
        }
        CHECK(std::abs(prev) <= 1e-15);  // H_t = 3
        CHECK(christensen_contact_ratio(3.0001) == 0.0);
    }

    TEST_CASE("paper_fit (26): equals the printed polynomials, clamped to [0, 1]") {
        for (int k = -100; k <= 1000; ++k) {
            const double H = 0.01 * k + 1e-7;  // off the branch points
            CAPTURE(H);
            const double a = paper_fit_contact_ratio(H);
            CHECK(a >= 0.0);
            CHECK(a <= 1.0);
            CHECK(std::abs(a - ref_paper_fit(H)) <= 1e-12);
        }
    }

    TEST_CASE("paper_fit (26): its documented defects, as facts") {
        // 1. A = 1 for H_t < 0.5, where the exact A runs from 1 down to 0.4385 (0.44).
        for (double H : {1e-6, 0.1, 0.25, 0.4, 0.49, 0.5 - 1e-9}) {
            CAPTURE(H);
            CHECK(paper_fit_contact_ratio(H) == 1.0);
            const double exact = ref_contact_of_film(H);
            CHECK(exact < 1.0);
            CHECK(exact > 0.438);
        }
        CHECK(ref_contact_of_film(0.5) == rollgap::test::approx(0.4385).epsilon(5e-4 / 0.4385));

        // 2. Jump at H_t = 0.5: 1 -> 0.449 (branch 1 at 0.5 = 0.449247 from the printed
        // coefficients).
        CHECK(paper_fit_contact_ratio(0.5 - 1e-12) == 1.0);
        const double after05 = paper_fit_contact_ratio(0.5 + 1e-12);
        CHECK(std::abs(after05 - 0.449) <= 5e-4);
        CHECK(std::abs(after05 - ref_contact_of_film(0.5)) > 0.01);  // and not the exact 0.4385

        // 3. Jump at H_t = 1.5: 0.088 -> 0.074 (branch 1 is "0.5 < H_t <= 1.5" in the paper).
        const double at15 = paper_fit_contact_ratio(1.5);
        const double after15 = paper_fit_contact_ratio(1.5 + 1e-12);
        CHECK(std::abs(at15 - 0.0876) <= 5e-4);
        CHECK(std::abs(paper_fit_contact_ratio(1.5 - 1e-12) - 0.0876) <= 5e-4);
        CHECK(std::abs(after15 - 0.0743) <= 5e-4);
        CHECK(at15 - after15 > 0.013);
        // the exact value sits with the second branch: 0.0746
        CHECK(std::abs(ref_contact_of_film(1.5) - 0.0746) <= 5e-4);

        // 4. The second branch crosses zero at H_t = 2.3456 and is negative up to 3: clamped to 0,
        //    while the exact A is positive and <= 0.0037 there (<= 0.004).
        const double root = bisect(fit_branch2, 2.0, 3.0);
        CHECK(root == rollgap::test::approx(2.3456).epsilon(1e-4));
        CHECK(paper_fit_contact_ratio(2.34) > 0.0);
        for (int k = 0; k <= 64; ++k) {  // H_t = 2.35 ... 2.99, and 3 itself
            const double H = 2.35 + 0.01 * k;
            CAPTURE(H);
            CHECK(fit_branch2(H) < 0.0);
            CHECK(paper_fit_contact_ratio(H) == 0.0);
            const double exact = ref_contact_of_film(H);
            CHECK(exact > 0.0);
            CHECK(exact <= 0.004);
        }
        CHECK(fit_branch2(3.0) < 0.0);
        CHECK(paper_fit_contact_ratio(3.0) == 0.0);
        CHECK(paper_fit_contact_ratio(3.5) == 0.0);
    }

    TEST_CASE("paper_fit (26) is close to exact where it is not defective") {
        // On (0.5, 2.35] the fit stays within 0.0135 of the exact A (observed max 0.01304, at
        // H_t = 1.5, the end of branch 1; 0.0108 at H_t = 0.5+; on (1.5, 2.35] within 0.0037).
        double max_dev = 0.0;
        double at = 0.0;
        double max_dev_b2 = 0.0;
        for (int k = 1; k <= 1850; ++k) {
            const double H = 0.5 + 1e-3 * k;
            const double dev = std::abs(paper_fit_contact_ratio(H) - ref_contact_of_film(H));
            if (dev > max_dev) {
                max_dev = dev;
                at = H;
            }
            if (H > 1.5) max_dev_b2 = std::max(max_dev_b2, dev);
        }
        MESSAGE("paper_fit max |fit - exact| on (0.5, 2.35] = "
                << max_dev << " at H_t = " << at << "; on (1.5, 2.35] = " << max_dev_b2);
        CHECK(max_dev <= 0.0135);
        CHECK(max_dev_b2 <= 0.004);
    }

    TEST_CASE("contact_ratio dispatches on the model") {
        for (double H : {0.0, 0.2, 0.49, 0.7, 1.2, 1.5, 1.9, 2.5, 2.9, 3.0, 4.0}) {
            CAPTURE(H);
            CHECK(contact_ratio(ContactModel::christensen_exact, H) ==
                  christensen_contact_ratio(H));
            CHECK(contact_ratio(ContactModel::paper_fit, H) == paper_fit_contact_ratio(H));
        }
        // and the two models really differ there (so the dispatch is observable)
        CHECK(contact_ratio(ContactModel::christensen_exact, 0.2) !=
              contact_ratio(ContactModel::paper_fit, 0.2));
        CHECK(contact_ratio(ContactModel::christensen_exact, 2.5) > 0.0);
        CHECK(contact_ratio(ContactModel::paper_fit, 2.5) == 0.0);
    }

    TEST_CASE("dA/dH_t (the bite sensitivities' slope) against central differences of A") {
        // Exact model: against the quadrature reference A(H_t) (a bisection inverse on the
        // quadrature), step d = 1e-5: truncation d^2 |A3| / 6 (A3 the third derivative, ~1e3 at
        // H_t = 0.05, where A ~ 1 - c H_t^(4/5): ~2e-8) and the reference's rounding ~1e-14 / d
        // = 1e-9; 1e-7 covers both. Paper fit: its own polynomials, away from the jumps at 0.5
        // and 1.5 and the clamp from 2.35.
        const double d = 1e-5;
        double worst = 0.0;
        for (int k = 1; k < 59; ++k) {
            const double H = 0.05 * k;
            CAPTURE(H);
            const ContactRatioAndSlope exact =
                contact_ratio_and_slope(ContactModel::christensen_exact, H);
            CHECK(exact.ratio == christensen_contact_ratio(H));
            const double fd = (ref_contact_of_film(H + d) - ref_contact_of_film(H - d)) / (2 * d);
            worst = std::max(worst, std::abs(exact.slope - fd));
            CHECK(std::abs(exact.slope - fd) <= 1e-7);
            CHECK(exact.slope < 0.0);  // contact falls as the film thickens
            const ContactRatioAndSlope fit = contact_ratio_and_slope(ContactModel::paper_fit, H);
            CHECK(fit.ratio == paper_fit_contact_ratio(H));
            const bool smooth = std::abs(H - 0.5) > 2 * d && std::abs(H - 1.5) > 2 * d && H < 2.3;
            if (smooth && H > 0.5) {
                const double fit_fd =
                    (paper_fit_contact_ratio(H + d) - paper_fit_contact_ratio(H - d)) / (2 * d);
                CHECK(std::abs(fit.slope - fit_fd) <= 1e-6);
            }
            if (H < 0.5 || H > 2.4) CHECK(fit.slope == 0.0);  // constant or clamped there
        }
        MESSAGE("max |dA/dH_t - central difference of the quadrature A| = " << worst);
        // beyond the range: no contact, no slope; at H_t <= 0 full contact
        CHECK(contact_ratio_and_slope(ContactModel::christensen_exact, 3.5).ratio == 0.0);
        CHECK(contact_ratio_and_slope(ContactModel::christensen_exact, 3.5).slope == 0.0);
        CHECK(contact_ratio_and_slope(ContactModel::christensen_exact, 0.0).ratio == 1.0);
    }

}  // TEST_SUITE
