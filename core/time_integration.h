#pragma once
// Time integration of the coupled model with SUNDIALS CVODE: BDF with a dense direct linear
// solver (the film relaxes in microseconds while the mill vibrates at ~100 Hz, docs/model.md §6).

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "core/control.h"
#include "core/coupled_model.h"
#include "core/dynamic_model.h"

namespace rollgap::core {

struct IntegrationOptions {
    double relative_tolerance = 1e-6;  // the bite is solved to ~1e-13, far below 1e-3 of this
    double max_step = 0.0;             // s; 0: no limit
    long max_steps = 100'000;          // between two output times
    long max_total_steps = 1'000'000;  // the whole run: bounds the work of any input
};

struct IntegrationResult {
    DynamicsStatus status = DynamicsStatus::solver_failure;
    const char* message = "";
    double end_time = 0.0;  // the last output time reached
    long steps = 0;
    long rhs_evaluations = 0;           // CVODE's own (nfe), the Jacobian's not included
    long jacobian_evaluations = 0;      // nje: the model's jacobian() (docs/model.md §6.1)
    long jacobian_rhs_evaluations = 0;  // right-hand sides a Jacobian took (the fallback's)
};

// What an output sees: the state and its time derivative (interpolated by CVODE).
struct Sample {
    double t;
    const Eigen::VectorXd& z;
    const Eigen::VectorXd& zdot;
};

// Integrates z from t0 through the increasing `output_times`, calling `on_output` at each. Stops
// at the first physical limit (contact lost, skidding, slack strip: the status says which), on
// cancellation (polled at every output) or on a solver failure. On return z holds the last state
// reached.
IntegrationResult integrate(const DynamicModel& model, Eigen::VectorXd& z, double t0,
                            const std::vector<double>& output_times,
                            const std::function<void(const Sample&)>& on_output,
                            const IntegrationOptions& options = {}, const Control& control = {});

}  // namespace rollgap::core
