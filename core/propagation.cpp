#include "core/propagation.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/parallel_for.h"

namespace rollgap::core {

Propagated propagate_linear(const Figure& f, const Eigen::VectorXd& mean,
                            const Eigen::MatrixXd& covariance, const Control& control) {
    Propagated out;
    const Eigen::Index n = mean.size();
    if (covariance.rows() != n || covariance.cols() != n) return out;
    // f at the mean and at x̂ ± σ_j e_j: 2n + 1 evaluations on the control's threads
    std::vector<std::optional<double>> values(static_cast<std::size_t>(2 * n + 1));
    parallel_for(static_cast<int>(2 * n + 1), control, [&](int k) {
        Eigen::VectorXd x = mean;
        if (k > 0) {
            const Eigen::Index j = (k - 1) / 2;
            const double step = std::sqrt(std::max(covariance(j, j), 0.0));
            x(j) += (k % 2 == 1 ? step : -step);
        }
        values[static_cast<std::size_t>(k)] = f(x);
    });
    if (!values[0]) return out;
    out.value = *values[0];
    out.gradient = Eigen::VectorXd::Zero(n);
    for (Eigen::Index j = 0; j < n; ++j) {
        const double step = std::sqrt(std::max(covariance(j, j), 0.0));
        if (step == 0.0) continue;  // a parameter known exactly carries nothing
        const auto& plus = values[static_cast<std::size_t>(2 * j + 1)];
        const auto& minus = values[static_cast<std::size_t>(2 * j + 2)];
        if (!plus || !minus) return out;
        out.gradient(j) = (*plus - *minus) / (2.0 * step);
    }
    out.standard_deviation = std::sqrt(std::max(out.gradient.dot(covariance * out.gradient), 0.0));
    out.ok = true;
    return out;
}

Propagated propagate_sampled(const Figure& f, const Eigen::VectorXd& mean,
                             const Eigen::MatrixXd& covariance, int count, std::uint64_t seed,
                             const Control& control) {
    Propagated out;
    const Eigen::Index n = mean.size();
    if (covariance.rows() != n || covariance.cols() != n || count < 2) return out;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(covariance);
    if (eigen.info() != Eigen::Success) return out;
    const Eigen::MatrixXd root =
        eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
    // the draws first, in order, so that they depend on the seed alone
    std::mt19937_64 generator(seed);
    std::normal_distribution<double> normal;
    std::vector<Eigen::VectorXd> draws(static_cast<std::size_t>(count));
    for (Eigen::VectorXd& x : draws) {
        Eigen::VectorXd z(n);
        for (Eigen::Index j = 0; j < n; ++j) z(j) = normal(generator);
        x = mean + root * z;
    }
    std::vector<std::optional<double>> values(draws.size());
    parallel_for(count, control, [&](int k) {
        values[static_cast<std::size_t>(k)] = f(draws[static_cast<std::size_t>(k)]);
    });
    double sum = 0.0, sum_squares = 0.0;
    for (const auto& v : values) {
        if (!v) {
            ++out.failed_samples;
            continue;
        }
        ++out.samples;
        sum += *v;
    }
    if (out.samples < 2) return out;
    out.value = sum / out.samples;
    for (const auto& v : values)
        if (v) sum_squares += (*v - out.value) * (*v - out.value);
    out.standard_deviation = std::sqrt(sum_squares / (out.samples - 1));
    out.ok = true;
    return out;
}

double normal_quantile(double p) {
    if (!(p > 0.0 && p < 1.0)) return std::numeric_limits<double>::quiet_NaN();
    // Acklam's coefficients (relative error < 1.15e-9), then one Halley step
    constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                            1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                            6.680131188771972e+01, -1.328068155288572e+01};
    constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                            -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                            3.754408661907416e+00};
    constexpr double low = 0.02425;
    double x;
    if (p < low) {
        const double q = std::sqrt(-2.0 * std::log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    } else if (p <= 1.0 - low) {
        const double q = p - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
    } else {
        const double q = std::sqrt(-2.0 * std::log(1.0 - p));
        x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    }
    // Halley: e = Φ(x) − p with Φ(x) = erfc(−x/√2)/2
    const double e = 0.5 * std::erfc(-x / std::numbers::sqrt2) - p;
    const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
    return x - u / (1.0 + 0.5 * x * u);
}

double lower_bound(const Propagated& p, double confidence) {
    return p.value - normal_quantile(confidence) * p.standard_deviation;
}

}  // namespace rollgap::core
