// The inlet film (paper eqs. 2-11, docs/model.md §2), checked against independent references:
// adaptive quadrature of I2's defining integral, the steady Reynolds-Barus inlet solved by
// quadrature + bisection, and finite differences for the linear structure of eq. (11).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/inlet_film.h"
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

// docs/model.md §8 defaults, SI.
constexpr double kA = 0.280;       // roll radius a, m
constexpr double kY1 = 1.6e-3;     // entry thickness, m
constexpr double kR = 0.15;        // reduction
constexpr double kEta0 = 5.5e-4;   // Pa s
constexpr double kGamma = 1.7e-6;  // 1/Pa
constexpr double kSigma = 380e6;   // Pa
constexpr double kSb = 18e6;       // Pa
constexpr double kU1bar = 17.6;    // m/s, (u1 + v)/2 at the default 19 m/s
const double kTheta = std::sqrt((kY1 - kY1 * (1.0 - kR)) / kA);  // sqrt((y1 - y2)/a)

// I2 = int_0^inf x^2 / h1^3 dx, h1 = h0 + theta x + x^2/(2a), by quadrature in u = ln x:
//   I2 = int_{-inf}^{inf} x^3 / h1^3 du = int 1 / (h0/x + theta + x/(2a))^3 du,
// split at u0 = ln x0 (x0 = where h1 stops being ~h0) into two semi-infinite integrals. The log
// map makes the ~1/x stretch between h0/theta and 2a theta (up to ~24 e-folds here) smooth.
double ref_I2(double a, double theta, double h0, double rel_tol = 1e-14) {
    auto g = [&](double u) {
        const double x = std::exp(u);
        const double q = h0 / x + theta + x / (2.0 * a);
        return 1.0 / (q * q * q);  // 0 at both ends, no inf * 0
    };
    const double x0 = std::min(h0 / theta, std::sqrt(2.0 * a * h0));
    const double u0 = std::log(x0);
    const double span =
        std::max(1.0, std::log(std::max(2.0 * a * theta, std::sqrt(2.0 * a * h0)) / x0));
    QuadratureOptions o;
    o.rel_tol = rel_tol;
    const auto left = integrate_to_infinity([&](double v) { return g(u0 - v); }, 0.0, 1.0, o);
    const auto right = integrate_to_infinity([&](double v) { return g(u0 + v); }, 0.0, span, o);
    REQUIRE(left.converged);
    REQUIRE(right.converged);
    return left.value + right.value;
}

// The same integral directly in x (x = s t/(1-t)); a second, differently conditioned path used
// to cross-check the reference itself.
double ref_I2_direct(double a, double theta, double h0) {
    QuadratureOptions o;
    o.rel_tol = 1e-13;
    const auto r = integrate_to_infinity(
        [&](double x) {
            const double h = h0 + theta * x + x * x / (2.0 * a);
            return x * x / (h * h * h);
        },
        0.0, h0 / theta, o);
    REQUIRE(r.converged);
    return r.value;
}

// 1 - exp(-x) by libm's expm1 (reference for the pressure factor).
double ref_factor(double gamma, double sigma, double sb) {
    return -std::expm1(-gamma * (sigma - sb));
}

// Steady inlet from the Reynolds equation (1) with Barus (2), phi = exp(-gamma p) (3), the
// wedge h1 = h0 + theta x (4) for the Couette term, no squeeze, Couette flux u1bar h0 at the
// bite entry (p'/eta -> 0 there):  d phi/dx = 12 gamma eta0 u1bar (h1 - h0) / h1^3,
// phi(inf) = 1, phi(0) = exp(-gamma (sigma - s_b)) (8). So h00 solves
//   12 gamma eta0 u1bar int_0^inf theta x / (h0 + theta x)^3 dx = 1 - exp(-gamma (sigma - s_b)),
// found here by quadrature + bisection on ln h0 (no closed form used).
double ref_steady_film(double eta0, double gamma, double u1bar, double theta, double sigma,
                       double sb) {
    const double target = ref_factor(gamma, sigma, sb);
    auto residual = [&](double log_h0) {
        const double h0 = std::exp(log_h0);
        QuadratureOptions o;
        o.rel_tol = 1e-14;
        const auto r = integrate_to_infinity(
            [&](double x) {
                const double h = h0 + theta * x;
                return theta * x / (h * h * h);
            },
            0.0, h0 / theta, o);
        REQUIRE(r.converged);
        return 12.0 * gamma * eta0 * u1bar * r.value - target;  // decreasing in h0
    };
    return std::exp(bisect(residual, std::log(1e-15), std::log(1.0)));
}

