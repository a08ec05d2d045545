// Chatter type (docs/model.md, "Chatter type"): synthetic mode shapes of known kind, stacks
// built so that only one kind of vibration can exist, and the coupled model's own crossings.

#include <cmath>
#include <complex>

#include <doctest/doctest.h>

#include "core/chatter_type.h"
#include "core/stand_structure.h"
#include "core/stability.h"
#include "core/sweep.h"
#include "support/pool_control.h"
#include "support/approx.h"

using namespace rollgap::core;

namespace {

Vector6c shape_of(std::initializer_list<std::complex<double>> q) {
    Vector6c v;
    int i = 0;
    for (auto value : q) v(i++) = value;
    return v;
}

Vector6c real_shape(const Vector6& q) { return q.cast<std::complex<double>>(); }

// The natural mode of the stack nearest to `frequency_Hz`, with the strip spring k4.
NaturalMode nearest_mode(const StandStructure& mill, double strip_stiffness, double frequency_Hz) {
    const ModalAnalysis modal = modal_analysis(structure_matrices(mill), strip_stiffness);
    REQUIRE(modal.natural.size() == 6);
    NaturalMode best = modal.natural.front();
    for (const NaturalMode& m : modal.natural) {
        if (std::abs(m.frequency_Hz - frequency_Hz) < std::abs(best.frequency_Hz - frequency_Hz))
            best = m;
    }
    return best;
}

}  // namespace

TEST_CASE(
    "synthetic shapes: the roll packages against each other are third-octave, work rolls against back-up rolls fifth-octave") {
    // upper half down, lower half up, each work roll riding on its back-up roll
    const Vector6c stack = shape_of({-0.8, -1.0, -0.45, 0.45, 1.0, 0.8});
    const ChatterClassification third = classify_chatter(stack, 104.0);
    CHECK(third.type == ChatterType::third_octave);
    CHECK(third.band == ChatterType::third_octave);
    CHECK(third.agrees());
    CHECK(third.shape.gap_opening == rollgap::test::approx(1.0));
    CHECK(third.shape.work_roll_motion == rollgap::test::approx(0.45));
    CHECK(third.shape.backup_follow == rollgap::test::approx(1.0 / 0.45));

    // the work rolls move against each other and against nearly still back-up rolls
    const Vector6c rolls = shape_of({0.0, 0.09, -1.0, 1.0, -0.09, 0.0});
    const ChatterClassification fifth = classify_chatter(rolls, 600.0);
    CHECK(fifth.type == ChatterType::fifth_octave);
    CHECK(fifth.band == ChatterType::fifth_octave);
    CHECK(fifth.shape.backup_follow == rollgap::test::approx(-0.09));

    // both work rolls together against their back-up rolls: the gap keeps its size
    CHECK(classify_chatter(shape_of({0.06, -0.22, 1.0, 1.0, -0.22, 0.06}), 313.0).type ==
          ChatterType::other);
    // the whole stack as one body
    CHECK(classify_chatter(shape_of({0.6, 0.95, 1.0, 1.0, 0.95, 0.6}), 64.0).type ==
          ChatterType::other);
    // a crosshead against its back-up roll, the work rolls almost still
    CHECK(classify_chatter(shape_of({1.0, -0.3, -0.05, 0.04, 0.0, 0.0}), 200.0).type ==
          ChatterType::other);
    // no shape at all (a non-oscillatory eigenvalue)
    CHECK(classify_chatter(Vector6c::Zero(), 0.0).type == ChatterType::other);
}

