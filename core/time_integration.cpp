#include "core/time_integration.h"

#include <vector>

#include "core/cvode_support.h"

namespace rollgap::core {

namespace {

struct RhsData {
    const DynamicModel* model;
    DynamicsStatus last_failure = DynamicsStatus::ok;
    int limit_failures = 0;
    long fallback_rhs_evaluations = 0;
};

// Trial steps that overshoot into a limit are few in a healthy run; many mean the trajectory is
// pressing against one (skidding has no root function), and CVODE would creep towards it in
// ever smaller steps. Past this budget the run ends there.
constexpr int limit_failure_budget = 100;

// A state without a valid right-hand side (the bite skids, the rolls lose contact, the strip goes
// slack) is reported to CVODE as recoverable: a trial step may overshoot into it, and CVODE then
// retries smaller. If the trajectory itself runs into the limit, CVODE gives up and the last
// failure says which limit ended the run.
int right_hand_side(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
    auto* data = static_cast<RhsData*>(user_data);
    const DynamicsStatus status =
        data->model->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
    if (status == DynamicsStatus::ok) return 0;
    data->last_failure = status;
    return ++data->limit_failures > limit_failure_budget ? -1 : 1;
}

// The Newton iteration's Jacobian: the model's own (assembled from the bite sensitivities for the
// coupled model, docs/model.md §6.1; ~1 right-hand side's cost instead of CVODE's n difference
// quotients). Where the model gives none (a state within a step of a limit), central differences
// of the right-hand side; if those fail too, CVODE retries with a smaller step.
int jacobian(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* user_data, N_Vector, N_Vector,
             N_Vector) {
    auto* data = static_cast<RhsData*>(user_data);
    const sunindextype n = SUNDenseMatrix_Rows(J);
    const Eigen::Map<const Eigen::VectorXd> z(N_VGetArrayPointer(y), n);
    Linearisation lin = data->model->jacobian(z, t);
    if (lin.status != DynamicsStatus::ok) {
        lin = finite_difference_jacobian(*data->model, z, t);
        data->fallback_rhs_evaluations += 2 * n;
        if (lin.status != DynamicsStatus::ok) return 1;
    }
    for (sunindextype j = 0; j < n; ++j) {
        sunrealtype* column = SUNDenseMatrix_Column(J, j);
        for (sunindextype i = 0; i < n; ++i) column[i] = lin.jacobian(i, j);
    }
    return 0;
}

int limit_margins(sunrealtype t, N_Vector y, sunrealtype* margins, void* user_data) {
    static_cast<RhsData*>(user_data)->model->limit_margins(t, N_VGetArrayPointer(y), margins);
    return 0;
}

}  // namespace

IntegrationResult integrate(const DynamicModel& model, Eigen::VectorXd& z, double t0,
                            const std::vector<double>& output_times,
                            const std::function<void(const Sample&)>& on_output,
                            const IntegrationOptions& options, const Control& control) {
    IntegrationResult result;
    result.end_time = t0;
    const int n = model.size();
    RhsData data{&model};

    // docs/model.md §6: q 1e-10 m, q' 1e-7 m/s, h0 1e-12 m, tensions 1 Pa
    std::vector<double> tolerances(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
        tolerances[static_cast<std::size_t>(i)] = model.absolute_tolerance(i);
    cvode::Cvode cv;
    result.message = cvode::setup(cv, n, t0, z.data(), tolerances.data(),
                                  options.relative_tolerance, right_hand_side, jacobian, &data);
    if (*result.message != '\0') return result;
    double* y = N_VGetArrayPointer(cv.y);
    CVodeSetMaxNumSteps(cv.memory, options.max_steps);
    if (CVodeRootInit(cv.memory, model.margin_count(), limit_margins) != CV_SUCCESS) {
        result.message = "CVODE root finding setup failed";
        return result;
    }
    if (options.max_step > 0.0) CVodeSetMaxStep(cv.memory, options.max_step);

    Eigen::VectorXd state(n), rate(n);
    result.status = DynamicsStatus::ok;
    result.message = "ok";
    for (double tout : output_times) {
        if (control.should_stop()) {
            result.status = DynamicsStatus::cancelled;
            result.message = "cancelled";
            break;
        }
        sunrealtype t = t0;
        int flag = CVode(cv.memory, tout, cv.y, &t, CV_NORMAL);
        if (flag == CV_ROOT_RETURN) {
            std::vector<int> crossed(static_cast<std::size_t>(model.margin_count()), 0);
            CVodeGetRootInfo(cv.memory, crossed.data());
            for (int i = 0; i < model.margin_count(); ++i) {
                if (crossed[static_cast<std::size_t>(i)] < 0)
                    result.status = model.margin_status(i);  // crossed downwards
            }
            if (result.status != DynamicsStatus::ok) {
                result.end_time = t;
                result.message = cvode::end_message(result.status);
                break;
            }
            // an upward crossing (a tension recovering) is no limit: go on to the output time
            flag = CVode(cv.memory, tout, cv.y, &t, CV_NORMAL);
        }
        if (flag < 0) {
            result.status = data.last_failure != DynamicsStatus::ok
                                ? data.last_failure
                                : DynamicsStatus::solver_failure;
            result.message = data.last_failure != DynamicsStatus::ok
                                 ? cvode::end_message(data.last_failure)
                                 : "CVODE could not continue (step size too small)";
            break;
        }
        CVodeGetDky(cv.memory, t, 1, cv.ydot);
        const double* yd = N_VGetArrayPointer(cv.ydot);
        for (int i = 0; i < n; ++i) {
            state(i) = y[i];
            rate(i) = yd[i];
        }
        result.end_time = t;
        if (on_output) on_output(Sample{t, state, rate});
        long steps = 0;
        CVodeGetNumSteps(cv.memory, &steps);
        if (steps > options.max_total_steps) {
            result.status = DynamicsStatus::solver_failure;
            result.message =
                "the step budget of the run is exhausted (the stack's modes are too fast for the window)";
            break;
        }
    }
    for (int i = 0; i < n; ++i) z(i) = y[i];
    CVodeGetNumSteps(cv.memory, &result.steps);
    CVodeGetNumRhsEvals(cv.memory, &result.rhs_evaluations);
    CVodeGetNumJacEvals(cv.memory, &result.jacobian_evaluations);
    CVodeGetNumLinRhsEvals(cv.memory, &result.jacobian_rhs_evaluations);
    result.jacobian_rhs_evaluations += data.fallback_rhs_evaluations;
    return result;
}

}  // namespace rollgap::core
