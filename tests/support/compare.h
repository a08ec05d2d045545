#pragma once
// Comparisons the tests share: written once (the suite is compiled as unity batches, so a
// helper copied into two test files is a redefinition).

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

namespace rollgap::test {

// |a − b| relative to the larger magnitude: symmetric, and 0 for a == b == 0 only by limit.
inline double rel(double a, double b) {
    return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

// The unit roundoff of double, u = ε/2: the relative error bound of one rounded operation.
inline constexpr double unit_roundoff = std::numeric_limits<double>::epsilon() / 2;

// The largest distance from each of `a` to the nearest of `b`, relative to its size (eigenvalue
// sets compared without an order; `b` not empty).
inline double worst_nearest(const std::vector<std::complex<double>>& a,
                            const std::vector<std::complex<double>>& b) {
    double worst = 0.0;
    for (const auto& x : a) {
        double nearest = std::abs(b.front() - x);
        for (const auto& y : b) nearest = std::min(nearest, std::abs(y - x));
        worst = std::max(worst, nearest / std::abs(x));
    }
    return worst;
}

}  // namespace rollgap::test
