#pragma once
// The least-damped oscillatory eigenpair of the coupled model's linearisation, computed in the
// tests on an explicitly scaled Jacobian (independently of core's balancing).

#include <complex>

#include <Eigen/Dense>

#include "core/stability.h"

namespace rollgap::test {

struct Eigenpair {
    std::complex<double> value;
    Eigen::VectorXcd vector;  // in the model's own state coordinates
};

inline Eigenpair least_damped_mode(const core::CoupledModel& model) {
    const Eigen::VectorXd z0 = model.equilibrium();
    const Eigen::MatrixXd J = core::linearise(model, z0).jacobian;
    const int n = model.size();
    Eigen::VectorXd scale(n);  // characteristic sizes: 1 um, 1 mm/s, the film, 1 MPa
    for (int j = 0; j < n; ++j)
        scale(j) = j < 6 ? 1e-6 : j < 12 ? 1e-3 : j == core::CoupledModel::film_index ? z0(j) : 1e6;
    Eigen::EigenSolver<Eigen::MatrixXd> solver(scale.cwiseInverse().asDiagonal() * J *
                                               scale.asDiagonal());
    int best = -1;
    for (int i = 0; i < n; ++i) {
        const auto lambda = solver.eigenvalues()(i);
        if (lambda.imag() > 0 && (best < 0 || lambda.real() > solver.eigenvalues()(best).real()))
            best = i;
    }
    return {solver.eigenvalues()(best),
            scale.cast<std::complex<double>>().asDiagonal() * solver.eigenvectors().col(best)};
}

}  // namespace rollgap::test
