#pragma once
// The speeds a tandem mill may run at under a plant's limits (docs/model.md §13.5): the single
// stand's engine (core/speed_limit.h, speed_window) over the mill speed V (the last stand's roll
// speed), its figures the pass schedule's at each V (mill_steady_state: every stand's roll
// force, torque, power and forward slip), each stand with its own limits, and the chatter limit
// the mill's headline critical speed (mill_critical_speeds) less the safety margin. A limit not
// given is not checked; a mill limit names its stand. Under a posterior (§13.7) the chatter limit
// is taken at V_c's one-sided lower bound and every plant end at its own.

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "core/control.h"
#include "core/mill/mill.h"
#include "core/mill/mill_critical_speed.h"
#include "core/propagation.h"
#include "core/speed_limit.h"

namespace rollgap::core {

// A mill's calibration posterior (docs/model.md §13.7): its stands' fitted numbers and their
// covariance, block-diagonal (each stand calibrated on its own; the stands independent). The
// numbers' steps are not read: the gradient is differenced over a hundredth of each standard
// error.
struct MillPosterior {
    std::vector<MillNumber> numbers;
    Eigen::MatrixXd covariance;
};

struct MillPlantLimits {
    // One per stand: max_force, max_torque, max_power, min_forward_slip (its chatter members are
    // not read: the mill's chatter limit is the mill's, below).
    std::vector<PlantLimits> stands;
    bool chatter = true;
    // [0, 1): the chatter limit is V_c (1 - margin), with a posterior (V_c - z sigma)(1 - margin)
    double chatter_margin = 0.0;
    std::optional<MillPosterior> posterior;
    double confidence = 0.95;  // of the one-sided bounds under the posterior (z its quantile)
    // with a posterior: the headline critical speed at this many seeded draws too, the check on
    // the linear sigma (docs/model.md §13.7); 0: none
    int samples = 0;
    std::uint64_t seed = 1;
};

// The headline critical speed's uncertainty (docs/model.md §13.7).
struct MillSpeedUncertainty {
    bool ok = false;              // the gradient was found (the crossing's margin at every point)
    double critical_speed = 0.0;  // the headline's, at the posterior mean, m/s
    double standard_deviation = 0.0;    // sqrt(g Σ gᵀ), m/s
    double lower_bound = 0.0;           // V_c − z sigma, m/s
    Eigen::VectorXd gradient;           // dV_c/dx_j, m/s per SI unit
    std::optional<Propagated> sampled;  // MillPlantLimits::samples > 0: the draws' figures
};

// Every stand's steady figures at mill speed V (the schedule, or the speeds mode's roll speeds
// scaled to V): none ok when the mill has no steady state there.
std::vector<SteadyFigures> mill_steady_figures(const Mill& mill, double speed);

struct MillSpeedLimitResult {
    SpeedLimitResult window;  // its `chatter` unused
    // the mill's critical speeds when the chatter limit is checked; the chatter limit is the
    // headline's speed, the range's highest speed when no crossing inside the model's range is
    // found (outside_range_below then says which were found outside it)
    std::optional<MillCriticalSpeeds> critical;
    // with a posterior and a headline crossing: the chatter limit is taken at its lower bound
    std::optional<MillSpeedUncertainty> uncertainty;
};

// V over options' range: the window, the binding limits with their stands. The chatter limit's
// stand is the headline crossing's moving stand. Cancelled: window.status says so.
MillSpeedLimitResult mill_speed_limit(const Mill& mill, const MillPlantLimits& limits,
                                      const CriticalSpeedOptions& options = {},
                                      const Control& control = {});

}  // namespace rollgap::core
