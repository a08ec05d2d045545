#include "core/stand_structure.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rollgap::core {

RayleighCoefficients rayleigh_coefficients(double damping_ratio, double low_frequency_Hz,
                                           double high_frequency_Hz) {
    const double w1 = 2.0 * std::numbers::pi * low_frequency_Hz;
    const double w2 = 2.0 * std::numbers::pi * high_frequency_Hz;
    return {2.0 * damping_ratio * w1 * w2 / (w1 + w2), 2.0 * damping_ratio / (w1 + w2)};
}

namespace {

// A spring or damper of value `value` between masses i and j (j < 0: the ground).
void connect(Matrix6& matrix, int i, int j, double value) {
    matrix(i, i) += value;
    if (j < 0) return;
    matrix(j, j) += value;
    matrix(i, j) -= value;
    matrix(j, i) -= value;
}

}  // namespace

StructureMatrices structure_matrices(const StandStructure& structure) {
    StructureMatrices m;
    m.mass = Matrix6::Zero();
    for (int i = 0; i < 6; ++i) m.mass(i, i) = structure.mass[static_cast<std::size_t>(i)];

    // eq. (37), masses 0..5 = m1..m6; k4 (masses 2-3) is the strip and stays out of K_s
    m.structural_stiffness = Matrix6::Zero();
    connect(m.structural_stiffness, 0, -1, structure.k1);
    connect(m.structural_stiffness, 0, 1, structure.k2);
    connect(m.structural_stiffness, 1, 2, structure.k3);
    connect(m.structural_stiffness, 3, 4, structure.k5);
    connect(m.structural_stiffness, 4, 5, structure.k6);
    connect(m.structural_stiffness, 5, -1, structure.k7);

    m.damping = Matrix6::Zero();
    connect(m.damping, 0, 1, structure.c1);
    connect(m.damping, 2, 3, structure.c2);
    if (structure.rayleigh) {
        m.rayleigh = rayleigh_coefficients(structure.rayleigh_damping_ratio,
                                           structure.rayleigh_frequency_low,
                                           structure.rayleigh_frequency_high);
        m.damping += m.rayleigh.alpha * m.mass + m.rayleigh.beta * m.structural_stiffness;
    }
    return m;
}

Vector6 gap_direction() {
    Vector6 b = Vector6::Zero();
    b(2) = 1.0;
    b(3) = -1.0;
    return b;
}

Matrix6 total_stiffness(const StructureMatrices& m, double strip_stiffness) {
    const Vector6 b = gap_direction();
    return m.structural_stiffness + strip_stiffness * b * b.transpose();
}

ModalAnalysis modal_analysis(const StructureMatrices& m, double strip_stiffness) {
    ModalAnalysis out;
    const Matrix6 K = total_stiffness(m, strip_stiffness);

    Eigen::GeneralizedSelfAdjointEigenSolver<Matrix6> undamped(K, m.mass);
    if (undamped.info() != Eigen::Success) return out;
    for (int i = 0; i < 6; ++i) {
        Vector6 shape = undamped.eigenvectors().col(i);
        Eigen::Index largest;
        shape.cwiseAbs().maxCoeff(&largest);
        if (shape(largest) < 0) shape = -shape;
        const double omega2 = std::max(0.0, undamped.eigenvalues()(i));
        out.natural.push_back({std::sqrt(omega2) / (2.0 * std::numbers::pi), shape});
    }

    // first-order form z = (q, q'): A = [0 I; -M^-1 K  -M^-1 C]
    Eigen::Matrix<double, 12, 12> A = Eigen::Matrix<double, 12, 12>::Zero();
    const Matrix6 Minv = m.mass.inverse();
    A.topRightCorner<6, 6>() = Matrix6::Identity();
    A.bottomLeftCorner<6, 6>() = -Minv * K;
    A.bottomRightCorner<6, 6>() = -Minv * m.damping;
    Eigen::EigenSolver<Eigen::Matrix<double, 12, 12>> damped(A);
    if (damped.info() != Eigen::Success) return out;
    for (int i = 0; i < 12; ++i) {
        const std::complex<double> lambda = damped.eigenvalues()(i);
        if (lambda.imag() <= 0.0) continue;
        DampedMode mode;
        mode.eigenvalue = lambda;
        mode.frequency_Hz = lambda.imag() / (2.0 * std::numbers::pi);
        mode.damping_ratio = -lambda.real() / std::abs(lambda);
        const Vector6 magnitude = damped.eigenvectors().col(i).head<6>().cwiseAbs();
        mode.shape = magnitude / magnitude.maxCoeff();
        out.damped.push_back(mode);
    }
    std::sort(out.damped.begin(), out.damped.end(), [](const DampedMode& a, const DampedMode& b) {
        return a.frequency_Hz < b.frequency_Hz;
    });
    out.ok = true;
    return out;
}

}  // namespace rollgap::core