struct Lube {
    double eta0, gamma, u1bar, theta, sigma, sb;
};

// Default plus variants where the pressure factor 1 - e^{-gamma(sigma - s_b)} is not 1.
std::vector<Lube> lubes() {
    return {
        {kEta0, kGamma, kU1bar, kTheta, kSigma, kSb},      // gamma (sigma - s_b) = 615
        {kEta0, 1.7e-8, kU1bar, kTheta, kSigma, kSb},      // 6.15, oil-typical gamma
        {kEta0, kGamma, kU1bar, kTheta, kSigma, 379.5e6},  // 0.85
        {0.03, 2e-8, 2.0, 0.05, 500e6, 100e6},             // 8, neat oil, slow
        {kEta0, 1.7e-8, 5.0, 0.01, kSigma, kSigma - 1e6},  // 0.017
    };
}

InletFilmInputs inputs(const Lube& l, double h0, double theta_dot = 0.0, double gap_rate = 0.0) {
    InletFilmInputs in{};
    in.inlet_film = h0;
    in.inlet_angle = l.theta;
    in.inlet_angle_rate = theta_dot;
    in.gap_rate = gap_rate;
    in.mean_inlet_speed = l.u1bar;
    in.roll_radius = kA;
    in.viscosity = l.eta0;
    in.pressure_viscosity = l.gamma;
    in.flow_stress = l.sigma;
    in.back_tension = l.sb;
    return in;
}

double ww(const Lube& l) {
    return wilson_walowit_film(l.eta0, l.gamma, l.u1bar, l.theta, l.sigma, l.sb);
}

}  // namespace

