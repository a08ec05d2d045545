#pragma once
// What the CVODE runs share (core/time_integration.cpp, the single stand and any DynamicModel;
// core/mill/mill_time.cpp, the mill with its thickness transport as a history): the owner of one
// run's SUNDIALS objects, the silenced error handler (failures are statuses, docs/model.md §6)
// and the words for why a run ended.

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "core/dynamic_model.h"

namespace rollgap::core::cvode {

// Owns the SUNDIALS objects of one run (one context per solver instance).
struct Cvode {
    SUNContext context = nullptr;
    N_Vector y = nullptr, abstol = nullptr, ydot = nullptr;
    SUNMatrix matrix = nullptr;
    SUNLinearSolver solver = nullptr;
    void* memory = nullptr;

    Cvode() = default;
    Cvode(const Cvode&) = delete;
    Cvode& operator=(const Cvode&) = delete;
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

// A run's failures are reported as statuses, not printed.
inline void silent_errors(int, const char*, const char*, char*, void*) {}

// BDF with a dense direct linear solver for n states (docs/model.md §6: the film relaxes in
// microseconds while the stands vibrate at ~100-500 Hz), started at (t0, y0) with per-component
// absolute tolerances `abstol` and the relative tolerance `rtol`, the right-hand side `rhs` and
// the Jacobian `jacobian` on `user_data`. Returns "" or what failed.
inline const char* setup(Cvode& cv, int n, double t0, const double* y0, const double* abstol,
                         double rtol, CVRhsFn rhs, CVLsJacFn jacobian, void* user_data) {
    if (SUNContext_Create(nullptr, &cv.context) != 0)
        return "SUNDIALS context could not be created";
    cv.y = N_VNew_Serial(n, cv.context);
    cv.abstol = N_VNew_Serial(n, cv.context);
    cv.ydot = N_VNew_Serial(n, cv.context);
    cv.memory = CVodeCreate(CV_BDF, cv.context);
    if (!cv.y || !cv.abstol || !cv.ydot || !cv.memory) return "CVODE could not be allocated";
    double* y = N_VGetArrayPointer(cv.y);
    double* tol = N_VGetArrayPointer(cv.abstol);
    for (int i = 0; i < n; ++i) {
        y[i] = y0[i];
        tol[i] = abstol[i];
    }
    CVodeSetErrHandlerFn(cv.memory, silent_errors, nullptr);
    if (CVodeInit(cv.memory, rhs, t0, cv.y) != CV_SUCCESS ||
        CVodeSVtolerances(cv.memory, rtol, cv.abstol) != CV_SUCCESS)
        return "CVODE initialisation failed";
    cv.matrix = SUNDenseMatrix(n, n, cv.context);
    cv.solver = SUNLinSol_Dense(cv.y, cv.matrix, cv.context);
    if (!cv.matrix || !cv.solver ||
        CVodeSetLinearSolver(cv.memory, cv.solver, cv.matrix) != CV_SUCCESS)
        return "CVODE linear solver setup failed";
    CVodeSetUserData(cv.memory, user_data);
    CVodeSetJacFn(cv.memory, jacobian);
    return "";
}

// Why a run ended early, for the user: the physical limits and the one non-physical end, a state
// where the model has no answer (the inlet film squeezed to nothing, a bite that does not solve).
inline const char* end_message(DynamicsStatus status) {
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

}  // namespace rollgap::core::cvode
