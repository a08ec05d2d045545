#pragma once
// The suite's one approximate comparison: relative, always.
//
// doctest's `Approx(b).epsilon(e)` accepts |a − b| < e·(scale + max(|a|, |b|)) with scale 1 by
// default, so for a quantity below 1 (a σ in m/s, a derivative per Pa, a thickness in m) its
// "relative" tolerance is an absolute one, and `Approx(1.2e-6)` with the default ε ≈ 1.2e-5
// accepts any value near zero. `approx(b)` is the same comparison relative at every magnitude:
// |a − b| < e·(s + max(|a|, |b|)) with s the smallest normal double rather than 1, so that the
// strict < still lets 0 match 0 (with s = 0 it would not) while a nonzero value never matches 0.
// A check that truly needs an absolute tolerance writes it out — CHECK(std::abs(a - b) < tol) —
// and says why.
// scripts/lint.sh refuses `doctest::Approx(` anywhere else in tests/.

#include <limits>

#include <doctest/doctest.h>

namespace rollgap::test {

inline doctest::Approx approx(double expected) {
    return doctest::Approx(expected).scale(std::numeric_limits<double>::min());
}

}  // namespace rollgap::test
