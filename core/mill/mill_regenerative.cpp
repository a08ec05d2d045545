#include "core/mill/mill_regenerative.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/golden_section.h"
#include "core/stability.h"

namespace rollgap::core {

TransportTransfer transport_transfer(const MillLinearisation& lin) {
    TransportTransfer out;
    if (lin.status != DynamicsStatus::ok) return out;
    const Eigensystem eig = eigensystem(lin.jacobian);
    if (!eig.ok) return out;
    out.poles = eig.values;
    out.modes = eig.vectors;
    out.delay = lin.delay;
    out.frozen_max_real_part = eig.values.real().maxCoeff();
    const Eigen::Index n = lin.jacobian.rows(), p = lin.input.cols();
    if (p == 0) {  // one stand: no transport, M is 0 x 0
        out.input = out.input_rate = Eigen::MatrixXcd::Zero(n, 0);
        out.output = Eigen::MatrixXcd::Zero(0, n);
        out.ok = true;
        return out;
    }
    // in balanced coordinates z = S zb: A0b = S^-1 A0 S, Bb = S^-1 B, Cb = C S
    const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(eig.balanced_vectors);
    const Eigen::VectorXcd inverse_scale = eig.scale.cwiseInverse().cast<std::complex<double>>();
    out.input = lu.solve(inverse_scale.asDiagonal() * lin.input.cast<std::complex<double>>());
    out.input_rate =
        lu.solve(inverse_scale.asDiagonal() * lin.input_rate.cast<std::complex<double>>());
    out.output = lin.output.cast<std::complex<double>>() *
                 eig.scale.cast<std::complex<double>>().asDiagonal() * eig.balanced_vectors;
    out.ok = out.input.allFinite() && out.input_rate.allFinite() && out.output.allFinite();
    return out;
}

namespace {

// M(s) for P spans (P = 0: any count): the sum over the modes k of (C V)_k r_k
// (V^-1 (B + s B'))_k, a rank-one update per mode, in real arithmetic on the parts (no library
// call per complex product or quotient; 1 / (s - lambda) as conj / |.|^2, the library's overflow
// guard being moot at distances of 1e-12 .. 1e9) with the accumulators in fixed-size arrays
// the compiler keeps in registers. A p x n by n x p product is too small for the blocked GEMM,
// which cost ten times more; the counts of docs/model.md §12.6 evaluate M ~10^3 times a speed.
template <int P>
Eigen::MatrixXcd transfer_at(const TransportTransfer& t, std::complex<double> s) {
    const Eigen::Index n = t.poles.size(), p = P > 0 ? P : t.input.cols();
    constexpr std::size_t fixed = P > 0 ? static_cast<std::size_t>(P * P) : 1;
    std::array<double, fixed> fixed_re{}, fixed_im{};
    std::vector<double> any_re, any_im;
    double* re = fixed_re.data();
    double* im = fixed_im.data();
    if constexpr (P == 0) {
        any_re.assign(static_cast<std::size_t>(p * p), 0.0);
        any_im.assign(any_re.size(), 0.0);
        re = any_re.data();
        im = any_im.data();
    }
    const double sr = s.real(), si = s.imag();
    const std::complex<double>* poles = t.poles.data();
    const std::complex<double>* input = t.input.data();
    const std::complex<double>* rate = t.input_rate.data();
    const std::complex<double>* output = t.output.data();
    for (Eigen::Index k = 0; k < n; ++k) {
        const double dr = sr - poles[k].real(), di = si - poles[k].imag();
        const double norm = dr * dr + di * di;
        const double rr = dr / norm, ri = -di / norm;    // 1 / (s - lambda_k)
        const std::complex<double>* c = output + k * p;  // column k of C V
        for (Eigen::Index j = 0; j < p; ++j) {
            const std::complex<double> b = input[k + j * n], b_rate = rate[k + j * n];
            // (b + s b') / (s - lambda_k)
            const double xr = b.real() + sr * b_rate.real() - si * b_rate.imag();
            const double xi = b.imag() + sr * b_rate.imag() + si * b_rate.real();
            const double yr = xr * rr - xi * ri, yi = xr * ri + xi * rr;
            for (Eigen::Index i = 0; i < p; ++i) {
                re[j * p + i] += c[i].real() * yr - c[i].imag() * yi;
                im[j * p + i] += c[i].real() * yi + c[i].imag() * yr;
            }
        }
    }
    Eigen::MatrixXcd m(p, p);
    for (Eigen::Index j = 0; j < p; ++j)
        for (Eigen::Index i = 0; i < p; ++i) m(i, j) = {re[j * p + i], im[j * p + i]};
    return m;
}

}  // namespace

Eigen::MatrixXcd TransportTransfer::at(std::complex<double> s) const {
    switch (input.cols()) {
        case 0: return Eigen::MatrixXcd(0, 0);
        case 1: return transfer_at<1>(*this, s);
        case 2: return transfer_at<2>(*this, s);
        case 3: return transfer_at<3>(*this, s);
        case 4: return transfer_at<4>(*this, s);
        case 5: return transfer_at<5>(*this, s);
        default: return transfer_at<0>(*this, s);
    }
}

Eigen::VectorXcd delay_root_vector(const TransportTransfer& transfer, std::complex<double> s) {
    const Eigen::Index n = transfer.poles.size(), p = transfer.spans();
    if (p == 0) return Eigen::VectorXcd::Zero(n);
    Eigen::VectorXcd e(p);
    for (Eigen::Index j = 0; j < p; ++j)
        e(j) = std::exp(-s * transfer.delay[static_cast<std::size_t>(j)]);
    const Eigen::MatrixXcd loop =
        Eigen::MatrixXcd::Identity(p, p) - transfer.at(s) * e.asDiagonal();
    const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(loop, Eigen::ComputeFullV);
    Eigen::VectorXcd z = transport_response(transfer, s, e.asDiagonal() * svd.matrixV().col(p - 1));
    const double norm = z.norm();
    if (norm > 0.0) z /= norm;
    return z;
}

Eigen::VectorXcd transport_response(const TransportTransfer& transfer, std::complex<double> s,
                                    const Eigen::VectorXcd& u) {
    const Eigen::Index n = transfer.poles.size();
    const Eigen::VectorXcd forcing = (transfer.input + s * transfer.input_rate) * u;
    Eigen::VectorXcd modal(n);
    for (Eigen::Index k = 0; k < n; ++k) modal(k) = forcing(k) / (s - transfer.poles(k));
    return transfer.modes * modal;
}

namespace {

// The largest singular value: the square root of the largest eigenvalue of the Hermitian
// m^H m (p <= 5; an order cheaper than a Jacobi SVD, and as accurate for the largest value).
double largest_singular_value(const Eigen::MatrixXcd& m) {
    if (m.size() == 1) return std::abs(m(0, 0));
    const Eigen::MatrixXcd gram = m.adjoint() * m;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(gram, Eigen::EigenvaluesOnly);
    return std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0));
}