TEST_CASE(
    "the type depends on the relative motion only: a common complex factor does not change it") {
    const Vector6c base =
        shape_of({{-0.79, 0.02}, -1.0, {-0.44, -0.08}, {0.44, 0.07}, 1.0, {0.79, -0.03}});
    const ChatterClassification reference = classify_chatter(base, 104.0);
    for (double phase : {0.3, 1.7, 3.1, -2.2}) {
        const Vector6c turned = base * std::polar(3.5e-6, phase);
        const ChatterClassification c = classify_chatter(turned, 104.0);
        CHECK(c.type == reference.type);
        CHECK(c.shape.gap_opening == rollgap::test::approx(reference.shape.gap_opening));
        CHECK(c.shape.backup_follow == rollgap::test::approx(reference.shape.backup_follow));
    }
    // one side only: the lower work roll moving against its still back-up roll
    CHECK(classify_chatter(shape_of({0.0, 0.0, 0.0, -1.0, 0.05, 0.0}), 550.0).type ==
          ChatterType::fifth_octave);
    // a back-up roll following its work roll by 40 % (in phase) still leaves the work roll
    // vibrating mostly on its own spring: fifth-octave; by 60 %: it carries the work roll
    CHECK(classify_chatter(shape_of({0.0, 0.4, 1.0, -1.0, -0.4, 0.0}), 550.0).type ==
          ChatterType::fifth_octave);
    CHECK(classify_chatter(shape_of({0.0, 0.6, 1.0, -1.0, -0.6, 0.0}), 250.0).type ==
          ChatterType::third_octave);
}

TEST_CASE("where shape and band disagree the shape decides and the band is reported beside it") {
    const ChatterClassification c =
        classify_chatter(shape_of({0.0, 0.1, -1.0, 1.0, -0.1, 0.0}), 435.0);
    CHECK(c.type == ChatterType::fifth_octave);
    CHECK(c.band == ChatterType::other);
    CHECK_FALSE(c.agrees());
    const ChatterClassification d =
        classify_chatter(shape_of({-0.8, -1.0, -0.45, 0.45, 1.0, 0.8}), 520.0);
    CHECK(d.type == ChatterType::third_octave);
    CHECK(d.band == ChatterType::fifth_octave);
}

TEST_CASE("the frequency bands are closed intervals") {
    CHECK(chatter_band(99.9) == ChatterType::other);
    CHECK(chatter_band(100.0) == ChatterType::third_octave);
    CHECK(chatter_band(300.0) == ChatterType::third_octave);
    CHECK(chatter_band(300.1) == ChatterType::other);
    CHECK(chatter_band(500.0) == ChatterType::fifth_octave);
    CHECK(chatter_band(700.0) == ChatterType::fifth_octave);
    CHECK(chatter_band(700.1) == ChatterType::other);
    CHECK(std::string(to_string(ChatterType::third_octave)) == "third_octave");
    CHECK(std::string(to_string(ChatterType::fifth_octave)) == "fifth_octave");
    CHECK(std::string(to_string(ChatterType::other)) == "other");
}

TEST_CASE(
    "stacks that allow one kind only: back-up rolls held still give fifth-octave, rigid work-roll springs third-octave") {
    const double k4 = 20e9;
    // back-up rolls a thousand times heavier: the work rolls can only vibrate against them
    StandStructure heavy;
    heavy.mass[1] = heavy.mass[4] = 6e7;
    const ModalAnalysis modal = modal_analysis(structure_matrices(heavy), k4);
    REQUIRE(modal.ok);
    // the gap mode of the work rolls on k3, k5 and the strip: omega^2 = (k3 + 2 k4) / m3
    const double expected =
        std::sqrt((heavy.k3 + 2.0 * k4) / heavy.mass[2]) / (2.0 * 3.141592653589793);
    const NaturalMode work_rolls = nearest_mode(heavy, k4, expected);
    CHECK(work_rolls.frequency_Hz == rollgap::test::approx(expected).epsilon(1e-3));
    CHECK(classify_chatter(real_shape(work_rolls.shape), work_rolls.frequency_Hz).type ==
          ChatterType::fifth_octave);

    // work rolls welded to their back-up rolls: each roll package moves as one body
    StandStructure welded;
    welded.k3 = welded.k5 = 1e15;
    const ModalAnalysis rigid = modal_analysis(structure_matrices(welded), k4);
    REQUIRE(rigid.ok);
    int gap_modes = 0;
    for (const NaturalMode& m : rigid.natural) {
        if (m.frequency_Hz > 5e3) continue;  // the welded springs' own (numerical) modes
        const ChatterClassification c = classify_chatter(real_shape(m.shape), m.frequency_Hz);
        CHECK(c.type != ChatterType::fifth_octave);
        if (c.type == ChatterType::third_octave) ++gap_modes;
    }
    CHECK(gap_modes >= 1);
}

