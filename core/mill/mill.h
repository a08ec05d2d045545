#pragma once
// The tandem mill of docs/model.md §12: N stands (1-6), each a complete single-stand scenario,
// coupled by the strip: the spans between them carry the strip force per width T (N/m), and
// each stand's exit thickness is the next stand's entry thickness. A mill composes stands; the
// stand code is the single stand's (core/roll_bite.h, core/stand_block.h), never a fork of it.
// This header: the mill's description and its steady state (the pass schedule, §12.3).

#include <functional>
#include <vector>

#include "core/roll_bite.h"
#include "core/scenario.h"

namespace rollgap::core {

// What holds the strip before the first stand and after the last (§12.1): a span to a bridle,
// uncoiler or coiler held at its steady speed (its force a state), or a constant tension stress.
enum class MillBoundary { span, constant };
// schedule: the last stand runs at the mill speed and every other stand's roll speed follows
// from the mass flow; speeds: every roll speed given (each stand's rolls.speed), the interstand
// tensions follow (§12.3).
enum class MillMode { schedule, speeds };
// How a span carries its strip force (§12.1): `spring`, one force per span, the strip massless
// (valid well below the span's first longitudinal mode c / 2L); `segments`, the span cut into n
// segments of length L / n whose forces are states, the strip's mass lumped at the n - 1 nodes
// between them, so the span carries longitudinal strip waves. One segment is the spring.
enum class SpanModel { spring, segments };

inline constexpr int max_mill_stands = 6;
inline constexpr int max_span_segments = 50;

struct Mill {
    // Each stand's own scenario: rolls, lubricant, roughness, friction, film model, structure,
    // flow stress. Its strip thicknesses, tensions, width and Young's modulus are the mill's
    // (below); its roll speed is solved (schedule mode).
    std::vector<Scenario> stands;
    // The strip thickness entering stand 1 and leaving each stand, m: N + 1 values, falling.
    std::vector<double> thickness;
    double width = 1.8;               // w, m, common to the mill
    double youngs_modulus = 210e9;    // E, Pa, of the strip
    double strip_density = 7850.0;    // rho, kg/m^3 (the span waves, §12.1)
    std::vector<double> span_length;  // the N - 1 interstand spans, m
    MillBoundary entry = MillBoundary::span;
    MillBoundary exit = MillBoundary::span;
    double entry_span_length = 5.0;  // m
    double exit_span_length = 5.0;   // m
    // Tension set points as stresses, Pa: the entry strip's, each interstand span's, the exit
    // strip's. A span's force is T = sigma * (its steady thickness).
    double entry_tension = 18e6;
    std::vector<double> interstand_tension;  // N - 1 values
    double exit_tension = 40e6;
    double speed = 15.0;  // V, m/s: the last stand's roll speed
    // schedule: the interstand tensions above are set points; speeds: each stand's roll speed is
    // its scenario's rolls.speed, scaled by V / (the last stand's) so that a scan over V keeps
    // the speeds' ratios, and the interstand tensions above are only the search's start
    MillMode mode = MillMode::schedule;
    SpanModel span_model = SpanModel::spring;
    int span_segments = 10;  // n per span under `segments` (every span: entry, interstand, exit)

    int size() const { return static_cast<int>(stands.size()); }
};

// A number of the mill (one member, or several moved together) and the step to difference it
// with (SI): shift(mill, delta) adds delta to it (docs/model.md §13.6-13.7).
struct MillNumber {
    std::function<void(Mill&, double)> shift;
    double step = 0.0;
};

// docs/model.md §12.3: 5 stands, 2.80 -> 2.25 -> 1.88 -> 1.60 -> 1.36 -> 1.20 mm (stand 4 is the
// single-stand default bite), the single-stand defaults otherwise, spans of 5 m, tensions 18 /
// 60 / 40 MPa, 15 m/s.
Mill default_mill();

// One stand's scenario inside the mill at roll speed `roll_speed`: the mill's thicknesses,
// width and E, and its steady tensions as constant stresses (the mill's spans carry them).
Scenario stand_scenario(const Mill& mill, int stand, double roll_speed);

// The steady tension stresses a stand sees (its back and front), Pa.
double back_tension_stress(const Mill& mill, int stand);
double front_tension_stress(const Mill& mill, int stand);

struct MillStandState {
    BiteStatus status = BiteStatus::solver_failure;
    const char* message = "";
    double roll_speed = 0.0;           // v_i, m/s
    double entry_speed = 0.0;          // u1_i, m/s
    double exit_speed = 0.0;           // u2_i, m/s
    double forward_slip = 0.0;         // (u2 - v) / v
    double force = 0.0;                // P, N
    double torque = 0.0;               // per roll, N m
    double power = 0.0;                // both rolls, 2 torque v / a, W
    double inlet_film = 0.0;           // h0, m
    double neutral_point = 0.0;        // x_n, m
    double back_tension = 0.0;         // stress, Pa
    double front_tension = 0.0;        // stress, Pa
    double back_tension_force = 0.0;   // T w, N
    double front_tension_force = 0.0;  // T w, N
    int bite_solves = 0;               // for this stand's roll speed
    BiteResult bite;                   // the steady bite (no distributions)
};

enum class MillSteadyStatus {
    ok,
    no_steady_state,  // a stand skids, loses contact or fails: `stand` names it
    invalid           // the description is not a mill (message says why)
};
const char* to_string(MillSteadyStatus);

struct MillSteadyState {
    MillSteadyStatus status = MillSteadyStatus::invalid;
    const char* message = "";
    int stand = -1;  // the stand without a steady state (0-based), or -1
    // speeds mode: the interstand span gone slack (numbered by the stand behind it, 1..N-1, as
    // MillFailure), or -1
    int span = -1;
    int newton_iterations = 0;  // speeds mode
    double mass_flow = 0.0;     // Q = u2_N y2_N, m^2/s
    // max over stands of |u2_i y2_i - Q| / Q: the schedule's own accuracy
    double mass_flow_residual = 0.0;
    std::vector<MillStandState> stands;
};

// The schedule (§12.3): stand N at the mill speed gives Q; every other stand's roll speed solves
// u2_i(v_i) y2_i = Q by the secant method (v from the stand's own forward slip, then secant to
// 1e-13 of Q), the tensions at their set points. Failures are values naming the stand.
// Speeds mode: the roll speeds given (mill_roll_speeds), the N - 1 interstand tensions solve
// u2_i y2_i = u2_N y2_N (i < N) by a damped Newton with a difference Jacobian, from the set
// points; the stands report the solved tensions. A span whose tension the speeds drive to zero
// is named (`span`), a stand that skids or loses contact at every step towards the solution too.
MillSteadyState mill_steady_state(const Mill& mill);

// The roll speeds of speeds mode at the mill speed: stand i's rolls.speed times V / (the last
// stand's rolls.speed), m/s.
std::vector<double> mill_roll_speeds(const Mill& mill);

// A description the mill model cannot take (wrong counts, a thickness that does not fall, a
// non-positive length or tension where a span needs one), or "" if it is one. The API reports
// the same conditions with field pointers; this is core's own guard.
const char* mill_defect(const Mill& mill);

}  // namespace rollgap::core
