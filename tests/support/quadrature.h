#pragma once
// Independent reference quadrature for the tests (header-only, test support only; nothing in
// core/ may use it). Globally adaptive Gauss-Kronrod 7-15 (the QUADPACK QAG scheme without
// extrapolation): the interval with the largest error estimate is bisected until the summed
// error estimate meets the tolerance. The error estimate of an interval is the raw |K15 - G7|,
// which for smooth integrands overestimates the error of K15 by orders of magnitude, so a
// converged result is usually far more accurate than requested.
//
// Semi-infinite integrals use the substitution x = lo + s t / (1 - t), t in [0, 1), with a
// user-chosen length scale s (put it where the integrand changes: the GK nodes never touch the
// singular endpoint t = 1, and the integrand must decay faster than 1/x for the transformed
// integrand to vanish there).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <queue>
#include <vector>

namespace rollgap::test {

struct QuadratureResult {
    double value = 0.0;      // the integral
    double error = 0.0;      // the summed |K15 - G7| estimate
    int intervals = 0;       // number of subintervals at the end
    bool converged = false;  // error <= max(abs_tol, rel_tol |value|)
};

struct QuadratureOptions {
    double abs_tol = 0.0;
    double rel_tol = 1e-13;
    int max_intervals = 20000;  // bounds the work
    int max_depth = 60;         // an interval is not split beyond 2^-max_depth of the original
};

namespace detail {

// Gauss-Kronrod 7-15 nodes and weights (QUADPACK qk15; Piessens et al. 1983).
inline constexpr std::array<double, 8> kXgk = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
inline constexpr std::array<double, 8> kWgk = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
// Gauss 7-point weights for the nodes kXgk[1], kXgk[3], kXgk[5], kXgk[7].
inline constexpr std::array<double, 4> kWg = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

struct Panel {
    double a, b, kronrod, error;
    int depth;
    bool operator<(const Panel& o) const { return error < o.error; }  // max-heap on error
};

template <class F>
Panel gk15(F& f, double a, double b, int depth) {
    const double c = 0.5 * (a + b);
    const double h = 0.5 * (b - a);
    const double fc = f(c);
    double k = fc * kWgk[7];
    double g = fc * kWg[3];
    for (int j = 0; j < 7; ++j) {
        const double dx = h * kXgk[j];
        const double f1 = f(c - dx);
        const double f2 = f(c + dx);
        k += kWgk[j] * (f1 + f2);
        if (j % 2 == 1) g += kWg[j / 2] * (f1 + f2);
    }
    return Panel{a, b, k * h, std::abs((k - g) * h), depth};
}

}  // namespace detail

// int_a^b f(x) dx, a < b finite.
template <class F>
QuadratureResult integrate(F f, double a, double b, QuadratureOptions opt = {}) {
    QuadratureResult r;
    if (a == b) {
        r.converged = true;
        return r;
    }
    double sign = 1.0;
    if (b < a) {
        std::swap(a, b);
        sign = -1.0;
    }
    std::priority_queue<detail::Panel> heap;
    std::vector<detail::Panel> frozen;  // panels at the depth limit
    double frozen_error = 0.0;
    heap.push(detail::gk15(f, a, b, 0));
    auto totals = [&](double& value, double& error) {
        value = 0.0;
        error = 0.0;
        auto copy = heap;
        while (!copy.empty()) {
            value += copy.top().kronrod;
            error += copy.top().error;
            copy.pop();
        }
        for (const auto& p : frozen) {
            value += p.kronrod;
            error += p.error;
        }
    };
    double value = heap.top().kronrod;
    double error = heap.top().error;
    while (true) {
        const double tol = std::max(opt.abs_tol, opt.rel_tol * std::abs(value));
        if (error <= tol) {
            r.converged = true;
            break;
        }
        if (heap.empty() || frozen_error > tol ||
            static_cast<int>(heap.size() + frozen.size()) >= opt.max_intervals) {
            break;  // not converged: the depth limit or the interval budget is exhausted
        }
        const detail::Panel worst = heap.top();
        heap.pop();
        if (worst.depth >= opt.max_depth) {
            frozen.push_back(worst);
            frozen_error += worst.error;
            continue;
        }
        const double mid = 0.5 * (worst.a + worst.b);
        const detail::Panel left = detail::gk15(f, worst.a, mid, worst.depth + 1);
        const detail::Panel right = detail::gk15(f, mid, worst.b, worst.depth + 1);
        heap.push(left);
        heap.push(right);
        // Incremental update, re-summed exactly every so often to keep rounding out.
        value += left.kronrod + right.kronrod - worst.kronrod;
        error += left.error + right.error - worst.error;
        if ((heap.size() + frozen.size()) % 64 == 0) totals(value, error);
    }
    totals(value, error);
    r.value = sign * value;
    r.error = error;
    r.intervals = static_cast<int>(heap.size() + frozen.size());
    r.converged = r.converged && error <= std::max(opt.abs_tol, opt.rel_tol * std::abs(value));
    return r;
}

// int_lo^inf f(x) dx by x = lo + scale t / (1 - t).
template <class F>
QuadratureResult integrate_to_infinity(F f, double lo, double scale, QuadratureOptions opt = {}) {
    auto g = [&](double t) {
        const double one_minus_t = 1.0 - t;
        if (one_minus_t <= 0.0) return 0.0;
        const double x = lo + scale * t / one_minus_t;
        const double jac = scale / (one_minus_t * one_minus_t);
        const double fx = f(x);
        if (fx == 0.0) return 0.0;  // avoids 0 * inf at the far end
        return fx * jac;
    };
    return integrate(g, 0.0, 1.0, opt);
}

// Plain bisection for a sign change of g on [lo, hi] (the test references use it instead of
// anything the implementation does). Stops when the bracket no longer shrinks in floating point.
template <class G>
double bisect(G g, double lo, double hi, int max_iter = 400) {
    double glo = g(lo);
    for (int i = 0; i < max_iter; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        const double gm = g(mid);
        if (gm == 0.0) return mid;
        if ((gm < 0.0) == (glo < 0.0)) {
            lo = mid;
            glo = gm;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

}  // namespace rollgap::test
