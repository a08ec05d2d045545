#pragma once
// Brent's bracketed root finder (inverse quadratic interpolation, secant, bisection).

#include <cmath>
#include <utility>

namespace rollgap::core {

struct RootResult {
    double x = 0.0;
    bool converged = false;
    int iterations = 0;
};

// Root of f in [a, b] given f(a) = fa and f(b) = fb of opposite signs, to an absolute
// tolerance `tolerance` in x. A `guess` inside (a, b) first narrows the bracket; it changes the
// path, not the root beyond the tolerance.
template <class F>
RootResult brent_root(F&& f, double a, double b, double fa, double fb, double tolerance,
                      double guess = -1.0, int max_iterations = 200) {
    RootResult result;
    if (guess > a && guess < b) {
        const double fg = f(guess);
        if (!std::isfinite(fg)) return result;
        if (fg == 0.0) return {guess, true, 0};
        if ((fg > 0.0) == (fa > 0.0)) {
            a = guess;
            fa = fg;
        } else {
            b = guess;
            fb = fg;
        }
    }
    double c = a, fc = fa, d = b - a, e = d;
    for (int i = 0; i < max_iterations; ++i) {
        result.iterations = i + 1;
        if ((fb > 0.0) == (fc > 0.0)) {
            c = a;
            fc = fa;
            d = e = b - a;
        }
        if (std::abs(fc) < std::abs(fb)) {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        const double tol = 2.0 * 2.2e-16 * std::abs(b) + 0.5 * tolerance;
        const double m = 0.5 * (c - b);
        if (std::abs(m) <= tol || fb == 0.0) {
            result.x = b;
            result.converged = true;
            return result;
        }
        if (std::abs(e) >= tol && std::abs(fa) > std::abs(fb)) {
            double p, q;
            const double s = fb / fa;
            if (a == c) {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                const double qa = fa / fc, r = fb / fc;
                p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if (p > 0.0) q = -q;
            else p = -p;
            if (2.0 * p < std::min(3.0 * m * q - std::abs(tol * q), std::abs(e * q))) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += std::abs(d) > tol ? d : (m > 0.0 ? tol : -tol);
        fb = f(b);
        if (!std::isfinite(fb)) return result;
    }
    return result;
}

}  // namespace rollgap::core
