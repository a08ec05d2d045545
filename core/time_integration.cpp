#include "core/time_integration.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <memory>
#include <vector>

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

void silent_errors(int, const char*, const char*, char*, void*) {}

// Owns the SUNDIALS objects of one run (one context per solver instance).
struct Cvode {
    SUNContext context = nullptr;
    N_Vector y = nullptr, abstol = nullptr, ydot = nullptr;
    SUNMatrix matrix = nullptr;
    SUNLinearSolver solver = nullptr;
    void* memory = nullptr;
    ~Cvode() {
        if (memory) CVodeFree(&memory);
        if (solver) SUNLinSolFree(solver);
        if (matrix) SUNMatDestroy(matrix);
        if (y) N_VDestroy(y);
        if (abstol) N_VDestroy(abstol);
        if (ydot) N_VDestroy(ydot);
        if (context) SUNContext_Free(&context);
    }
};

// Why a run ended early, for the user: the physical limits and the one non-physical end, a state
// where the model has no answer (the inlet film squeezed to nothing, a bite that does not solve).
const char* end_message(DynamicsStatus status) {
    switch (status) {
        case DynamicsStatus::contact_lost:
            return "the gap opened past the entry thickness: the rolls lost the strip";
        case DynamicsStatus::skidding:
            return "the rolls skid on the strip (no neutral point in the bite)";
        case DynamicsStatus::slack_strip:
            return "a strip tension fell to zero: the strip went slack";
        case DynamicsStatus::solver_failure:
            return "the model has no state here: the inlet film collapsed or the roll bite did not solve";
        case DynamicsStatus::cancelled: return "cancelled";
        case DynamicsStatus::ok: break;
    }
    return "ok";
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

    Cvode cv;
    if (SUNContext_Create(nullptr, &cv.context) != 0) {
        result.message = "SUNDIALS context could not be created";
        return result;
    }
    cv.y = N_VNew_Serial(n, cv.context);
    cv.abstol = N_VNew_Serial(n, cv.context);
    cv.ydot = N_VNew_Serial(n, cv.context);
    cv.memory = CVodeCreate(CV_BDF, cv.context);
    if (!cv.y || !cv.abstol || !cv.ydot || !cv.memory) {
        result.message = "CVODE could not be allocated";
        return result;
    }
    double* y = N_VGetArrayPointer(cv.y);
    double* tol = N_VGetArrayPointer(cv.abstol);
    for (int i = 0; i < n; ++i) {
        y[i] = z(i);
        // docs/model.md §6: q 1e-10 m, q' 1e-7 m/s, h0 1e-12 m, tensions 1 Pa
        tol[i] = model.absolute_tolerance(i);
    }
    CVodeSetErrHandlerFn(cv.memory, silent_errors, nullptr);
    if (CVodeInit(cv.memory, right_hand_side, t0, cv.y) != CV_SUCCESS ||
        CVodeSVtolerances(cv.memory, options.relative_tolerance, cv.abstol) != CV_SUCCESS) {
        result.message = "CVODE initialisation failed";
        return result;
    }
    cv.matrix = SUNDenseMatrix(n, n, cv.context);
    cv.solver = SUNLinSol_Dense(cv.y, cv.matrix, cv.context);
    if (!cv.matrix || !cv.solver ||
        CVodeSetLinearSolver(cv.memory, cv.solver, cv.matrix) != CV_SUCCESS) {
        result.message = "CVODE linear solver setup failed";
        return result;
    }
    CVodeSetUserData(cv.memory, &data);
    CVodeSetJacFn(cv.memory, jacobian);
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
                result.message = end_message(result.status);
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
                                 ? end_message(data.last_failure)
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
