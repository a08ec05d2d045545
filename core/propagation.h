#pragma once
// Uncertainty carried from a calibration's posterior to a derived figure (docs/model.md §13.2):
// the fitted values x̂ with their covariance Σ, and a figure f(x) (a critical speed, a speed
// limit). Linear: σ_f² = g Σ gᵀ with g by central differences of one posterior standard deviation
// per parameter (the figure comes from searches with a tolerance, ~1e-4 of it: a step of 1e-6
// would difference its noise); sampled, as the check: f at seeded draws from N(x̂, Σ). Either way
// the answer is a mean, a standard deviation and a one-sided lower bound at a confidence.
#include <cstdint>
#include <functional>
#include <optional>

#include <Eigen/Dense>

#include "core/control.h"

namespace rollgap::core {

// The figure at parameter values; nullopt where it has none (no steady state, no crossing).
// Called concurrently from the control's threads.
using Figure = std::function<std::optional<double>(const Eigen::VectorXd& x)>;

struct Propagated {
    bool ok = false;     // the figure at the mean (linear: and at every difference point) exists
    double value = 0.0;  // f(x̂) (linear), the samples' mean (sampled)
    double standard_deviation = 0.0;  // linear: sqrt(g Σ gᵀ); sampled: the samples' (n − 1)
    Eigen::VectorXd gradient;         // linear only: df/dx_j
    int samples = 0;                  // sampled: draws with a figure
    int failed_samples = 0;           // sampled: draws without one
};

Propagated propagate_linear(const Figure& f, const Eigen::VectorXd& mean,
                            const Eigen::MatrixXd& covariance, const Control& control = {});

// `count` draws x = x̂ + V sqrt(Λ) z (Σ = V Λ Vᵀ, negative rounding in Λ clamped to 0), z from
// a 64-bit Mersenne twister seeded with `seed`: the same draws for the same seed.
Propagated propagate_sampled(const Figure& f, const Eigen::VectorXd& mean,
                             const Eigen::MatrixXd& covariance, int count, std::uint64_t seed,
                             const Control& control = {});

// z with Φ(z) = p, 0 < p < 1 (Acklam's rational approximation, one Halley step on erfc: to a
// few ulps); NaN outside (0, 1).
double normal_quantile(double p);

// The one-sided lower bound value − z_c σ at confidence c (0.95: z = 1.6449).
double lower_bound(const Propagated& p, double confidence);

}  // namespace rollgap::core
