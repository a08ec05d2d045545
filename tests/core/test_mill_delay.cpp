// The mill with its nominal transport delays (docs/model.md §12.6), against an independent
// construction: the delays replaced by cascades of k first-order Padé sections, whose state
// matrix's eigenvalues converge to the exact roots as k grows (identity 4 of the specification).
// The count by the argument principle is an integer and equals the cascade's count; Newton's
// roots have residuals below 1e-10.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/mill/mill.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_delay.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_stability.h"
#include "core/stability.h"
#include "tools/verify_mill/mills.h"

namespace mill_delay_test {

using namespace rollgap::core;
using cd = std::complex<double>;

// The last two stands of the default mill with a short span (0.05 m: tau = 3.7 ms, omega tau
// ~ 12 at the rightmost root's 515 Hz, so that 160 Padé sections resolve the delay to 1/s);
// the cascades of tools/verify_mill/mills.h.
using rollgap::tools::mills::pade_closed_loop;
using rollgap::tools::mills::two_stand_mill;

MillLinearisation linearised(const Mill& m) {
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const MillModel model(m, steady);
    const MillLinearisation lin = model.linearise(model.equilibrium());
    REQUIRE(lin.status == DynamicsStatus::ok);
    return lin;
}

TEST_CASE("nominal delays: the Padé cascades converge to the exact roots and count") {
    const MillLinearisation lin = linearised(two_stand_mill(0.05));
    REQUIRE(lin.delay.size() == 1);
    CHECK((lin.output * lin.input).norm() == 0.0);
    CHECK((lin.output * lin.input_rate).norm() == 0.0);
    const TransportTransfer transfer = transport_transfer(lin);
    REQUIRE(transfer.ok);

    const DelayRootCount count = nominal_delay_root_count(transfer, 0.0);
    REQUIRE(count.ok);
    MESSAGE("2 stands, 0.05 m span, tau = "
            << lin.delay[0] * 1e3 << " ms: " << count.count << " roots right of the axis (A0: "
            << count.frozen_right << "), winding off an integer by " << count.integer_error << ", "
            << count.evaluations << " evaluations of F");
    CHECK(count.integer_error < 1e-2);

    // the cascades of 10 .. 160 sections; the exact rightmost root by Newton from the finest
    // one's rightmost eigenvalue
    const auto count_right = [](const Eigen::VectorXcd& values) {
        int right = 0;
        for (Eigen::Index j = 0; j < values.size(); ++j) right += values(j).real() > 0.0 ? 1 : 0;
        return right;
    };
    const std::vector<int> sections{10, 20, 40, 80, 160};
    std::vector<Eigen::VectorXcd> cascades;
    for (int k : sections) {
        cascades.push_back(balanced_eigenvalues(pade_closed_loop(lin, k)));
        REQUIRE(cascades.back().size() > 0);
    }
    Eigen::Index best = 0;
    for (Eigen::Index j = 1; j < cascades.back().size(); ++j)
        if (cascades.back()(j).real() > cascades.back()(best).real()) best = j;
    const DelayRoot exact = delay_root(transfer, cascades.back()(best));
    REQUIRE(exact.converged);
    MESSAGE("rightmost root " << exact.s << " 1/s (" << exact.s.imag() / (2.0 * std::numbers::pi)
                              << " Hz), |F| = " << exact.residual << ", " << exact.iterations
                              << " Newton steps");
    CHECK(exact.residual < 1e-10);

    std::vector<double> errors;
    for (std::size_t c = 0; c < cascades.size(); ++c) {
        double nearest = std::numeric_limits<double>::infinity();
        for (Eigen::Index j = 0; j < cascades[c].size(); ++j)
            nearest = std::min(nearest, std::abs(cascades[c](j) - exact.s));
        errors.push_back(nearest);
        MESSAGE("Padé cascade of " << sections[c] << " sections: nearest root " << nearest
                                   << " 1/s from the exact one; " << count_right(cascades[c])
                                   << " roots right of the axis");
        CHECK(count_right(cascades[c]) == count.count);
        if (c > 0) CHECK(nearest < errors[c - 1]);
    }
    // the first-order section's phase error is O((omega h)^3) a section, so the root moves as
    // h^2: halving h quarters the error once the cascade resolves the delay
    const double ratio = errors[errors.size() - 2] / errors.back();
    MESSAGE("last halving: error ratio " << ratio);
    CHECK(ratio > 3.5);
    CHECK(ratio < 4.5);

    // the analysis at one speed finds the same rightmost root from the count's dips and A0's
    // poles
    const MillSpeedStability at = mill_stability_at(two_stand_mill(0.05));
    REQUIRE(at.rightmost.found);
    CHECK(std::abs(at.rightmost.root.s - exact.s) < 1e-8 * std::abs(exact.s));
    CHECK(at.nominal.count == count.count);
    CHECK_FALSE(at.nominal_stable);
    CHECK_FALSE(at.delay_independent_stable);  // unstable with its delays: rho >= 1 somewhere
    CHECK(at.margin.margin >= 1.0);

    // alpha to the right of the rightmost root: nothing left to count
    const DelayRootCount beyond = nominal_delay_root_count(transfer, exact.s.real() + 1e-3);
    REQUIRE(beyond.ok);
    CHECK(beyond.count == 0);
    const DelayRootCount before = nominal_delay_root_count(transfer, exact.s.real() - 1e-3);
    REQUIRE(before.ok);
    CHECK(before.count >= 2);  // the root and its conjugate
}

TEST_CASE("nominal delays: one stand has no transport, and the count is A0's") {
    Mill m = two_stand_mill(0.25);
    m.stands.resize(1);
    m.thickness.resize(2);
    m.span_length.clear();
    m.interstand_tension.clear();
    m.exit_tension = default_mill().interstand_tension[3];
    const TransportTransfer transfer = transport_transfer(linearised(m));
    REQUIRE(transfer.ok);
    CHECK(transfer.spans() == 0);
    const DelayRootCount count = nominal_delay_root_count(transfer, 0.0);
    CHECK(count.ok);
    CHECK(count.count == count.frozen_right);
    CHECK(delay_characteristic(transfer, {1.0, 600.0}) == cd(1.0, 0.0));
}

}  // namespace mill_delay_test

