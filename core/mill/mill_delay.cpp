#include "core/mill/mill_delay.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <cmath>
#include <numbers>
#include <vector>

namespace rollgap::core {

namespace {

using Complex = std::complex<double>;

Eigen::MatrixXcd loop(const TransportTransfer& transfer, Complex s) {
    Eigen::MatrixXcd m = transfer.at(s);
    for (Eigen::Index j = 0; j < m.cols(); ++j)
        m.col(j) *= std::exp(-s * transfer.delay[static_cast<std::size_t>(j)]);
    return Eigen::MatrixXcd::Identity(m.rows(), m.cols()) - m;
}

// The sum of the principal arguments of the eigenvalues of I - M E: arg F where every
// eigenvalue stays in the right half plane (|M E| < 1), continuous there.
double eigen_argument(const Eigen::MatrixXcd& x) {
    const Eigen::VectorXcd values =
        Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(x, false).eigenvalues();
    double sum = 0.0;
    for (Eigen::Index k = 0; k < values.size(); ++k) sum += std::arg(values(k));
    return sum;
}

}  // namespace

Complex delay_characteristic(const TransportTransfer& transfer, Complex s) {
    if (transfer.spans() == 0) return 1.0;
    return loop(transfer, s).partialPivLu().determinant();
}

DelayRootCount nominal_delay_root_count(const TransportTransfer& transfer, double alpha) {
    DelayRootCount out;
    if (!transfer.ok) {
        out.message = "no linearisation";
        return out;
    }
    const Eigen::VectorXcd& poles = transfer.poles;
    // the line must miss A0's poles (F has them): move it by a hair where one sits on it
    for (int attempt = 0; attempt < 8; ++attempt) {
        bool clear = true;
        for (Eigen::Index k = 0; k < poles.size(); ++k) {
            if (std::abs(poles(k).real() - alpha) <= 1e-9 * std::max(1.0, std::abs(poles(k))))
                clear = false;
        }
        if (clear) break;
        alpha += 1e-6 * std::max(1.0, std::abs(alpha));
    }
    out.alpha = alpha;
    for (Eigen::Index k = 0; k < poles.size(); ++k)
        if (poles(k).real() > alpha) ++out.frozen_right;
    if (transfer.spans() == 0) {
        out.ok = true;
        out.count = out.frozen_right;
        return out;
    }

    double tau_max = 0.0, shrink = 0.0;  // max_i exp(-alpha tau_i) bounds |E| on the line
    for (double tau : transfer.delay) {
        tau_max = std::max(tau_max, tau);
        shrink = std::max(shrink, std::exp(-alpha * tau));
    }
    // the structured gain: below 1/2, rho(M E) <= sigma(D M D^-1 E) = sigma(D M D^-1) < 1/2 for
    // every diagonal E of modulus <= 1 (D and E commute), so the eigenvalues of I - M E stay
    // within 1/2 of 1. The mill's M is nearly lower triangular at low frequency (the thickness
    // passes downstream; only the tension path comes back), where sigma(M) alone is ~0.8.
    const auto gain = [&](double omega) {
        return balanced_bound(transfer.at({alpha, omega})) * shrink;
    };
    const auto pole_distance = [&](double omega) {
        double d = std::numeric_limits<double>::infinity();
        for (Eigen::Index k = 0; k < poles.size(); ++k)
            d = std::min(d, std::abs(Complex(alpha, omega) - poles(k)));
        return d;
    };

    // the coarse grid: log-spaced over 1e-2 .. 1e7 rad/s, and around every pole of A0
    std::vector<double> grid{0.0};
    constexpr int decades = 9, per_decade = 60;
    for (int k = 0; k <= decades * per_decade; ++k)
        grid.push_back(1e-2 * std::pow(10.0, static_cast<double>(k) / per_decade));
    const double top = grid.back();
    for (Eigen::Index k = 0; k < poles.size(); ++k) {
        const double w = poles(k).imag();
        if (w < 0.0 || w > top) continue;
        const double d = std::max(std::abs(poles(k).real() - alpha), 1e-9 * std::abs(poles(k)));
        for (double f : {-4.0, -2.0, -1.0, -0.5, -0.25, 0.0, 0.25, 0.5, 1.0, 2.0, 4.0}) {
            const double x = w + f * d;
            if (x > 0.0 && x < top) grid.push_back(x);
        }
    }
    std::sort(grid.begin(), grid.end());
    grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
    std::vector<double> gains(grid.size());
    for (std::size_t k = 0; k < grid.size(); ++k) gains[k] = gain(grid[k]);
    if (gains.back() >= 0.5) {
        out.message = "the loop gain does not fall below 1/2 by 1e7 rad/s";
        return out;
    }

    double theta = 0.0;                           // the change of arg F from omega = 0
    std::vector<std::pair<double, double>> dips;  // (|F|, omega) at local minima
    Complex previous = delay_characteristic(transfer, {alpha, 0.0});
    ++out.evaluations;
    double before = std::abs(previous), at = before;  // |F| at the last two points followed
    double argument = 0.0, argument_at = -1.0;        // the eigenvalues' arguments' sum, and where
    constexpr double small = 0.5, quarter_turn = std::numbers::pi / 4.0;
    constexpr int budget = 4'000'000;
    for (std::size_t k = 0; k + 1 < grid.size(); ++k) {
        const double a = grid[k], b = grid[k + 1];
        if (gains[k] < small && gains[k + 1] < small) {
            // no winding possible: the eigenvalues' principal arguments carry arg F
            if (!(argument_at == a)) {
                argument = eigen_argument(loop(transfer, {alpha, a}));
                ++out.evaluations;
            }
            const Eigen::MatrixXcd xb = loop(transfer, {alpha, b});
            const double next_argument = eigen_argument(xb);
            theta += next_argument - argument;
            argument = next_argument;
            argument_at = b;
            previous = xb.partialPivLu().determinant();
            before = at = std::abs(previous);
            ++out.evaluations;
            continue;
        }
        double omega = a;
        while (omega < b) {
            double h =
                std::min({b - omega, 1.0 / std::max(tau_max, 1e-12), 0.25 * pole_distance(omega)});
            for (;;) {
                const Complex next = delay_characteristic(transfer, {alpha, omega + h});
                ++out.evaluations;
                if (out.evaluations > budget) {
                    out.message = "the argument principle needed more than 4e6 evaluations";
                    return out;
                }
                const double step = std::arg(next / previous);
                if (std::abs(step) <= quarter_turn || h <= 1e-12 * std::max(1.0, omega)) {
                    theta += step;
                    const double after = std::abs(next);
                    if (at < before && at <= after) dips.push_back({at, omega});
                    before = at;
                    at = after;
                    previous = next;
                    omega += h;
                    break;
                }
                h *= 0.5;
            }
        }
    }
    // the tail: from the last point, where every eigenvalue of I - M E is within 1/2 of 1, to
    // infinity, where M = O(1/s^2) and F -> 1
    theta -= eigen_argument(loop(transfer, {alpha, grid.back()}));
    // omega = 0: F is real there, so arg F(alpha) is 0 or pi; the increments start from it
    const double winding = -theta / std::numbers::pi;
    const double total = out.frozen_right + winding;
    out.winding = winding;
    out.count = static_cast<int>(std::lround(total));
    out.integer_error = std::abs(total - out.count);
    out.ok = out.integer_error < 1e-2;
    std::sort(dips.begin(), dips.end());
    if (dips.size() > 16) dips.resize(16);
    for (const auto& [value, omega] : dips) out.dips.emplace_back(alpha, omega);
    out.message = out.ok ? "" : "the winding number is not an integer: F vanishes near the line";
    return out;
}

DelayRoot delay_root(const TransportTransfer& transfer, Complex start) {
    DelayRoot out;
    Complex s = start;
    for (int k = 0; k < 60; ++k) {
        out.iterations = k + 1;
        const Complex f = delay_characteristic(transfer, s);
        const double h = 1e-7 * std::max(1.0, std::abs(s));
        const Complex slope =
            (delay_characteristic(transfer, s + h) - delay_characteristic(transfer, s - h)) /
            (2.0 * h);
        if (!(std::abs(slope) > 0.0)) break;
        const Complex step = f / slope;
        s -= step;
        if (!std::isfinite(s.real()) || !std::isfinite(s.imag())) break;
        if (std::abs(step) <= 1e-12 * std::max(1.0, std::abs(s))) {
            out.converged = true;
            break;
        }
    }
    out.s = s;
    out.residual = std::abs(delay_characteristic(transfer, s));
    return out;
}

RightmostDelayRoot rightmost_delay_root(const TransportTransfer& transfer,
                                        const DelayRootCount& count) {
    RightmostDelayRoot out;
    std::vector<Complex> starts = count.dips;
    for (Eigen::Index k = 0; k < transfer.poles.size(); ++k) {
        const Complex pole = transfer.poles(k);
        // F has A0's poles: start a step to their right
        if (pole.imag() > 0.0 && pole.imag() <= 2.0 * std::numbers::pi * 2000.0)
            starts.push_back(pole + std::max(1.0, 0.1 * std::abs(pole.real())));
    }
    for (int round = 0; round < 8 && !starts.empty(); ++round) {
        for (const Complex& start : starts) {
            ++out.starts;
            const DelayRoot root = delay_root(transfer, start);
            if (!root.converged || !(root.residual < 1e-8) || root.s.imag() < 0.0) continue;
            if (!out.found || root.s.real() > out.root.s.real()) {
                out.found = true;
                out.root = root;
            }
        }
        if (!out.found) return out;
        const double beyond = out.root.s.real() + std::max(1e-3, 1e-9 * std::abs(out.root.s));
        const DelayRootCount right = nominal_delay_root_count(transfer, beyond);
        ++out.counts;
        if (!right.ok) return out;
        if (right.count == 0) {
            out.verified = true;
            return out;
        }
        starts = right.dips;
    }
    return out;
}

}  // namespace rollgap::core
