// The dual numbers of the bite sensitivities (core/dual.h, docs/model.md §6.1): every operation's
// derivative against its closed form, and the value of a dual computation equal, bit for bit, to
// the same computation in doubles (the bite's Newton search relies on it: its dual passes are
// remembered as plain trials).
#include <doctest/doctest.h>

#include <cmath>

#include "core/dual.h"
#include "support/approx.h"

namespace dual_test {

using rollgap::core::Dual;
using D = Dual<2>;

TEST_CASE("dual numbers: each operation's derivative is its closed form") {
    const double x = 0.7, y = -1.3;
    const D X = D::variable(x, 0), Y = D::variable(y, 1);
    const auto check = [](const D& f, double value, double dx, double dy) {
        CHECK(f.v == rollgap::test::approx(value).epsilon(1e-15));
        CHECK(f.d[0] == rollgap::test::approx(dx).epsilon(1e-14));
        CHECK(f.d[1] == rollgap::test::approx(dy).epsilon(1e-14));
    };
    check(X + Y, x + y, 1, 1);
    check(X - Y, x - y, 1, -1);
    check(X * Y, x * y, y, x);
    check(X / Y, x / y, 1 / y, -x / (y * y));
    check(2.0 / X, 2.0 / x, -2.0 / (x * x), 0);
    check(3.0 - X * 2.0 + 1.5, 3.0 - 2 * x + 1.5, -2, 0);
    check(exp(X * Y), std::exp(x * y), y * std::exp(x * y), x * std::exp(x * y));
    check(expm1(-X), std::expm1(-x), -std::exp(-x), 0);
    check(sqrt(X), std::sqrt(x), 0.5 / std::sqrt(x), 0);
    check(abs(Y), -y, 0, -1);
    check(-X, -x, -1, 0);
    CHECK(rollgap::core::isfinite(X));
    CHECK(!rollgap::core::isfinite(sqrt(D(-1.0))));
    CHECK((X < Y) == (x < y));
    CHECK((X > 0.5) == (x > 0.5));
}

TEST_CASE("dual numbers: the value is the double computation's, bit for bit") {
    // a chain of the kernel's operations (core/bite_kernel.h) in both types
    const auto f = [](auto a, auto b) {
        using std::abs;
        using std::exp;
        using std::sqrt;
        auto t = (a * b - 0.25) / (b + 3.0);
        t = t * exp(-abs(a) * 0.3) + sqrt(b * b + 1.0) / (2.0 + a);
        return 1.0 - t / 7.0;
    };
    for (double a : {0.1, 1.7, -2.3, 1e-9, 123.456}) {
        for (double b : {0.3, -0.9, 42.0}) {
            CAPTURE(a);
            CAPTURE(b);
            CHECK(f(D::variable(a, 0), D::variable(b, 1)).v == f(a, b));
        }
    }
}

}  // namespace dual_test
