#pragma once
// The speeds a stand may run at under a plant's limits (docs/model.md §13): the roll force, the
// torque per work roll, the motor power of both work rolls and the forward slip (the skid margin)
// of the steady bite over the speed range, the chatter limit (the critical speed less a safety
// margin) and where the bite has a steady state at all. Each limit permits a set of speeds;
// their intersection is the permitted set, and the answer is its interval around the operating
// speed (DECISIONS A: the force falls with speed, so a force limit is usually a lower bound),
// each end named by the limit that binds there. A limit not given is not checked.
#include <functional>
#include <optional>
#include <vector>

#include "core/control.h"
#include "core/scenario.h"
#include "core/stability.h"

namespace rollgap::core {

enum class SpeedLimitKind { chatter, force, torque, power, skid, steady_state };
const char* to_string(SpeedLimitKind);

struct PlantLimits {
    std::optional<double> max_force;         // N
    std::optional<double> max_torque;        // N m per work roll, |torque|
    std::optional<double> max_power;         // W, both work rolls: 2 |torque| v / a
    std::optional<double> min_forward_slip;  // (u2 - v) / v, the skid margin
    bool chatter = true;                     // the critical speed is a limit
    double chatter_margin = 0.0;             // the chatter limit is V_c (1 - margin), [0, 1)
    // The critical speed's standard deviation from the scenario's calibration posterior
    // (core/propagation.h), m/s: the chatter limit is then (V_c - z_c sigma)(1 - margin), the
    // one-sided lower bound at `confidence` (DECISIONS A); 0: V_c itself.
    double chatter_sigma = 0.0;
    double confidence = 0.95;
};

// One stand's steady figures at one roll speed: what the limits are checked on.
struct SteadyFigures {
    bool ok = false;  // the bite has a steady state
    double speed = 0.0;
    double force = 0.0;         // N
    double torque = 0.0;        // N m per work roll (magnitude)
    double power = 0.0;         // W, both work rolls
    double forward_slip = 0.0;  // fraction
};
SteadyFigures steady_figures(const Scenario& s, double speed);

// One limit over the range: the interval of speeds it permits that holds the answer's window,
// its ends where it binds (a limit met everywhere on one side has no end there), and its margin
// at the operating speed.
struct LimitAnswer {
    SpeedLimitKind kind = SpeedLimitKind::force;
    // The stand it belongs to, 0-based (a single stand: 0); -1 for a limit of the whole mill
    // (its steady state) and for a chatter limit without a moving stand.
    int stand = 0;
    double limit = 0.0;         // the plant's value in SI (chatter: the limit speed, m/s)
    double at_operating = 0.0;  // the figure at the operating speed (chatter: the speed)
    double utilisation = 0.0;   // at_operating / limit (skid: limit / at_operating)
    bool met_at_operating = false;
    std::optional<double> lower_speed;  // m/s: below it this limit is violated
    std::optional<double> upper_speed;  // m/s: above it this limit is violated
    // Their standard deviations from a calibration posterior (§13.2), m/s, when propagated
    std::optional<double> lower_speed_sd, upper_speed_sd;
};

enum class SpeedLimitStatus {
    ok,            // a permitted window (the operating speed inside it or not)
    no_window,     // no speed in the range meets every checked limit
    no_operating,  // the operating speed has no steady state and nothing else to start from
    cancelled
};
const char* to_string(SpeedLimitStatus);

struct SpeedLimitResult {
    SpeedLimitStatus status = SpeedLimitStatus::no_window;
    double operating_speed = 0.0;  // m/s, the scenario's rolls.speed
    // The permitted interval holding the operating speed, else the nearest (the lower on a tie)
    double window_min = 0.0, window_max = 0.0;  // m/s
    // What binds at each end; none where the end is the range's own
    std::optional<SpeedLimitKind> binding_min, binding_max;
    int binding_min_stand = -1, binding_max_stand = -1;  // their LimitAnswer::stand
    bool operating_permitted = false;
    double advised_speed = 0.0;       // m/s: window_max, the fastest permitted speed
    std::vector<LimitAnswer> limits;  // every checked limit, steady_state always among them
    CriticalSpeedResult chatter;      // when the chatter limit is checked
};

// The engine behind speed_limit and mill_speed_limit (core/mill/mill_speed_limit.h): limits of
// figures that are functions of one speed (a stand's roll speed, a mill's speed).
struct SpeedCheck {
    SpeedLimitKind kind = SpeedLimitKind::force;  // force, torque, power or skid
    int stand = 0;                                // which of the figures it reads
    double limit = 0.0;                           // SI
};
// The steady figures of every stand at one speed (a single stand: one). The speed has a steady
// state iff every one is ok.
using SteadyAtSpeed = std::function<std::vector<SteadyFigures>(double speed)>;
struct ChatterLimit {
    double speed = 0.0;  // m/s: every speed up to it is permitted; below speed_min: none is
    int stand = -1;      // the stand that moves (LimitAnswer::stand)
};
// The steady figures on options' speed grid (speed_min by speed_step to speed_max, in parallel
// on the control's threads), each change of a limit's verdict between two grid speeds bisected
// to 1e-9 relative; the steady_state limit first, the checks in order, the chatter limit last.
// The result's `chatter` is left for the caller.
SpeedLimitResult speed_window(const std::vector<SpeedCheck>& checks, const SteadyAtSpeed& at,
                              double operating_speed, const std::optional<ChatterLimit>& chatter,
                              const CriticalSpeedOptions& options, const Control& control = {});

// The limits over options' speed range: the steady figures on its grid (speed_step, in parallel
// on the control's threads), each sign change of a limit refined by Brent to 1e-9 m/s relative;
// the chatter limit from critical_speed() with the same options.
SpeedLimitResult speed_limit(const Scenario& s, const PlantLimits& limits,
                             const CriticalSpeedOptions& options = {}, const Control& control = {});

// The speed within `half_width` of `near` where the stand's figure of `kind` (force, torque,
// power or skid) meets `limit`: Brent on its margin to 1e-9 of the speed; nullopt without a
// steady state at either end of the bracket or without a sign change in it. What a posterior's
// differences move (§13.2): the end a limit has at the posterior mean, found again at a nearby x.
std::optional<double> limit_crossing(const Scenario& s, SpeedLimitKind kind, double limit,
                                     double near, double half_width);

// The window with each plant limit's ends at their one-sided bounds (docs/model.md §13.2): an
// upper end u with standard deviation sd at u - z sd, a lower end l at l + z sd (an end without
// a standard deviation as it is; the chatter limit is bounded already). Of the limits whose end
// bounds the window on that side, the tightest bound binds; a window left empty is no_window.
void bound_window(SpeedLimitResult& result, double z);

}  // namespace rollgap::core
