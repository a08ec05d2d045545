#pragma once
// The mill's regenerative path (docs/model.md §12.5): the frozen transfer M(s) from the thickness
// entering stands 2..N to the exit thicknesses of stands 1..N-1, in the modal basis of A0, and
// the regenerative margin rho = max over omega of the structured bound of M(i omega). With the
// transport's delays the loop closes as u = E(s) M(s) u, E = diag(exp(-s tau_i)); on the
// imaginary axis E is any diagonal of unit-modulus phases, so the mill is stable for every set of
// delays if A0 is stable and rho < 1 (and only if, for up to three spans, where the bound is
// exact).

#include <complex>
#include <vector>

#include <Eigen/Dense>

#include "core/mill/mill_model.h"

namespace rollgap::core {

// M(s) = C (sI - A0)^-1 (B + s B') = (C V) diag(1 / (s - lambda)) V^-1 (B + s B'), V the
// eigenvectors of A0 (balanced coordinates; ~1 us an evaluation at 5 stands instead of an LU of
// the whole mill per frequency).
struct TransportTransfer {
    bool ok = false;
    Eigen::VectorXcd poles;       // the eigenvalues of A0, 1/s
    Eigen::MatrixXcd output;      // C V, p x n
    Eigen::MatrixXcd input;       // V^-1 B, n x p
    Eigen::MatrixXcd input_rate;  // V^-1 B', n x p
    std::vector<double> delay;    // tau_i, s
    Eigen::MatrixXcd modes;       // V, A0's right eigenvectors in the mill's coordinates
    double frozen_max_real_part = 0.0;

    int spans() const { return static_cast<int>(input.cols()); }
    Eigen::MatrixXcd at(std::complex<double> s) const;
};

TransportTransfer transport_transfer(const MillLinearisation& linearisation);

// The frozen mill's state response to the entering thicknesses u at s:
// z = (sI - A0)^-1 (B + sB') u, in the modal basis.
Eigen::VectorXcd transport_response(const TransportTransfer& transfer, std::complex<double> s,
                                    const Eigen::VectorXcd& u);

// The mill's state vector of a root s of det(I - M(s) E(s)) = 0: z = (sI - A0)^-1 (B + sB') E u
// with u the loop's null vector (the right singular vector of I - M E for its smallest singular
// value), scaled to |z| = 1.
Eigen::VectorXcd delay_root_vector(const TransportTransfer& transfer, std::complex<double> s);

// min over positive diagonal D of the largest singular value of D M D^-1: an upper bound of the
// structured singular value of M for independent complex scalars (the delays' phases), exact for
// up to three (docs/model.md §12.5). log sigma(e^X M e^-X) is convex in the diagonal X: the
// minimum is found by Osborne's balancing of |M| and then cyclic golden-section searches on each
// log d_i. `scaling` (optional) receives D (d_0 = 1).
double structured_bound(const Eigen::MatrixXcd& m, Eigen::VectorXd* scaling = nullptr);

// sigma(D M D^-1) with D from Osborne's balancing of |M| alone: an upper bound of the same
// structured singular value (any D gives one), microseconds. With `enough` > 0, where the
// Frobenius norm of D M D^-1 (>= sigma) is already below `enough`, that norm instead: for a
// caller that only asks whether the bound is below `enough` (the counts' small-gain test), the
// same answer without the singular value.
double balanced_bound(const Eigen::MatrixXcd& m, double enough = 0.0);

struct RegenerativeOptions {
    double frequency_min_Hz = 1.0;
    double frequency_max_Hz = 2000.0;
    int grid = 400;  // log-spaced frequencies, plus every pole's own frequency in the range
};

struct RegenerativeMargin {
    bool ok = false;
    bool frozen_stable = false;  // rho is a margin only where A0 is stable
    bool exact = false;          // one to three spans: rho < 1 is necessary as well
    double margin = 0.0;         // rho
    double frequency_Hz = 0.0;   // where the bound peaks
    Eigen::VectorXd scaling;     // D there
    Eigen::MatrixXcd transfer;   // M(i omega) there
    int evaluations = 0;         // M(i omega) evaluated
};

RegenerativeMargin regenerative_margin(const TransportTransfer& transfer,
                                       const RegenerativeOptions& options = {});

// The loop's worst input at the margin's peak: u = D^-1 v, v the top right singular vector of
// D M D^-1 (M and D there); empty when the margin holds no peak.
Eigen::VectorXcd margin_worst_input(const RegenerativeMargin& margin);

}  // namespace rollgap::core
