// The slab equation under the Coulomb verification law against published numbers (docs/model.md
// §4): a textbook problem (FOSSEE Scilab port 3250/CH3/EX3.2, Bland-Ford numerics) and Hill's
// formula.

#include <doctest/doctest.h>

#include <cmath>

#include "core/roll_bite.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace {

Scenario textbook_strip(double mu, double reduction) {
    Scenario s;
    s.strip.entry_thickness = 6.0e-3;
    s.strip.reduction = reduction;
    s.rolls.radius = 0.200;       // 400 mm diameter
    s.strip.flow_stress = 750e6;  // 2k
    s.strip.width = 0.150;
    s.friction.model = FrictionModel::coulomb;
    s.friction.coulomb_coefficient = mu;
    s.tensions.back.stress = 0.0;
    s.tensions.front.stress = 0.0;
    return s;
}

}  // namespace

TEST_CASE("textbook anchor: 6.0 -> 4.8 mm, D = 400 mm, 2k = 750 MPa, mu = 0.1, w = 150 mm") {
    const Scenario s = textbook_strip(0.1, 0.2);
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    CHECK(r.force == rollgap::test::approx(1912.6e3).epsilon(1e-3));  // this slab equation
    CHECK(r.force == rollgap::test::approx(1908e3).epsilon(5e-3));    // the textbook's answer
}

TEST_CASE("Hill's formula agrees within a few per cent over friction and reduction") {
    for (double mu : {0.05, 0.08, 0.1, 0.15}) {
        for (double reduction : {0.1, 0.2, 0.3}) {
            CAPTURE(mu);
            CAPTURE(reduction);
            const Scenario s = textbook_strip(mu, reduction);
            const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
            REQUIRE(r.status == BiteStatus::ok);
            const double y1 = s.strip.entry_thickness, y2 = exit_thickness(s), a = s.rolls.radius;
            const double hill =
                s.strip.width * s.strip.flow_stress * std::sqrt(a * (y1 - y2)) *
                (1.08 + 1.79 * mu * reduction * std::sqrt(1 - reduction) * std::sqrt(a / y2) -
                 1.02 * reduction);
            CHECK(r.force == rollgap::test::approx(hill).epsilon(0.03));
        }
    }
}

TEST_CASE("the Coulomb friction hill: tau = mu p, pressure peaks at the neutral point") {
    const Scenario s = textbook_strip(0.1, 0.2);
    const BiteResult r = solve_roll_bite(s, steady_bite_state(s));
    REQUIRE(r.status == BiteStatus::ok);
    double peak = 0.0, peak_x = 0.0;
    for (const BitePoint& p : r.distribution) {
        CHECK(std::abs(p.friction) == rollgap::test::approx(0.1 * p.pressure).epsilon(1e-14));
        if (p.pressure > peak) {
            peak = p.pressure;
            peak_x = p.x;
        }
    }
    CHECK(peak_x == rollgap::test::approx(r.neutral_point).epsilon(1e-12));
    // more friction, a higher friction hill
    const Scenario more = textbook_strip(0.15, 0.2);
    CHECK(solve_roll_bite(more, steady_bite_state(more)).force > r.force);
}