namespace mill_delay_test {

TEST_CASE("nominal delays: the default mill's rightmost root has nothing to its right") {
    const MillSpeedStability at = mill_stability_at(default_mill());
    REQUIRE(at.nominal.ok);
    REQUIRE(at.rightmost.found);
    const cd s = at.rightmost.root.s;
    MESSAGE("default mill at 15 m/s: " << at.nominal.count << " roots right of the axis (A0: "
                                       << at.nominal.frozen_right << "), rightmost " << s
                                       << " 1/s at " << s.imag() / (2.0 * std::numbers::pi)
                                       << " Hz; rho = " << at.margin.margin);
    CHECK(at.rightmost.root.residual < 1e-10);
    CHECK(at.rightmost.verified);
    const MillLinearisation lin = linearised(default_mill());
    const TransportTransfer transfer = transport_transfer(lin);
    const DelayRootCount beyond = nominal_delay_root_count(transfer, s.real() + 1e-3);
    REQUIRE(beyond.ok);
    CHECK(beyond.count == 0);
    if (s.real() > 0.0) {
        CHECK_FALSE(at.nominal_stable);
        CHECK(at.nominal.count >= 2);
    }
}

}  // namespace mill_delay_test

// The band 0 < Im s < Omega (docs/model.md §12.7): the roots the model's range admits, counted by
// the argument principle on a rectangle. Each case takes under 10 s in Release and under a minute
// under ASan.
namespace mill_delay_test {

Mill at_speed(Mill m, double speed) {
    m.speed = speed;
    return m;
}

// The top of the model's range at the mill's steady state: the largest frequency at which every
// span's spring law and every stand's quasi-static bite are valid (both errors grow with f), by
// bisection.
double valid_frequency_Hz(const Mill& m) {
    const MillSteadyState steady = mill_steady_state(m);
    REQUIRE(steady.status == MillSteadyStatus::ok);
    const auto valid = [&](double f) { return crossing_validity(m, steady, f).valid(); };
    double lo = 0.0, hi = 1.0;
    while (valid(hi)) {
        lo = hi;
        hi *= 2.0;
        REQUIRE(hi < 1e7);
    }
    for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (valid(mid) ? lo : hi) = mid;
    }
    return lo;
}

