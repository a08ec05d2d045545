#pragma once
// The tandem mill in the time domain (docs/model.md §12.9; the specification's §3 and §7): the
// whole mill (13 states per stand, the span forces) in CVODE with the thickness transport as a
// history, not a rational approximation. The state adds one strip position per interstand span,
//   s_i = S_i - u2_i,ref t,   S_i' = u2_i(t) (stand i's exit strip speed),
// and each span keeps a history of (t, S_i, y2_i, y2_i') at every accepted step. The strip now
// entering stand i+1 left stand i at t_d, where S_i(t) - S_i(t_d) = L_i; stand i+1 sees
//   y1_{i+1}(t) = y2_i(t_d),   y1_{i+1}'(t) = y2_i'(t_d) u2_i(t) / u2_i(t_d)
// (d/dt of the position relation: u2_i(t) - u2_i(t_d) dt_d/dt = 0), both read off the history by
// cubic Hermite interpolation. Before the start the history is the steady state (y2 steady, S
// extrapolated at the steady speed). The step never exceeds a quarter of the shortest delay, so
// t_d always lies in the stored history.

#include <vector>

#include <Eigen/Dense>

#include "core/control.h"
#include "core/mill/mill.h"
#include "core/mill/mill_model.h"

namespace rollgap::core {

// How the mill is moved off its steady state at t = 0.
struct MillKick {
    // Added to z0 component by component, in MillModel's state order (docs/model.md §12.4: the
    // stands' blocks, then the spans); empty: nothing.
    Eigen::VectorXd state;
    // A gap kick: stand `stand`'s work rolls moved apart by `gap` m (q3 += gap/2, q4 -= gap/2,
    // so y2 rises by `gap`); stand -1: none.
    int stand = -1;
    double gap = 0.0;
};

struct MillTimeOptions {
    double relative_tolerance = 1e-6;
    // Times the model's absolute tolerances (docs/model.md §6: q 1e-10 m, q' 1e-7 m/s, h0
    // 1e-12 m, span forces 1 Pa times the span's thickness; strip positions 1e-10 m): a kick of
    // a nanometre needs ~1e-3, or the tolerance is a tenth of the motion.
    double absolute_tolerance_scale = 1.0;
    double max_step = 0.0;             // s; 0: a quarter of the shortest delay (never more)
    long max_total_steps = 1'000'000;  // the whole run: bounds the work of any input
    bool frozen_transport = false;     // y1 held at its steady value (the frozen mill, §12.4)
};

enum class MillTimeStatus {
    ok,
    slack_span,      // a span's force reached zero: `span` names it
    contact_lost,    // a stand's gap opened past its entry thickness: `stand`
    skidding,        // a stand's bite has no neutral point: `stand`
    solver_failure,  // the model has no state (a film collapsed, a bite did not solve) or CVODE
                     // could not go on: `stand` when a stand's bite is the cause
    step_budget,     // max_total_steps exhausted
    cancelled,
    invalid  // the mill, its steady state or the request is not one the time domain can run
};
const char* to_string(MillTimeStatus);

// One stand at one output time.
struct MillStandSample {
    double gap = 0.0;              // the work rolls' gap change q3 - q4 = y2 - y2_ref, m
    double force = 0.0;            // roll force P, N
    double back_tension = 0.0;     // sigma_b, Pa
    double front_tension = 0.0;    // sigma_f, Pa
    double entry_thickness = 0.0;  // y1 (the delayed y2 of the stand before), m
    double exit_thickness = 0.0;   // y2, m
    double entry_speed = 0.0;      // u1, m/s
    double exit_speed = 0.0;       // u2, m/s
};

struct MillTimeSample {
    double t = 0.0;  // s
    std::vector<MillStandSample> stands;
    // The strip force per width T of the span behind stand j, N/m (N + 1 values: 0 the entry,
    // N the exit; a boundary held at a constant stress gives that stress times its thickness).
    std::vector<double> span_force;
    // Per interstand span: the transport time t - t_d of the strip now entering stand i+1, s.
    std::vector<double> transport_time;
};

struct MillTimeResult {
    MillTimeStatus status = MillTimeStatus::invalid;
    const char* message = "";
    int stand = -1;         // the stand that ended the run (0-based), or -1
    int span = -1;          // the slack span, numbered as span_force (0 entry .. N exit), or -1
    double end_time = 0.0;  // the last time reached: the limit's time when one ended the run
    std::vector<MillTimeSample> samples;  // one per output time reached
    std::vector<double> delay;            // the nominal delays tau_i = L_i / u2_i,ref, s
    double max_step = 0.0;                // the step limit used, s (0: none)
    long steps = 0;
    long rhs_evaluations = 0;
    long jacobian_evaluations = 0;
};

// Integrates the mill `mill` (with its steady state `steady`, which must be ok) from its steady
// state moved by `kick` at t = 0 through the increasing positive `output_times`. Stops at the
// first physical limit, found by root finding on the span forces and each stand's y1 - y2 (the
// result names the span or stand and the time), at a stand that skids, on cancellation (polled at
// every output) or when the step budget is spent; never throws.
MillTimeResult mill_time_domain(const Mill& mill, const MillSteadyState& steady,
                                const MillKick& kick, const std::vector<double>& output_times,
                                const MillTimeOptions& options = {}, const Control& control = {});

}  // namespace rollgap::core