TEST_CASE("the default stand's crossing at 104 Hz is third-octave") {
    const CriticalSpeedResult r = critical_speed(Scenario{});
    REQUIRE(r.status == CriticalSpeedStatus::found);
    CHECK(r.unstable_mode.frequency_Hz == rollgap::test::approx(104.0).epsilon(0.01));
    CHECK(r.unstable_mode.chatter.type == ChatterType::third_octave);
    CHECK(r.unstable_mode.chatter.band == ChatterType::third_octave);
    // the least-damped mode at the scenario's speed is the same gap mode
    const SpeedStability at = stability_at(Scenario{});
    CHECK(at.least_damped.chatter.type == ChatterType::third_octave);
}

TEST_CASE(
    "a rough strip moves the crossing to the work-roll mode near 500 Hz: fifth-octave by shape, and the sweep flags the change") {
    std::vector<Scenario> scenarios(3);
    scenarios[0].roughness.strip_rq = 8e-6;
    scenarios[1].roughness.strip_rq = 9e-6;
    scenarios[2].roughness.strip_rq = 20e-6;
    const auto results = sweep_critical_speed(scenarios, CriticalSpeedOptions{},
                                              rollgap::test::PoolControl(2).control);
    for (const auto& r : results) REQUIRE(r.status == CriticalSpeedStatus::found);
    CHECK(results[0].unstable_mode.frequency_Hz < 150.0);
    CHECK(results[0].unstable_mode.chatter.type == ChatterType::third_octave);
    // 9 um: the work-roll mode crosses near 480 Hz, below the fifth-octave band: the shape decides
    CHECK(results[1].unstable_mode.frequency_Hz > 400.0);
    CHECK(results[1].unstable_mode.chatter.type == ChatterType::fifth_octave);
    CHECK(results[1].unstable_mode.chatter.band == ChatterType::other);
    // 20 um: shape and band agree
    CHECK(results[2].unstable_mode.frequency_Hz > 500.0);
    CHECK(results[2].unstable_mode.chatter.type == ChatterType::fifth_octave);
    CHECK(results[2].unstable_mode.chatter.band == ChatterType::fifth_octave);

    const auto changes = chatter_type_changes(results);
    REQUIRE(changes.size() == 1);
    CHECK(changes[0].from == 0);
    CHECK(changes[0].to == 1);
    CHECK(changes[0].from_type == ChatterType::third_octave);
    CHECK(changes[0].to_type == ChatterType::fifth_octave);
}

TEST_CASE("a change needs a crossing mode on both sides") {
    std::vector<CriticalSpeedResult> results(3);
    results[0].status = CriticalSpeedStatus::found;
    results[0].unstable_mode.chatter.type = ChatterType::third_octave;
    results[1].status = CriticalSpeedStatus::stable_in_range;
    results[1].unstable_mode.chatter.type = ChatterType::fifth_octave;  // no crossing: ignored
    results[2].status = CriticalSpeedStatus::unstable_at_lower_bound;
    results[2].unstable_mode.chatter.type = ChatterType::fifth_octave;
    CHECK(chatter_type_changes(results).empty());
    const auto direct = chatter_type_changes(results, {{0, 2}, {2, 0}, {0, 7}});
    REQUIRE(direct.size() == 2);
    CHECK(direct[0].to_type == ChatterType::fifth_octave);
    CHECK(direct[1].from_type == ChatterType::fifth_octave);
}
