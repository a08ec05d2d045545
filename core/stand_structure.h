#pragma once
// The six-mass structure of one stand, eq. (37) (crossheads, backup and work rolls), with the
// mass mapping of docs/model.md §5:
//   M q'' + C q' + K q = b dP,  b = e3 - e4,  K = K_s + k4 b b^T,
// where K_s is the structure without the strip spring k4 and the gap is g = x3 - x4.

#include <complex>
#include <vector>

#include <Eigen/Dense>

#include "core/scenario.h"

namespace rollgap::core {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// Rayleigh damping C = alpha M + beta K with damping ratio zeta at two frequencies:
// zeta(omega) = alpha / (2 omega) + beta omega / 2 equals zeta at both.
struct RayleighCoefficients {
    double alpha = 0.0;  // 1/s
    double beta = 0.0;   // s
};
RayleighCoefficients rayleigh_coefficients(double damping_ratio, double low_frequency_Hz,
                                           double high_frequency_Hz);

struct StructureMatrices {
    Matrix6 mass;
    Matrix6 structural_stiffness;  // K_s, without k4
    Matrix6 damping;               // c1, c2 and, if enabled, alpha M + beta K_s
    RayleighCoefficients rayleigh;
};

StructureMatrices structure_matrices(const StandStructure& structure);

// b = e3 - e4: +dP pushes the upper work roll up and the lower one down.
Vector6 gap_direction();

// K_s + k4 b b^T.
Matrix6 total_stiffness(const StructureMatrices& m, double strip_stiffness);

struct NaturalMode {
    double frequency_Hz;
    Vector6 shape;  // mass-normalised, largest component positive
};

struct DampedMode {
    std::complex<double> eigenvalue;  // 1/s
    double frequency_Hz;              // |Im| / 2 pi
    double damping_ratio;             // -Re / |lambda|
    Vector6 shape;                    // |displacement| per mass, normalised to max 1
};

struct ModalAnalysis {
    bool ok = false;
    std::vector<NaturalMode> natural;  // of (M, K), ascending frequency
    std::vector<DampedMode>
        damped;  // of (M, C, K), oscillatory pairs once (Im > 0), ascending frequency
};

ModalAnalysis modal_analysis(const StructureMatrices& m, double strip_stiffness);

}  // namespace rollgap::core