double scaled(const Eigen::MatrixXcd& m, const Eigen::VectorXd& x) {
    const Eigen::Index p = m.rows();
    const Eigen::VectorXd d = x.array().exp();
    Eigen::MatrixXcd s(p, p);
    for (Eigen::Index j = 0; j < p; ++j)
        for (Eigen::Index i = 0; i < p; ++i) s(i, j) = m(i, j) * (d(i) / d(j));
    return largest_singular_value(s);
}

// Osborne's balancing of |M|: log d evening out each row's and column's off-diagonal norms of
// |D M D^-1| (a start for the bound, and a bound itself). d_0 = 1.
Eigen::VectorXd osborne(const Eigen::MatrixXcd& m, int sweeps) {
    const Eigen::Index p = m.rows();
    Eigen::VectorXd x = Eigen::VectorXd::Zero(p);
    Eigen::VectorXd d = Eigen::VectorXd::Ones(p);  // exp(x)
    const Eigen::MatrixXd a = m.cwiseAbs2();
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        for (Eigen::Index i = 0; i < p; ++i) {
            double row = 0.0, col = 0.0;
            for (Eigen::Index j = 0; j < p; ++j) {
                if (j == i) continue;
                const double ratio = d(i) / d(j);
                row += a(i, j) * ratio * ratio;
                col += a(j, i) / (ratio * ratio);
            }
            if (row > 0.0 && col > 0.0) {
                x(i) += 0.25 * std::log(col / row);
                d(i) = std::exp(x(i));
            }
        }
    }
    if (p > 0) x.array() -= x(0);
    return x;
}

}  // namespace

double structured_bound(const Eigen::MatrixXcd& m, Eigen::VectorXd* scaling) {
    const Eigen::Index p = m.rows();
    Eigen::VectorXd x = Eigen::VectorXd::Zero(p);  // log d: no scaling, or Osborne's if better
    if (p > 1) {
        const Eigen::VectorXd balanced = osborne(m, 20);
        if (scaled(m, balanced) < scaled(m, x)) x = balanced;
        // cyclic golden-section searches on each log d_i (i >= 1), the function convex in x
        for (int sweep = 0; sweep < 3; ++sweep) {
            for (Eigen::Index i = 1; i < p; ++i) {
                Eigen::VectorXd trial = x;
                const auto f = [&](double xi) {
                    trial(i) = xi;
                    return scaled(m, trial);
                };
                const double best = golden_section_minimum(f, x(i) - 8.0, x(i) + 8.0, 40).x;
                trial(i) = best;
                if (scaled(m, trial) < scaled(m, x)) x(i) = best;
            }
        }
    }
    if (scaling) *scaling = x.array().exp();
    return p == 0 ? 0.0 : scaled(m, x);
}