// The real roots of chi = det(sI - A0) F(s) in (a, b), by the sign changes of chi on a fine grid
// (chi is real there: its sign is that of F times (x - lambda) over A0's real poles). Roots of
// even multiplicity are not seen; generically there are none.
int real_roots(const TransportTransfer& transfer, double a, double b, int n = 20000) {
    const auto sign = [&](double x) {
        double sgn = delay_characteristic(transfer, {x, 0.0}).real() >= 0.0 ? 1.0 : -1.0;
        for (Eigen::Index k = 0; k < transfer.poles.size(); ++k)
            if (transfer.poles(k).imag() == 0.0 && x < transfer.poles(k).real()) sgn = -sgn;
        return sgn;
    };
    int changes = 0;
    double last = sign(a);
    for (int k = 1; k <= n; ++k) {
        const double now = sign(a + (b - a) * k / n);
        if (now != last) ++changes;
        last = now;
    }
    return changes;
}

TEST_CASE("band count: above every root's frequency it is the line's count of oscillatory roots") {
    // the line's count = 2 x the upper band's (the conjugates) + the real roots right of the
    // axis, which the band leaves out (they lie below its bottom edge)
    for (const Mill& m : {two_stand_mill(0.05), at_speed(two_stand_mill(0.25), 10.0),
                          default_mill(), at_speed(default_mill(), 5.0)}) {
        const TransportTransfer transfer = transport_transfer(linearised(m));
        REQUIRE(transfer.ok);
        const DelayRootCount line = nominal_delay_root_count(transfer, 0.0);
        REQUIRE(line.ok);
        const BandRootCount band = band_root_count(transfer, 1e6);
        REQUIRE(band.ok);
        const int real = real_roots(transfer, band.alpha, band.right);
        MESSAGE(m.size() << " stands at " << m.speed << " m/s: line " << line.count
                         << " (A0: " << line.frozen_right << "), band to 1e6 1/s " << band.count
                         << " (A0 inside: " << band.frozen_inside << ", right edge " << band.right
                         << " 1/s, off an integer by " << band.integer_error << ", "
                         << band.evaluations << " evaluations), real roots " << real);
        CHECK(band.integer_error < 1e-2);
        CHECK(line.count == 2 * band.count + real);
    }
}

TEST_CASE("band count: two stands, every root Newton finds in the band is counted, no more") {
    for (const Mill& m : {two_stand_mill(0.05), at_speed(two_stand_mill(0.05), 8.0),
                          at_speed(two_stand_mill(0.25), 20.0)}) {
        const TransportTransfer transfer = transport_transfer(linearised(m));
        REQUIRE(transfer.ok);
        double tau_max = 0.0;
        for (double tau : transfer.delay) tau_max = std::max(tau_max, tau);
        const double f_valid = valid_frequency_Hz(m);
        for (double omega_max :
             {2.0 * std::numbers::pi * f_valid, 2.0 * std::numbers::pi * 2000.0}) {
            const BandRootCount band = band_root_count(transfer, omega_max);
            REQUIRE(band.ok);
            // Newton from a dense set of starts over the rectangle: columns across [0, right]
            // (12 equal ones and a doubling series from 1/4 1/s), rows half a radian of the
            // longest delay's phase apart and at most Omega / 250
            std::vector<cd> roots;
            std::vector<double> columns;
            for (int i = 0; i < 12; ++i) columns.push_back(band.right * (i + 0.5) / 12);
            for (double x = 0.25; x < band.right; x *= 2.0) columns.push_back(x);
            const double row = std::min(omega_max / 250.0, 0.5 / tau_max);
            int starts = 0;
            for (double x : columns) {
                for (double w = 0.5 * row; w < omega_max; w += row) {
                    ++starts;
                    const DelayRoot r = delay_root(transfer, {x, w});
                    if (!r.converged || !(r.residual < 1e-8)) continue;
                    if (!(r.s.real() > band.alpha) || !(r.s.imag() > band.epsilon) ||
                        !(r.s.imag() < band.omega_max))
                        continue;
                    const bool known = std::any_of(roots.begin(), roots.end(), [&](cd q) {
                        return std::abs(q - r.s) <= 1e-6 * std::max(1.0, std::abs(r.s));
                    });
                    if (!known) roots.push_back(r.s);
                }
            }
            std::string listed;
            for (cd r : roots) {
                std::ostringstream o;
                o << " " << r << " (" << r.imag() / (2.0 * std::numbers::pi) << " Hz)";
                listed += o.str();
            }
            MESSAGE("2 stands, span " << m.span_length[0] << " m at " << m.speed << " m/s, band to "
                                      << omega_max / (2.0 * std::numbers::pi) << " Hz (valid to "
                                      << f_valid << " Hz): count " << band.count << " ("
                                      << band.evaluations << " evaluations); Newton from " << starts
                                      << " starts:" << listed);
            CHECK(band.count == static_cast<int>(roots.size()));
            // the band's rightmost root is the rightmost Newton found in it
            const RightmostDelayRoot rightmost = band_rightmost_root(transfer, band);
            if (!roots.empty()) {
                REQUIRE(rightmost.found);
                CHECK(rightmost.verified);
                double best = -std::numeric_limits<double>::infinity();
                for (cd r : roots) best = std::max(best, r.real());
                CHECK(std::abs(rightmost.root.s.real() - best) <=
                      1e-8 * std::abs(rightmost.root.s));
            }
        }
    }
}

