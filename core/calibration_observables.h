#pragma once
// Calibration of a scenario (docs/model.md §11): what the model predicts for each plant
// observation, as a function of the fitted scenario fields, handed to calibrate().
//
// Each observation was measured under its own conditions (a scenario); the fitted fields are
// set into every condition before it is evaluated. Observations that share a condition share
// its computations: one roll-bite solve, one critical-speed search, one modal analysis.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration.h"
#include "core/control.h"
#include "core/stand_structure.h"
#include "core/scenario.h"
#include "core/stability.h"

namespace rollgap::core {

enum class Observable {
    roll_force,         // N, the steady bite at the condition's speed (docs/model.md §7.1)
    torque,             // N m per roll
    forward_slip,       // 1
    critical_speed,     // m/s (docs/model.md §7.3)
    chatter_frequency,  // Hz, of the mode that goes unstable at the critical speed
    natural_frequency,  // Hz, of one undamped mode of the stack with the strip spring k4
    damping_ratio,      // 1, of that mode with the structure's damping (c1, c2, Rayleigh)
    // Operational modal analysis (docs/model.md §11.6): the least-damped oscillatory root of the
    // running stand linearised at the condition's speed (§7.3), bite and tension loop included
    running_frequency,      // Hz
    running_damping_ratio,  // 1
};
const char* to_string(Observable);
bool needs_mode(Observable);

// Which mode of the stack, chosen at the start values: the index-th natural mode (ascending
// frequency) or the one nearest a frequency. Across parameter changes the mode is followed by
// its shape (the modal assurance criterion against the chosen mode), not by its index: two
// modes of the default stand sit at 201 and 210 Hz and can swap order.
struct ModeChoice {
    int index = -1;        // ≥ 0: by index
    double near_Hz = 0.0;  // > 0: nearest this frequency
};

struct ScenarioObservation {
    int condition = 0;  // index into ScenarioCalibration::conditions
    Observable quantity = Observable::roll_force;
    double value = 0.0;        // SI
    double uncertainty = 0.0;  // SI, > 0
    ModeChoice mode;           // natural_frequency and damping_ratio only
};

using ParameterAccess = std::function<double&(Scenario&)>;

struct ScenarioCalibration {
    std::vector<Scenario> conditions;     // the fitted fields at their start values
    std::vector<ParameterAccess> access;  // one per parameter: where it lives in a scenario
    std::vector<CalibrationParameter> parameters;  // SI
    std::vector<ScenarioObservation> observations;
    // The search for critical-speed observations (threads are set by the fit). Its result is
    // then refined by secant steps on the growth rate (smooth in speed), so the critical speed
    // is a differentiable function of the parameters for the finite-difference Jacobian.
    CriticalSpeedOptions critical_speed;
    CalibrationOptions options;
    // A stored posterior as the prior of some parameters (coil-by-coil adaptation).
    std::optional<JointPrior> joint_prior;
};

struct ObservationPrediction {
    double value = 0.0;              // SI; NaN when the model has no answer
    std::string failure;             // why not, when value is NaN
    double mode_frequency_Hz = 0.0;  // of the mode chosen at the start (mode observations)
    double mode_mac = 0.0;           // shape agreement of the followed mode with it, 0..1
};

struct ScenarioCalibrationResult {
    CalibrationResult fit;
    // At the fitted values (at the start values when the model failed there).
    std::vector<ObservationPrediction> predictions;
};

ScenarioCalibrationResult calibrate_scenario(const ScenarioCalibration& setup,
                                             const Control& control = {});

// The predictions at parameter values `x` (SI): what a fit compares with the observations.
// The modes are the ones chosen at the setup's start values.
std::vector<ObservationPrediction> predict_observations(const ScenarioCalibration& setup,
                                                        const Eigen::VectorXd& x,
                                                        const Control& control = {});

// The number of stability evaluations (linearisations) one evaluation of all observations
// costs at most: a critical-speed search per condition that needs one, plus its refinement.
long stability_evaluations_per_prediction(const ScenarioCalibration& setup);

}  // namespace rollgap::core
