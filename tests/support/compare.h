#pragma once
// Comparisons the tests share: written once (the suite is compiled as unity batches, so a
// helper copied into two test files is a redefinition).

#include <algorithm>
#include <cmath>
#include <limits>

namespace rollgap::test {

// |a − b| relative to the larger magnitude: symmetric, and 0 for a == b == 0 only by limit.
inline double rel(double a, double b) {
    return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

// The unit roundoff of double, u = ε/2: the relative error bound of one rounded operation.
inline constexpr double unit_roundoff = std::numeric_limits<double>::epsilon() / 2;

}  // namespace rollgap::test