TEST_SUITE("inlet_film") {
    TEST_CASE(
        "reference I2: log-map quadrature, direct quadrature and the e = 0 closed form agree") {
        // At e = a theta^2 - 2 h0 = 0, h1 = (x + a theta)^2 / (2a) and
        // I2 = 8 a^3 int x^2/(x + a theta)^6 dx = 8 a^3 B(3,3) / (a theta)^3 = 4 / (15 theta^3).
        for (double theta : {0.005, kTheta, 0.15}) {
            const double h0 = kA * theta * theta / 2.0;
            CAPTURE(theta);
            CHECK(std::abs(ref_I2(kA, theta, h0) / (4.0 / (15.0 * theta * theta * theta)) - 1.0) <=
                  1e-13);
        }
        for (double h0 : {3.4e-6, 1e-7, 1e-4, 1e-3}) {
            CAPTURE(h0);
            CHECK(std::abs(ref_I2_direct(kA, kTheta, h0) / ref_I2(kA, kTheta, h0) - 1.0) <= 1e-12);
        }
    }

    TEST_CASE("I2 closed form at the default scenario: ~8.77e4, and equal to quadrature") {
        const double h0 = 3.4e-6;
        const double ref = ref_I2(kA, kTheta, h0);
        CHECK(std::abs(ref / 8.77e4 - 1.0) <=
              6e-4);  // docs/model.md §2 quotes 3 digits (87709 here)
        const double got = inlet_integral_I2(kA, kTheta, h0);
        CAPTURE(ref);
        CAPTURE(got);
        CHECK(std::abs(got / ref - 1.0) <= 1e-9);
    }

    TEST_CASE("I2 closed form against quadrature over e > 0, e < 0 and e ~ 0") {
        // h0 = (a theta^2 / 2) r: r < 1 is e > 0 (log branch), r > 1 is e < 0 (atan branch), and
        // r = 1 +- 1e-2 ... 1e-9 and r = 1 straddle the series branch and wherever the
        // implementation switches to it (the closed form loses ~1/(r-1)^2 of its digits there).
        const std::vector<double> ratios = {1e-10,    1e-8,     1e-6,     1e-4,  1e-2,     0.1,
                                            0.5,      0.9,      0.99,     0.999, 1 - 1e-4, 1 - 1e-5,
                                            1 - 1e-6, 1 - 1e-7, 1 - 1e-9, 1.0,   1 + 1e-9, 1 + 1e-7,
                                            1 + 1e-6, 1 + 1e-5, 1 + 1e-4, 1.001, 1.01,     1.1,
                                            2.0,      10.0,     1e3,      1e6};
        double max_rel = 0.0;
        double worst_r = 0.0;
        for (double a : {0.1, kA, 0.6}) {
            for (double theta : {0.005, kTheta, 0.15}) {
                for (double r : ratios) {
                    const double h0 = a * theta * theta / 2.0 * r;
                    CAPTURE(a);
                    CAPTURE(theta);
                    CAPTURE(r);
                    CAPTURE(h0);
                    const double ref = ref_I2(a, theta, h0);
                    const double got = inlet_integral_I2(a, theta, h0);
                    CAPTURE(ref);
                    CAPTURE(got);
                    REQUIRE(std::isfinite(got));
                    const double rel = std::abs(got / ref - 1.0);
                    if (rel > max_rel) {
                        max_rel = rel;
                        worst_r = r;
                    }
                    CHECK(rel <= 1e-9);
                }
            }
        }
        MESSAGE("I2: max relative error vs quadrature = " << max_rel << " (at r = " << worst_r
                                                          << ")");
    }

    TEST_CASE("inlet_pressure_factor: 1 - exp(-gamma (sigma - s_b))") {
        // Large gamma (sigma - s_b): -> 1 (615 at the defaults).
        CHECK(inlet_pressure_factor(kGamma, kSigma, kSb) ==
              rollgap::test::approx(1.0).epsilon(1e-15));
        CHECK(inlet_pressure_factor(1.7e-8, kSigma, kSb) ==
              rollgap::test::approx(ref_factor(1.7e-8, kSigma, kSb)).epsilon(1e-14));  // 6.15
        CHECK(inlet_pressure_factor(1e-6, 60e6, 10e6) ==
              rollgap::test::approx(1.0).epsilon(1e-15));  // 50
        // Small x = gamma (sigma - s_b): ~ x (1 - x/2). Tolerance from the documented formula's
        // conditioning: 1 - exp(-x) computed as written has an absolute error <= ~2u (exp rounds
        // within 1 ulp near 1, the subtraction is exact), i.e. a relative error 2u / x; -expm1
        // would be exact to ~u.
        for (double x : {1e-2, 1e-4, 1e-6, 1e-9}) {
            const double gamma = 1.7e-8;
            const double sb = kSigma - x / gamma;
            const double xx = gamma * (kSigma - sb);  // the x actually represented
            CAPTURE(x);
            const double f = inlet_pressure_factor(gamma, kSigma, sb);
            CHECK(std::abs(f / ref_factor(gamma, kSigma, sb) - 1.0) <=
                  1e-13 + 4.0 * unit_roundoff / xx);
            CHECK(std::abs(f / xx - 1.0) <= 0.5 * xx * 1.0001 + 1e-13 + 4.0 * unit_roundoff / xx);
        }
        // monotone increasing in gamma (sigma - s_b)
        double prev = 0.0;
        for (double sb = 379.9e6; sb >= 0.0; sb -= 10e6) {
            const double f = inlet_pressure_factor(1.7e-8, kSigma, sb);
            CHECK(f > prev);
            prev = f;
        }
    }

    TEST_CASE("Wilson-Walowit film = the steady inlet of the Reynolds-Barus equation") {
        // Independent route: quadrature of the steady inlet pressure equation + bisection.
        for (const Lube& l : lubes()) {
            CAPTURE(l.gamma);
            CAPTURE(l.sb);
            CAPTURE(l.u1bar);
            const double ref = ref_steady_film(l.eta0, l.gamma, l.u1bar, l.theta, l.sigma, l.sb);
            const double got = ww(l);
            CAPTURE(ref);
            CAPTURE(got);
            CHECK(std::abs(got / ref - 1.0) <= 1e-10);
        }
    }

    TEST_CASE("steady state of (11): rate vanishes at the Wilson-Walowit film, both models") {
        double max_scaled = 0.0;
        for (const Lube& l : lubes()) {
            CAPTURE(l.gamma);
            CAPTURE(l.sb);
            const double h00 = ww(l);
            const double scale = l.theta * l.u1bar;  // theta u1bar
            for (InletFilmModel m : {InletFilmModel::paper, InletFilmModel::eulerian}) {
                const double rate = inlet_film_rate(m, inputs(l, h00));
                max_scaled = std::max(max_scaled, std::abs(rate) / scale);
                CHECK(std::abs(rate) <= 1e-12 * scale);
            }
            // ... and the root of inlet_film_rate(h0) = 0 found by bisection IS the WW film.
            for (InletFilmModel m : {InletFilmModel::paper, InletFilmModel::eulerian}) {
                auto rate_of = [&](double log_h0) {
                    return inlet_film_rate(m, inputs(l, std::exp(log_h0)));
                };
                CHECK(rate_of(std::log(1e-12)) > 0.0);  // thin film grows
                CHECK(rate_of(std::log(1e-1)) < 0.0);   // thick film shrinks
                const double root = std::exp(bisect(rate_of, std::log(1e-12), std::log(1e-1)));
                CHECK(std::abs(root / h00 - 1.0) <= 1e-12);
                // and the root is the Reynolds reference
                const double ref =
                    ref_steady_film(l.eta0, l.gamma, l.u1bar, l.theta, l.sigma, l.sb);
                CHECK(std::abs(root / ref - 1.0) <= 1e-10);
            }
        }
        MESSAGE("max |dh0/dt at h00| / (theta u1bar) = " << max_scaled);
    }

    TEST_CASE(
        "stable relaxation: d(dh0/dt)/dh0 = -theta^2 (1 - e^{-gamma(sigma-s_b)}) / (6 gamma eta0)") {
        // (11) is affine in h0 when thetadot = 0, so a central difference is exact up to rounding
        // (terms ~ theta u1bar, step 1 % of h0: rounding ~1e-13 relative).
        for (const Lube& l : lubes()) {
            CAPTURE(l.gamma);
            CAPTURE(l.sb);
            const double h00 = ww(l);
            const double want =
                -l.theta * l.theta * ref_factor(l.gamma, l.sigma, l.sb) / (6.0 * l.gamma * l.eta0);
            // the same rate from the independent steady film: -theta u1bar / h00_ref
            const double h00_ref =
                ref_steady_film(l.eta0, l.gamma, l.u1bar, l.theta, l.sigma, l.sb);
            CHECK(std::abs(want / (-l.theta * l.u1bar / h00_ref) - 1.0) <= 1e-10);
            for (InletFilmModel m : {InletFilmModel::paper, InletFilmModel::eulerian}) {
                for (double h0 : {h00, 0.3 * h00, 3.0 * h00}) {
                    const double d = 0.01 * h0;
                    const double fd = (inlet_film_rate(m, inputs(l, h0 + d)) -
                                       inlet_film_rate(m, inputs(l, h0 - d))) /
                                      (2 * d);
                    CHECK(fd < 0.0);
                    CHECK(std::abs(fd / want - 1.0) <= 1e-9);
                }
            }
        }
        // still negative with a moving gap (defaults, thetadot up to +-0.5 1/s, ydot_c +-1 mm/s)
        const Lube l = lubes()[0];
        const double h00 = ww(l);
        for (InletFilmModel m : {InletFilmModel::paper, InletFilmModel::eulerian}) {
            for (double td : {-0.5, 0.5}) {
                for (double yc : {-1e-3, 1e-3}) {
                    const double d = 0.01 * h00;
                    const double fd = (inlet_film_rate(m, inputs(l, h00 + d, td, yc)) -
                                       inlet_film_rate(m, inputs(l, h00 - d, td, yc))) /
                                      (2 * d);
                    CHECK(fd < 0.0);
                }
            }
        }
    }

    TEST_CASE("paper model: d(dh0/dt)/d(thetadot) = -theta^2 h0 I2, independent of the gap rate") {
        double max_rel = 0.0;
        for (const Lube& l : lubes()) {
            const double h00 = ww(l);
            for (double h0 : {h00, 0.3 * h00, 3.0 * h00}) {
                CAPTURE(l.gamma);
                CAPTURE(h0);
                const double want = -l.theta * l.theta * h0 * ref_I2(kA, l.theta, h0);
                // affine in thetadot: central difference exact up to rounding; step 1 1/s
                const double td0 = 0.2;
                const double dt = 1.0;
                const double fd =
                    (inlet_film_rate(InletFilmModel::paper, inputs(l, h0, td0 + dt)) -
                     inlet_film_rate(InletFilmModel::paper, inputs(l, h0, td0 - dt))) /
                    (2 * dt);
                const double rel = std::abs(fd / want - 1.0);
                max_rel = std::max(max_rel, rel);
                CHECK(fd < 0.0);  // a growing inlet angle thins the film
                CHECK(rel <= 1e-9);
                // the paper's (11) has no gap-rate term
                const double base = inlet_film_rate(InletFilmModel::paper, inputs(l, h0, td0, 0.0));
                const double moved =
                    inlet_film_rate(InletFilmModel::paper, inputs(l, h0, td0, 5e-3));
                CHECK(std::abs(moved - base) <= 4.0 * unit_roundoff * l.theta * l.u1bar);
            }
        }
        MESSAGE(
            "paper d/dthetadot: max relative error vs -theta^2 h0 I2(quadrature) = " << max_rel);
    }

    TEST_CASE("eulerian model: d(dh0/dt)/d(ydot_c) = -1/2, independent of thetadot") {
        for (const Lube& l : lubes()) {
            const double h00 = ww(l);
            for (double h0 : {h00, 0.3 * h00, 3.0 * h00}) {
                CAPTURE(l.gamma);
                CAPTURE(h0);
                const double yc0 = 2e-4;
                const double d = 1e-3;  // m/s
                const double fd =
                    (inlet_film_rate(InletFilmModel::eulerian, inputs(l, h0, 0.0, yc0 + d)) -
                     inlet_film_rate(InletFilmModel::eulerian, inputs(l, h0, 0.0, yc0 - d))) /
                    (2 * d);
                CHECK(std::abs(fd + 0.5) <= 1e-10);
                const double base =
                    inlet_film_rate(InletFilmModel::eulerian, inputs(l, h0, 0.0, yc0));
                for (double td : {-3.0, 0.7, 50.0}) {
                    const double moved =
                        inlet_film_rate(InletFilmModel::eulerian, inputs(l, h0, td, yc0));
                    CHECK(std::abs(moved - base) <= 4.0 * unit_roundoff * l.theta * l.u1bar);
                }
            }
        }
    }

    TEST_CASE("both models: d(dh0/dt)/d(u1bar) = theta, and they coincide without motion") {
        for (const Lube& l : lubes()) {
            const double h00 = ww(l);
            for (double h0 : {h00, 0.3 * h00, 3.0 * h00}) {
                CAPTURE(l.gamma);
                CAPTURE(h0);
                const double p = inlet_film_rate(InletFilmModel::paper, inputs(l, h0));
                const double e = inlet_film_rate(InletFilmModel::eulerian, inputs(l, h0));
                CHECK(std::abs(p - e) <=
                      4.0 * unit_roundoff * l.theta * l.u1bar * (1.0 + h0 / h00));
                for (InletFilmModel m : {InletFilmModel::paper, InletFilmModel::eulerian}) {
                    Lube lp = l;
                    Lube lm = l;
                    const double du = 0.01 * l.u1bar;
                    lp.u1bar += du;
                    lm.u1bar -= du;
                    const double fd =
                        (inlet_film_rate(m, inputs(lp, h0)) - inlet_film_rate(m, inputs(lm, h0))) /
                        (2 * du);
                    CHECK(std::abs(fd / l.theta - 1.0) <= 1e-10);
                }
            }
        }
    }

    TEST_CASE("default-scenario anchor: h00 ~ 3.4 um at u1bar ~ 17.6 m/s (docs/model.md §8)") {
        const double h00 = wilson_walowit_film(kEta0, kGamma, kU1bar, kTheta, kSigma, kSb);
        CAPTURE(h00);
        CHECK(h00 ==
              rollgap::test::approx(3.4e-6).epsilon(0.03));  // 3.372e-6 from the quadrature route
        CHECK(std::abs(h00 / ref_steady_film(kEta0, kGamma, kU1bar, kTheta, kSigma, kSb) - 1.0) <=
              1e-10);
        // and the film is the mixed regime for Rq = 2 um: H_t = h00 / Rq in [0.5, 3]
        CHECK(h00 / 2e-6 > 0.5);
        CHECK(h00 / 2e-6 < 3.0);
    }

}  // TEST_SUITE
