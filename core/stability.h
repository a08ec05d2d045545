#pragma once
// Linear stability of the coupled model about its steady operating point, and the critical
// rolling speed (docs/model.md §7.3).

#include <complex>
#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "core/chatter_type.h"
#include "core/control.h"
#include "core/coupled_model.h"
#include "core/dynamic_model.h"

namespace rollgap::core {

// The model's jacobian() at (t, z): by default central differences with the model document's
// steps (q 1e-7 m, q' 1e-3 m/s, h0 1e-5 h0, tensions 1 kPa; core/dynamic_model.h); the coupled
// model's is assembled from the bite linearisation with the same steps (docs/model.md §6.1).
Linearisation linearise(const DynamicModel& model, const Eigen::VectorXd& z, double t = 0.0);

// Eigenvalues of a Jacobian after Parlett-Reinsch balancing (the coupled model's Jacobian
// mixes entries from 1e-13 to 1e14; unbalanced, the QR iteration is wrong by O(10/s)).
// Empty when the eigenvalue iteration fails.
Eigen::VectorXcd balanced_eigenvalues(const Eigen::MatrixXd& jacobian);

// Eigenvalues and right eigenvectors (columns, in the original coordinates) of a Jacobian after
// the same balancing. ok false when the iteration fails.
struct Eigensystem {
    bool ok = false;
    Eigen::VectorXcd values;
    Eigen::MatrixXcd vectors;
    // the balancing: vectors = scale .* balanced_vectors, the eigenvectors of S^-1 J S, whose
    // inverse is well conditioned where the original's rows span 27 decades
    Eigen::VectorXd scale;
    Eigen::MatrixXcd balanced_vectors;
};
Eigensystem eigensystem(const Eigen::MatrixXd& jacobian);

struct Eigenmode {
    std::complex<double> eigenvalue;  // 1/s
    double frequency_Hz = 0.0;        // Im / 2 pi
    double damping_ratio = 1.0;       // -Re / |lambda|
    // One entry per stand (the single stand has one), in the model's stand order:
    // |q| per mass (m1..m6), scaled so that the largest component over all stands is 1
    std::vector<Vector6> shapes = {Vector6::Zero()};
    // q per mass with its phase, on the same scale (the largest component is 1, real): which
    // masses move with and against which, the basis of the chatter type
    std::vector<Vector6c> displacements = {Vector6c::Zero()};
    // from the displacements of the stand that moves most, and the frequency
    ChatterClassification chatter;
};

struct SpeedStability {
    double speed = 0.0;
    BiteStatus steady_status = BiteStatus::solver_failure;  // no steady state unless ok
    DynamicsStatus status = DynamicsStatus::solver_failure;
    bool stable = false;
    double max_real_part = 0.0;          // over all eigenvalues, 1/s
    Eigenmode least_damped;              // the oscillatory eigenvalue with the largest real part
    std::vector<Eigenmode> oscillatory;  // Im > 0, ascending frequency
    std::vector<std::complex<double>> eigenvalues;
    double strip_stiffness = 0.0;
    double force = 0.0;
};

// Eigenvalues of the linearisation at the scenario's own speed.
SpeedStability stability_at(const Scenario& s);

// The eigenvalues and modes of any model linearised at its equilibrium (the speed, steady status,
// force and k4 are the caller's to fill). Mode shapes are read at stand 0's displacements.
SpeedStability linear_stability(const DynamicModel& model);

struct CriticalSpeedOptions {
    double speed_min = 1.0;   // m/s
    double speed_max = 60.0;  // m/s
    double speed_step = 0.5;  // m/s, at most 0.5
    double relative_tolerance = 1e-4;
    // Scan the grid only up to its first crossing (docs/model.md §7.3): the status, the critical
    // speed and its mode are the full scan's, as they depend on no speed above the crossing;
    // `scan` and `branches` then stop there. For callers that report no scan (a summary, a
    // sweep, a map, a calibration).
    bool stop_at_crossing = false;
};

enum class CriticalSpeedStatus {
    found,
    stable_in_range,
    unstable_at_lower_bound,
    no_steady_state,
    cancelled
};
const char* to_string(CriticalSpeedStatus);

// One oscillatory eigenvalue followed over speed by frequency continuity.
struct DampingBranch {
    std::vector<double> speed, frequency_Hz, damping_ratio;
};

struct CriticalSpeedResult {
    CriticalSpeedStatus status = CriticalSpeedStatus::no_steady_state;
    double critical_speed = 0.0;       // m/s, when found
    Eigenmode unstable_mode;           // the eigenvalue crossing zero there
    std::vector<SpeedStability> scan;  // without the per-speed mode lists
    std::vector<DampingBranch> branches;
};

// The scan speeds run in parallel on the executor and thread budget of `control`.
CriticalSpeedResult critical_speed(const Scenario& s, const CriticalSpeedOptions& options = {},
                                   const Control& control = {});

// The search behind critical_speed() for any model: `analyse_at(speed, with_strip_stiffness)`
// is the stability at one speed (called concurrently from the scan; k4 only where a result
// reports it). A mill passes its own.
using StabilityAtSpeed = std::function<SpeedStability(double speed, bool with_strip_stiffness)>;
CriticalSpeedResult critical_speed_search(const StabilityAtSpeed& analyse_at,
                                          const CriticalSpeedOptions& options = {},
                                          const Control& control = {});

}  // namespace rollgap::core
