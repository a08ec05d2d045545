#include "core/mill/mill_regenerative.h"

#include <algorithm>
#include <cmath>
#include <numbers>

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

Eigen::MatrixXcd TransportTransfer::at(std::complex<double> s) const {
    const Eigen::Index n = poles.size(), p = input.cols();
    if (p == 0) return Eigen::MatrixXcd(0, 0);
    Eigen::MatrixXcd right(n, p);
    for (Eigen::Index k = 0; k < n; ++k) {
        const std::complex<double> r = 1.0 / (s - poles(k));
        right.row(k) = r * (input.row(k) + s * input_rate.row(k));
    }
    return output * right;
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

double largest_singular_value(const Eigen::MatrixXcd& m) {
    if (m.size() == 1) return std::abs(m(0, 0));
    return Eigen::JacobiSVD<Eigen::MatrixXcd>(m).singularValues()(0);
}

double scaled(const Eigen::MatrixXcd& m, const Eigen::VectorXd& x) {
    const Eigen::Index p = m.rows();
    Eigen::MatrixXcd s(p, p);
    for (Eigen::Index i = 0; i < p; ++i)
        for (Eigen::Index j = 0; j < p; ++j) s(i, j) = m(i, j) * std::exp(x(i) - x(j));
    return largest_singular_value(s);
}

// Osborne's balancing of |M|: log d evening out each row's and column's off-diagonal norms of
// |D M D^-1| (a start for the bound, and a bound itself). d_0 = 1.
Eigen::VectorXd osborne(const Eigen::MatrixXcd& m, int sweeps) {
    const Eigen::Index p = m.rows();
    Eigen::VectorXd x = Eigen::VectorXd::Zero(p);
    const Eigen::MatrixXd a = m.cwiseAbs();
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        for (Eigen::Index i = 0; i < p; ++i) {
            double row = 0.0, col = 0.0;
            for (Eigen::Index j = 0; j < p; ++j) {
                if (j == i) continue;
                row += a(i, j) * a(i, j) * std::exp(2.0 * (x(i) - x(j)));
                col += a(j, i) * a(j, i) * std::exp(2.0 * (x(j) - x(i)));
            }
            if (row > 0.0 && col > 0.0) x(i) += 0.25 * std::log(col / row);
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
        constexpr double golden = 0.6180339887498949;
        for (int sweep = 0; sweep < 3; ++sweep) {
            for (Eigen::Index i = 1; i < p; ++i) {
                double lo = x(i) - 8.0, hi = x(i) + 8.0;
                Eigen::VectorXd trial = x;
                const auto f = [&](double xi) {
                    trial(i) = xi;
                    return scaled(m, trial);
                };
                double c = hi - golden * (hi - lo), d = lo + golden * (hi - lo);
                double fc = f(c), fd = f(d);
                for (int k = 0; k < 40; ++k) {
                    if (fc < fd) {
                        hi = d;
                        d = c;
                        fd = fc;
                        c = hi - golden * (hi - lo);
                        fc = f(c);
                    } else {
                        lo = c;
                        c = d;
                        fc = fd;
                        d = lo + golden * (hi - lo);
                        fd = f(d);
                    }
                }
                const double best = 0.5 * (lo + hi);
                trial(i) = best;
                if (scaled(m, trial) < scaled(m, x)) x(i) = best;
            }
        }
    }
    if (scaling) *scaling = x.array().exp();
    return p == 0 ? 0.0 : scaled(m, x);
}

double balanced_bound(const Eigen::MatrixXcd& m) {
    if (m.rows() == 0) return 0.0;
    if (m.rows() == 1) return std::abs(m(0, 0));
    return scaled(m, osborne(m, 10));
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
        double a = std::log(frequencies[k == 0 ? 0 : k - 1]);
        double b = std::log(frequencies[std::min(k + 1, frequencies.size() - 1)]);
        constexpr double golden = 0.6180339887498949;
        double c = b - golden * (b - a), d = a + golden * (b - a);
        double fc = scan_bound(std::exp(c)), fd = scan_bound(std::exp(d));
        for (int it = 0; it < 40 && b - a > 1e-10; ++it) {
            if (fc > fd) {
                b = d;
                d = c;
                fd = fc;
                c = b - golden * (b - a);
                fc = scan_bound(std::exp(c));
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + golden * (b - a);
                fd = scan_bound(std::exp(d));
            }
        }
        const double f = std::exp(0.5 * (a + b));
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

}  // namespace rollgap::core
