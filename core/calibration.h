#pragma once
// Weighted nonlinear least squares with box bounds and Gaussian priors, by Levenberg–Marquardt
// (docs/model.md §11). Pure: the model is a residual function, failures are status values.
//
//   minimise  Σ_i r_i(x)²  +  Σ_j ((x_j − prior_j) / σ_j)²   subject to lower ≤ x ≤ upper,
//
// where r_i = (model_i(x) − observed_i) / u_i is a residual already divided by its standard
// uncertainty. The priors are extra residual rows, so the normal matrix JᵀJ at the solution
// is the posterior information and its inverse the posterior covariance.
//
// Why a small LM of our own rather than Eigen's unsupported MINPACK port (LevenbergMarquardt /
// NonLinearOptimization): neither has bounds (a transform such as x = lower + (upper − lower)
// sin² hides a parameter sitting on its bound behind a zero derivative, which then reads as
// "unobservable"), MINPACK computes its forward-difference Jacobian column after column with
// no hook to spread the columns over threads or to stop between them, and its covariance and
// conditioning would still have to be computed here. The classic method (Marquardt's diagonal
// scaling, Nielsen's damping update, bounds by projection with an active set) is ~150 lines.

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "core/control.h"

namespace rollgap::core {

struct CalibrationParameter {
    double start = 0.0;  // lower ≤ start ≤ upper
    double lower = 0.0;
    double upper = 0.0;  // lower < upper, both finite
    bool has_prior = false;
    double prior_value = 0.0;
    double prior_uncertainty = 0.0;  // > 0 when has_prior
};

// A joint Gaussian prior over some of the parameters: a stored posterior (docs/model.md §11.6),
// so that a stand adapts coil after coil. Its rows L⁻¹ (x_S − mean) with Σ = L Lᵀ take the
// places of those parameters' own prior rows (a covered parameter has none of its own); they
// are linear, so the posterior information JᵀJ gains exactly Σ⁻¹ on S.
struct JointPrior {
    std::vector<int> indices;    // the parameters it covers, each once
    Eigen::VectorXd mean;        // SI, one per index
    Eigen::MatrixXd covariance;  // SI, symmetric positive definite
};

// Fills `residuals` (size observation_count) at `x`; false when the model has no answer there
// (no steady bite, no critical speed in range): the fit treats the point as unacceptable.
// `control` carries the executor and the thread budget of this one evaluation (its inner loops
// may run on the executor); it is called from several threads at once (one per Jacobian
// column), so it must not share mutable state.
using ResidualFunction = std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd& residuals,
                                            const Control& control)>;

struct CalibrationOptions {
    int max_iterations = 30;
    int max_evaluations = 400;      // residual evaluations in all, Jacobian columns included
    double relative_step = 1e-6;    // forward-difference step, of max(|x|, scale)
    double step_tolerance = 1e-9;   // converged when every step is below this, relative
    double cost_tolerance = 1e-12;  // ... or χ² decreases by less than this, relative
    // Below this reciprocal condition number of the observations' (correlation-scaled) normal
    // matrix the observations are said not to separate the parameters of the near-null
    // direction (|correlation| beyond ~0.9998 for two parameters).
    double separability_limit = 1e-4;
};

enum class CalibrationStatus {
    converged,
    max_iterations,
    max_evaluations,
    stalled,        // no step lowers χ² any more before the tolerances are met
    model_failure,  // the model has no answer at the start values
    cancelled,
};
const char* to_string(CalibrationStatus);

enum class BoundState { inside, lower, upper };

struct CalibrationResult {
    CalibrationStatus status = CalibrationStatus::model_failure;
    int iterations = 0;
    int evaluations = 0;
    Eigen::VectorXd values;  // the fitted parameters (the start if model_failure)
    // Posterior (observations and priors): sqrt of the diagonal of (JᵀJ)⁻¹ at the solution;
    // +inf for a parameter in a direction neither observations nor priors determine.
    Eigen::VectorXd standard_errors;
    Eigen::MatrixXd correlation;      // posterior; NaN where a standard error is infinite
    Eigen::VectorXd residuals;        // the observations' normalised residuals at the solution
    Eigen::VectorXd prior_residuals;  // (x − prior) / σ, 0 where no prior
    double chi_squared_observations = 0.0;
    double chi_squared_priors = 0.0;
    int degrees_of_freedom = 0;      // observations − parameters
    std::vector<BoundState> bounds;  // where each fitted value sits
    // Parameters the observations alone cannot separate: one group per near-null direction of
    // the observations' normal matrix (indices with a large component in it), and parameters
    // the observations do not depend on at all.
    std::vector<std::vector<int>> inseparable;
    std::vector<int> unobservable;
    double reciprocal_condition = 0.0;  // of the observations' correlation-scaled normal matrix
};

CalibrationResult calibrate(const std::vector<CalibrationParameter>& parameters,
                            int observation_count, const ResidualFunction& residuals,
                            const CalibrationOptions& options = {}, const Control& control = {},
                            const JointPrior* joint_prior = nullptr);

}  // namespace rollgap::core
