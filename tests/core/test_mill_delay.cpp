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
#include <vector>

#include "core/mill/mill.h"
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
