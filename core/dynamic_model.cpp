#include "core/dynamic_model.h"

namespace rollgap::core {

const char* to_string(DynamicsStatus status) {
    switch (status) {
        case DynamicsStatus::ok: return "ok";
        case DynamicsStatus::contact_lost: return "contact_lost";
        case DynamicsStatus::skidding: return "skidding";
        case DynamicsStatus::slack_strip: return "slack_strip";
        case DynamicsStatus::solver_failure: return "solver_failure";
        case DynamicsStatus::cancelled: return "cancelled";
    }
    return "unknown";
}

Linearisation DynamicModel::jacobian(const Eigen::VectorXd& z, double t) const {
    return finite_difference_jacobian(*this, z, t);
}

Linearisation finite_difference_jacobian(const DynamicModel& model, const Eigen::VectorXd& z,
                                         double t) {
    Linearisation out;
    const int n = model.size();
    out.jacobian = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd plus(n), minus(n), f_plus(n), f_minus(n);
    for (int j = 0; j < n; ++j) {
        const double delta = model.perturbation(j, z);
        plus = z;
        minus = z;
        plus(j) += delta;
        minus(j) -= delta;
        const DynamicsStatus a = model.rhs(t, plus.data(), f_plus.data());
        const DynamicsStatus b = model.rhs(t, minus.data(), f_minus.data());
        if (a != DynamicsStatus::ok || b != DynamicsStatus::ok) {
            out.status = a != DynamicsStatus::ok ? a : b;
            return out;
        }
        out.jacobian.col(j) = (f_plus - f_minus) / (plus(j) - minus(j));
    }
    out.status = DynamicsStatus::ok;
    return out;
}

}  // namespace rollgap::core