TEST_CASE("band count: the default mill's valid roots at 15 m/s and at 5 m/s") {
    // at 15 m/s (README example 4): the rightmost root, at 105 Hz inside the model's range,
    // grows at 4.5 /s
    {
        const Mill m = default_mill();
        const double f_valid = valid_frequency_Hz(m);
        const TransportTransfer transfer = transport_transfer(linearised(m));
        const BandRootCount band = band_root_count(transfer, 2.0 * std::numbers::pi * f_valid);
        REQUIRE(band.ok);
        const RightmostDelayRoot rightmost = band_rightmost_root(transfer, band);
        REQUIRE(rightmost.found);
        const cd s = rightmost.root.s;
        MESSAGE("default mill at 15 m/s, valid to "
                << f_valid << " Hz: " << band.count << " roots in the band (" << band.evaluations
                << " evaluations), rightmost " << s << " 1/s at "
                << s.imag() / (2.0 * std::numbers::pi) << " Hz; " << rightmost.starts
                << " Newton runs, " << rightmost.counts << " counts");
        CHECK(band.count > 0);
        CHECK(rightmost.verified);
        CHECK(rightmost.root.residual < 1e-10);
        CHECK(std::abs(s.imag() / (2.0 * std::numbers::pi) - 105.0) < 0.5);
        CHECK(std::abs(s.real() - 4.5) < 0.05);
        // the whole line's rightmost root is this one
        const MillSpeedStability at = mill_stability_at(m);
        REQUIRE(at.rightmost.found);
        CHECK(std::abs(at.rightmost.root.s - s) < 1e-8 * std::abs(s));
    }
    // at 5 m/s only roots outside the range grow: the band count is zero, the line's is not
    {
        const Mill m = at_speed(default_mill(), 5.0);
        const double f_valid = valid_frequency_Hz(m);
        const TransportTransfer transfer = transport_transfer(linearised(m));
        const DelayRootCount line = nominal_delay_root_count(transfer, 0.0);
        REQUIRE(line.ok);
        const BandRootCount band = band_root_count(transfer, 2.0 * std::numbers::pi * f_valid);
        REQUIRE(band.ok);
        const RightmostDelayRoot rightmost = band_rightmost_root(transfer, band);
        const RightmostDelayRoot anywhere = rightmost_delay_root(transfer, line);
        REQUIRE(anywhere.found);
        MESSAGE("default mill at 5 m/s, valid to "
                << f_valid << " Hz: band " << band.count << ", line " << line.count
                << "; rightmost anywhere " << anywhere.root.s << " 1/s at "
                << anywhere.root.s.imag() / (2.0 * std::numbers::pi) << " Hz, in the band "
                << rightmost.root.s << " 1/s at "
                << rightmost.root.s.imag() / (2.0 * std::numbers::pi) << " Hz");
        CHECK(band.count == 0);
        CHECK(line.count > 0);
        CHECK(anywhere.root.s.imag() > 2.0 * std::numbers::pi * f_valid);  // outside the range
        if (rightmost.found) {
            CHECK(rightmost.verified);
            CHECK(rightmost.root.s.real() < 0.0);
        }
    }
}

}  // namespace mill_delay_test
