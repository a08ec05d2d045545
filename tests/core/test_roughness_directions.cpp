// The paper's Section 6.2 claims, checked as directions on the steady bite (docs/model.md §9):
// compressive stress rises with roughness, more so at high back tension; friction stress is very
// sensitive to roughness. Rq = 1 and 6 um as in Figs. 14-15; back tension 18 +- 9 MPa.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "core/roll_bite.h"

using namespace rollgap::core;

namespace {

struct Peaks {
    double force, pressure, friction;
};

Peaks peaks(double rq, double back_tension) {
    Scenario s;
    s.roughness.roll_rq = rq;
    s.roughness.strip_rq = 0.0;
    BiteState state = steady_bite_state(s);
    state.back_tension = back_tension;
    const BiteResult r = solve_roll_bite(s, state);
    REQUIRE(r.status == BiteStatus::ok);
    Peaks p{r.force, 0.0, 0.0};
    for (const BitePoint& b : r.distribution) {
        p.pressure = std::max(p.pressure, b.pressure);
        p.friction = std::max(p.friction, std::abs(b.friction));
    }
    return p;
}

}  // namespace

TEST_CASE("compressive stress rises with roughness, at every back tension of the cycle") {
    for (double sb : {27e6, 18e6, 9e6}) {
        CAPTURE(sb);
        const Peaks smooth = peaks(1e-6, sb), rough = peaks(6e-6, sb);
        CHECK(rough.pressure > smooth.pressure);
        CHECK(rough.force > smooth.force);
    }
}

TEST_CASE("the roughness effect on the force is larger at high back tension than at low") {
    const double high = peaks(6e-6, 27e6).force - peaks(1e-6, 27e6).force;
    const double low = peaks(6e-6, 9e6).force - peaks(1e-6, 9e6).force;
    CHECK(high > low);
}

TEST_CASE("friction stress is very sensitive to roughness") {
    const Peaks smooth = peaks(1e-6, 18e6), rough = peaks(6e-6, 18e6);
    // more asperity contact (A) at the same film: the friction at least doubles
    CHECK(rough.friction > 2.0 * smooth.friction);
}