double balanced_bound(const Eigen::MatrixXcd& m, double enough) {
    if (m.rows() == 0) return 0.0;
    if (m.rows() == 1) return std::abs(m(0, 0));
    const Eigen::VectorXd x = osborne(m, 10);
    if (enough > 0.0) {
        // the Frobenius norm bounds sigma from above: below `enough` it answers the question
        const Eigen::VectorXd d = x.array().exp();
        double sum = 0.0;
        for (Eigen::Index j = 0; j < m.cols(); ++j)
            for (Eigen::Index i = 0; i < m.rows(); ++i)
                sum += std::norm(m(i, j)) * d(i) * d(i) / (d(j) * d(j));
        const double frobenius = std::sqrt(sum);
        if (frobenius < enough) return frobenius;
    }
    return scaled(m, x);
}

RegenerativeMargin regenerative_margin(const TransportTransfer& transfer,
                                       const RegenerativeOptions& options) {
    RegenerativeMargin out;
    if (!transfer.ok) return out;
    out.ok = true;
    out.frozen_stable = transfer.frozen_max_real_part < 0.0;
    out.exact = transfer.spans() <= 3;
    if (transfer.spans() == 0) return out;  // one stand: no transport
    constexpr double two_pi = 2.0 * std::numbers::pi;
    const double lo = options.frequency_min_Hz, hi = options.frequency_max_Hz;

    // The scan ranks frequencies by the bound after Osborne's balancing alone (itself an upper
    // bound, microseconds); the optimised bound is taken at the best candidates.
    const auto scan_bound = [&](double f) {
        ++out.evaluations;
        return balanced_bound(transfer.at({0.0, two_pi * f}));
    };
    std::vector<double> frequencies;
    const int grid = std::max(options.grid, 2);
    for (int k = 0; k < grid; ++k)
        frequencies.push_back(lo * std::pow(hi / lo, static_cast<double>(k) / (grid - 1)));
    for (Eigen::Index k = 0; k < transfer.poles.size(); ++k) {
        const double f = transfer.poles(k).imag() / two_pi;
        if (f > lo && f < hi) frequencies.push_back(f);
    }
    std::sort(frequencies.begin(), frequencies.end());
    std::vector<double> values;
    values.reserve(frequencies.size());
    for (double f : frequencies) values.push_back(scan_bound(f));

    // the three highest local maxima of the scan, each refined by a golden-section search in
    // log f between its neighbours (on the same balanced bound: the optimised one is flat in D at
    // its minimum and moves with f as the balanced one does), then the optimised bound there
    std::vector<std::size_t> peaks;
    for (std::size_t k = 0; k < values.size(); ++k) {
        const bool left = k == 0 || values[k] >= values[k - 1];
        const bool right = k + 1 == values.size() || values[k] >= values[k + 1];
        if (left && right) peaks.push_back(k);
    }
    std::sort(peaks.begin(), peaks.end(),
              [&](std::size_t a, std::size_t b) { return values[a] > values[b]; });
    if (peaks.size() > 3) peaks.resize(3);
    out.margin = -1.0;
    for (std::size_t k : peaks) {
        const double a = std::log(frequencies[k == 0 ? 0 : k - 1]);
        const double b = std::log(frequencies[std::min(k + 1, frequencies.size() - 1)]);
        // the bound's maximum: the minimum of its negative
        const double peak = golden_section_minimum(
                                [&](double x) { return -scan_bound(std::exp(x)); }, a, b, 40, 1e-10)
                                .x;
        const double f = std::exp(peak);
        Eigen::VectorXd scaling;
        ++out.evaluations;
        const Eigen::MatrixXcd m = transfer.at({0.0, two_pi * f});
        const double value = structured_bound(m, &scaling);
        if (value > out.margin) {
            out.margin = value;
            out.frequency_Hz = f;
            out.scaling = scaling;
            out.transfer = m;
        }
    }
    return out;
}

Eigen::VectorXcd margin_worst_input(const RegenerativeMargin& margin) {
    const Eigen::Index p = margin.transfer.rows();
    if (p == 0 || margin.transfer.cols() != p) return {};
    const Eigen::VectorXd d =
        margin.scaling.size() == p ? margin.scaling : Eigen::VectorXd::Ones(p);
    const Eigen::MatrixXcd scaled = d.cast<std::complex<double>>().asDiagonal() * margin.transfer *
                                    d.cwiseInverse().cast<std::complex<double>>().asDiagonal();
    const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(scaled, Eigen::ComputeFullV);
    return d.cwiseInverse().cast<std::complex<double>>().asDiagonal() * svd.matrixV().col(0);
}

}  // namespace rollgap::core
