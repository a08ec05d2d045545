// rho broken into its factors per span at its peak (docs/model.md §12.5): on one span the span's
// own loop is rho itself; the worst input's shares sum to one; the thickness gain is the loop
// matrix's subdiagonal; the receiving stand's compliance at omega -> 0 is its static compliance
// from the natural modes (an independent eigen-decomposition); the bite gains have the signs and
// the size the bite's continuity gives them.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "core/mill/mill.h"
#include "core/mill/mill_model.h"
#include "core/mill/mill_regenerative.h"
#include "core/mill/mill_stability.h"
#include "core/stand_structure.h"
#include "tools/verify_mill/mills.h"
#include "support/approx.h"

namespace mill_margin_factors_test {

using namespace rollgap::core;

struct Analysed {
    MillSteadyState steady;
    std::unique_ptr<MillModel> model;
    TransportTransfer transfer;
    RegenerativeMargin margin;
};

Analysed analyse(const Mill& m) {
    Analysed out;
    out.steady = mill_steady_state(m);
    REQUIRE(out.steady.status == MillSteadyStatus::ok);
    out.model = std::make_unique<MillModel>(m, out.steady);
    const MillModel& model = *out.model;
    out.transfer = transport_transfer(model.linearise(model.equilibrium()));
    REQUIRE(out.transfer.ok);
    out.margin = regenerative_margin(out.transfer);
    REQUIRE(out.margin.ok);
    return out;
}

TEST_CASE("margin factors: one span's own loop is rho, and it carries the whole input") {
    const Mill m = rollgap::tools::mills::two_stand_mill(5.0);
    const Analysed a = analyse(m);
    const std::vector<MarginFactors> f = margin_factors(m, *a.model, a.transfer, a.margin);
    REQUIRE(f.size() == 1);
    MESSAGE("rho " << a.margin.margin << " at " << a.margin.frequency_Hz << " Hz; |M_11| "
                   << f[0].tension_loop_gain);
    CHECK(f[0].tension_loop_gain == rollgap::test::approx(a.margin.margin).epsilon(1e-9));
    CHECK(f[0].worst_input_share == rollgap::test::approx(1.0).epsilon(1e-12));
    CHECK(f[0].thickness_gain == -1.0);  // the last span feeds no span
}

TEST_CASE("margin factors: five stands, shares, the thickness path and the bite's gains") {
    const Mill m = default_mill();
    const Analysed a = analyse(m);
    const std::vector<MarginFactors> f = margin_factors(m, *a.model, a.transfer, a.margin);
    REQUIRE(f.size() == 4);
    const Eigen::MatrixXcd direct =
        a.transfer.at({0.0, 2.0 * std::numbers::pi * a.margin.frequency_Hz});
    double shares = 0.0;
    for (const MarginFactors& x : f) {
        const int i = x.span, k = i + 1;  // the receiving stand
        CAPTURE(i);
        shares += x.worst_input_share;
        CHECK(x.tension_loop_gain == rollgap::test::approx(std::abs(direct(i, i))).epsilon(1e-9));
        if (i + 1 < 4)
            CHECK(x.thickness_gain ==
                  rollgap::test::approx(std::abs(direct(i + 1, i))).epsilon(1e-9));
        // a thicker strip entering: more force, a slower entry. With the exit held the bite's
        // continuity u1 y1 = u2 y2 gives du1/dy1 = -u1/y1 + (y2/y1) du2/dy1, and u2 moves only
        // by the forward slip: du1/dy1 lies within 30 % of -u1/y1
        const MillStandState& s = a.steady.stands[static_cast<std::size_t>(k)];
        const double y1 = m.thickness[static_cast<std::size_t>(k)];
        MESSAGE("span " << i + 1 << ": share " << x.worst_input_share << ", |M_ii| "
                        << x.tension_loop_gain << ", dF/dy1 " << x.force_per_entry_thickness * 1e-6
                        << " kN/mm, du1/dy1 " << x.entry_speed_per_entry_thickness << " /s (-u1/y1 "
                        << -s.entry_speed / y1 << "), compliance " << x.compliance * 1e9
                        << " um/kN");
        CHECK(x.force_per_entry_thickness > 0.0);
        CHECK(x.entry_speed_per_entry_thickness < 0.0);
        CHECK(std::abs(x.entry_speed_per_entry_thickness * y1 / s.entry_speed + 1.0) < 0.3);
        CHECK(x.compliance > 0.0);
    }
    CHECK(shares == rollgap::test::approx(1.0).epsilon(1e-12));

    // the compliance as omega -> 0 against the static one from the natural modes of (M, K_s):
    // g^T K_s^-1 g = sum_k (g^T phi_k)^2 / omega_k^2, phi mass-normalised
    RegenerativeMargin still = a.margin;
    still.frequency_Hz = 1e-9;
    const std::vector<MarginFactors> static_factors =
        margin_factors(m, *a.model, a.transfer, still);
    REQUIRE(static_factors.size() == 4);
    const StructureMatrices structure = structure_matrices(m.stands[1].structure);
    const ModalAnalysis modes = modal_analysis(structure, 0.0);
    REQUIRE(modes.ok);
    double compliance = 0.0;
    for (const NaturalMode& mode : modes.natural) {
        const double omega = 2.0 * std::numbers::pi * mode.frequency_Hz;
        compliance += std::pow(gap_direction().dot(mode.shape), 2) / (omega * omega);
    }
    MESSAGE("static compliance " << static_factors[0].compliance * 1e9 << " um/kN, from the modes "
                                 << compliance * 1e9 << " um/kN");
    CHECK(static_factors[0].compliance == rollgap::test::approx(compliance).epsilon(1e-9));
}

}  // namespace mill_margin_factors_test
