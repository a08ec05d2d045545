#pragma once
// The interface the dynamic analyses take (docs/model.md §6): linearisation, time integration,
// the critical-speed search and the limit margins see a state vector z, its right-hand side and
// where each stand's masses sit in it, never the concrete model. The single stand
// (core/coupled_model.h) is one stand block and its span elements; a mill is more of both.

#include <Eigen/Dense>

namespace rollgap::core {

// Why a state has no valid right-hand side, or why a run ended.
enum class DynamicsStatus { ok, contact_lost, skidding, slack_strip, solver_failure, cancelled };
const char* to_string(DynamicsStatus);

struct Linearisation {
    DynamicsStatus status = DynamicsStatus::solver_failure;
    Eigen::MatrixXd jacobian;
};

class DynamicModel {
public:
    DynamicModel() = default;
    DynamicModel(const DynamicModel&) = default;
    DynamicModel& operator=(const DynamicModel&) = default;
    DynamicModel(DynamicModel&&) = default;
    DynamicModel& operator=(DynamicModel&&) = default;
    virtual ~DynamicModel() = default;

    // The state: its size and the steady state z0 the dynamics start from (f(z0) = 0).
    virtual int size() const = 0;
    virtual Eigen::VectorXd equilibrium() const = 0;

    // z' = f(t, z); a state without one (a physical limit, a bite that does not solve) is a
    // status, never an exception.
    virtual DynamicsStatus rhs(double t, const double* z, double* zdot) const = 0;

    // Per component: the central-difference step of the linearisation at z and the absolute
    // tolerance of time integration (docs/model.md §6, §7.3), in the component's own unit.
    virtual double perturbation(int index, const Eigen::VectorXd& z) const = 0;
    virtual double absolute_tolerance(int index) const = 0;

    // Signed distances to the physical limits that have a cheap test, positive inside; time
    // integration stops where one crosses zero, with margin_status(index) as the result.
    virtual int margin_count() const = 0;
    virtual void limit_margins(double t, const double* z, double* margins) const = 0;
    virtual DynamicsStatus margin_status(int index) const = 0;

    // The output map: stand i's six mass displacements q1..q6 are z[displacement_index(i) + k];
    // mode shapes are read there.
    virtual int stand_count() const = 0;
    virtual int displacement_index(int stand) const = 0;

    // J = df/dz at (t, z). The default is central differences with perturbation(); a model
    // with an assembled Jacobian overrides it (DECISIONS R, P).
    virtual Linearisation jacobian(const Eigen::VectorXd& z, double t) const;
};

// Central differences of f at (t, z) with the model's perturbation() steps.
Linearisation finite_difference_jacobian(const DynamicModel& model, const Eigen::VectorXd& z,
                                         double t);

}  // namespace rollgap::core
