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
        m.col(j) *= -std::exp(-s * transfer.delay[static_cast<std::size_t>(j)]);
    m.diagonal().array() += 1.0;  // I - M E, in place
    return m;
}

// det x by Gaussian elimination with partial pivoting, on the stack for up to five spans (the
// mill's limit): the pivot chosen by |.|^2 (the library's LU takes |.| by hypot, a third of the
// determinant's cost; F is evaluated ~10^3 times a count).
template <int P>
Complex fixed_determinant(const Eigen::MatrixXcd& x) {
    Eigen::Matrix<Complex, P, P> a = x;
    Complex det = 1.0;
    for (int k = 0; k < P; ++k) {
        int pivot = k;
        double largest = std::norm(a(k, k));
        for (int i = k + 1; i < P; ++i)
            if (const double v = std::norm(a(i, k)); v > largest) {
                largest = v;
                pivot = i;
            }
        if (!(largest > 0.0)) return 0.0;
        if (pivot != k) {
            a.row(k).swap(a.row(pivot));
            det = -det;
        }
        det *= a(k, k);
        const Complex inverse = 1.0 / a(k, k);
        for (int i = k + 1; i < P; ++i) {
            const Complex factor = a(i, k) * inverse;
            for (int j = k + 1; j < P; ++j) a(i, j) -= factor * a(k, j);
        }
    }
    return det;
}

Complex determinant(const Eigen::MatrixXcd& x) {
    switch (x.rows()) {
        case 1: return x(0, 0);
        case 2: return fixed_determinant<2>(x);
        case 3: return fixed_determinant<3>(x);
        case 4: return fixed_determinant<4>(x);
        case 5: return fixed_determinant<5>(x);
        default: return x.partialPivLu().determinant();
    }
}

// I - M E at s from M (`m`, M(s)), in place.
Eigen::MatrixXcd loop_from(Eigen::MatrixXcd m, const TransportTransfer& transfer, Complex s) {
    for (Eigen::Index j = 0; j < m.cols(); ++j)
        m.col(j) *= -std::exp(-s * transfer.delay[static_cast<std::size_t>(j)]);
    m.diagonal().array() += 1.0;
    return m;
}

// The sum of the principal arguments of the eigenvalues of I - M E: arg F, continuous wherever
// every eigenvalue of M E stays inside the unit disc (docs/model.md §12.6). Where the structured
// gain is below 1/2 every eigenvalue of I - M E lies within 1/2 of 1, its argument within pi/6
// of 0, so for up to five spans (six stands, the mill's limit) the sum lies in (-5pi/6, 5pi/6)
// and is the principal argument of det F itself: no eigenvalues needed. Up to the tracker's
// threshold 0.9 each argument lies within asin 0.9 = 64 degrees: two spans' sum still does.
double small_gain_argument(const Eigen::MatrixXcd& x, Complex determinant, double gain) {
    if (x.rows() <= 2 || (gain < 0.5 && x.rows() <= 5)) return std::arg(determinant);
    const Eigen::VectorXcd values =
        Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(x, false).eigenvalues();
    double sum = 0.0;
    for (Eigen::Index k = 0; k < values.size(); ++k) sum += std::arg(values(k));
    return sum;
}

namespace tracker_detail {

// M along a straight piece s = a + t d, t in [t0, t1], as its Chebyshev interpolant of degree
// 15: the dense steps of the argument principle need F ~10^3 times across a band a few pole
// distances wide, where M (a sum over ~70 modes, microseconds) hardly changes while E turns. M
// is analytic on the piece (its nearest pole at least the piece's length away), its coefficients
// fall geometrically; the piece is taken only where the last two are below 1e-11 of the largest,
// which bounds the interpolant's error (|F| itself stays above 1e-8 wherever a count is an
// integer). One node evaluation of M costs as much as ~8 interpolated ones.
struct Panel {
    static constexpr int nodes = 16;
    Complex a, d;
    double t0 = 0.0, t1 = -1.0;
    Eigen::Index p = 0;
    std::vector<Complex> coefficient;  // nodes x (p x p), column-major per node

    bool covers(Complex origin, Complex direction, double t) const {
        return origin == a && direction == d && t >= t0 && t <= t1;
    }

    // false: the coefficients do not fall fast enough on [from, to] (the caller narrows it)
    bool build(const TransportTransfer& transfer, Complex origin, Complex direction, double from,
               double to, int& evaluations) {
        a = origin;
        d = direction;
        p = transfer.spans();
        const std::size_t size = static_cast<std::size_t>(p * p);
        coefficient.assign(nodes * size, Complex(0.0));
        const double mid = 0.5 * (from + to), half = 0.5 * (to - from);
        for (int j = 0; j < nodes; ++j) {
            const double angle = std::numbers::pi * (j + 0.5) / nodes;
            const Eigen::MatrixXcd m = transfer.at(a + (mid + half * std::cos(angle)) * d);
            ++evaluations;
            for (int k = 0; k < nodes; ++k) {
                const double weight = (k == 0 ? 1.0 : 2.0) / nodes * std::cos(k * angle);
                Complex* c = coefficient.data() + k * size;
                for (std::size_t e = 0; e < size; ++e) c[e] += weight * m.data()[e];
            }
        }
        double largest = 0.0, tail = 0.0;
        for (int k = 0; k < nodes; ++k)
            for (std::size_t e = 0; e < size; ++e) {
                const double v = std::abs(coefficient[k * size + e]);
                largest = std::max(largest, v);
                if (k >= nodes - 2) tail = std::max(tail, v);
            }
        if (!(tail <= 1e-11 * largest)) {
            t1 = t0 - 1.0;
            return false;
        }
        t0 = from;
        t1 = to;
        return true;
    }

    Eigen::MatrixXcd at(double t) const {
        const double y = (2.0 * t - t0 - t1) / (t1 - t0);
        const std::size_t size = static_cast<std::size_t>(p * p);
        Eigen::MatrixXcd out(p, p);
        for (std::size_t e = 0; e < size; ++e) {  // Clenshaw's recurrence per entry
            Complex b1 = 0.0, b2 = 0.0;
            for (int k = nodes - 1; k >= 1; --k) {
                const Complex b = coefficient[k * size + e] + 2.0 * y * b1 - b2;
                b2 = b1;
                b1 = b;
            }
            out.data()[e] = coefficient[e] + y * b1 - b2;
        }
        return out;
    }
};

}  // namespace tracker_detail

// arg F followed along a polyline (the line of nominal_delay_root_count, the band's edges):
// where the structured gain at both ends of a grid interval is below 1/2, or below 0.9 at both
// ends and its middle, by the eigenvalues' principal arguments (no winding possible in between);
// elsewhere in steps of at most 1/tau_max (no delay phase turns by more than a radian) and a
// quarter of the distance to A0's nearest pole, halved until each increment is under pi/4, M
// interpolated on pieces (tracker_detail::Panel) where they hold enough steps. The one edge
// tracker of both counts.
struct ArgumentTracker {
    const TransportTransfer& transfer;
    double tau_max = 0.0;
    int evaluations = 0;
    bool failed = false;
    static constexpr int budget = 4'000'000;
    static constexpr double small = 0.5;  // below it everywhere: no winding (the tail, edges)
    static constexpr double skip = 0.9;   // below it at an interval's ends and middle: none

    // M at a polyline's points, and the gain there
    struct Samples {
        std::vector<Complex> s;
        std::vector<Eigen::MatrixXcd> m;
        std::vector<double> gain;
        // interval k..k+1 known to be quiet (a gap between loud stretches): empty, or one per
        // interval
        std::vector<char> given_quiet;
    };

    explicit ArgumentTracker(const TransportTransfer& t) : transfer(t) {
        for (double tau : t.delay) tau_max = std::max(tau_max, tau);
    }

    // the structured gain of the loop M E at s (below 1/2: no winding possible): rho(M E) <=
    // sigma(D M D^-1 E) <= sigma(D M D^-1) max_i exp(-Re s tau_i) for every diagonal E of
    // modulus <= exp(-Re s tau_i) (D and E commute). The mill's M is nearly lower triangular at
    // low frequency (the thickness passes downstream; only the tension path comes back), where
    // sigma(M) alone is ~0.8. Only compared with the thresholds: below `enough`, any upper bound
    // of the gain under it may stand for it (balanced_bound's Frobenius shortcut).
    double gain_of(const Eigen::MatrixXcd& m, Complex s, double enough = skip) const {
        double shrink = 0.0;
        for (double tau : transfer.delay) shrink = std::max(shrink, std::exp(-s.real() * tau));
        // M's own Frobenius norm bounds the gain too (D = I): far above the resonances, where M
        // falls as 1/s^2, it answers without the balancing
        const double frobenius = m.norm() * shrink;
        if (frobenius < enough) return frobenius;
        return balanced_bound(m, enough / shrink) * shrink;
    }
    double gain(Complex s, double enough = skip) const {
        return gain_of(transfer.at(s), s, enough);
    }

    Samples sample(const std::vector<Complex>& grid) const {
        Samples out;
        out.s = grid;
        out.m.reserve(grid.size());
        out.gain.reserve(grid.size());
        for (Complex s : grid) {
            out.m.push_back(transfer.at(s));
            out.gain.push_back(gain_of(out.m.back(), s, small));
        }
        return out;
    }

    double pole_distance(Complex s) const {
        double d2 = std::numeric_limits<double>::infinity();
        for (Eigen::Index k = 0; k < transfer.poles.size(); ++k)
            d2 = std::min(d2, std::norm(s - transfer.poles(k)));
        return std::sqrt(d2);
    }

    // arg F at sample k where the gain is below the skip threshold (small_gain_argument), and F
    double argument(const Samples& samples, std::size_t k, Complex& value) {
        const Eigen::MatrixXcd x = loop_from(samples.m[k], transfer, samples.s[k]);
        value = determinant(x);
        ++evaluations;
        return small_gain_argument(x, value, samples.gain[k]);
    }

    // F at a + t d, from the piece's interpolant when it covers t, else from M itself
    tracker_detail::Panel panel;
    Complex characteristic(Complex a, Complex d, double t) {
        ++evaluations;
        const Complex s = a + t * d;
        if (!panel.covers(a, d, t)) return determinant(loop(transfer, s));
        return determinant(loop_from(panel.at(t), transfer, s));
    }

    // Interpolates M over [t, t + width] of the piece from a in direction d when the width holds
    // at least 48 of the longest steps (three times the panel's nodes), halving it up to three
    // times until the coefficients fall fast enough.
    // After a failure no piece is tried again within 48 steps of where it failed.
    Complex failed_a, failed_d;
    double failed_until = -1.0;
    void prepare_panel(Complex a, Complex d, double t, double width) {
        const double longest = 1.0 / std::max(tau_max, 1e-12);
        if (a == failed_a && d == failed_d && t < failed_until) return;
        for (int attempt = 0; attempt < 4 && width >= 48.0 * longest; ++attempt, width *= 0.5)
            if (panel.build(transfer, a, d, t, t + width, evaluations)) return;
        failed_a = a;
        failed_d = d;
        failed_until = t + 48.0 * longest;
    }

    // Whether no winding is possible over samples k..k+1 (see the struct's comment)
    bool quiet(const Samples& samples, std::size_t k) {
        if (!samples.given_quiet.empty() && samples.given_quiet[k] != 0) return true;
        const double g0 = samples.gain[k], g1 = samples.gain[k + 1];
        if (g0 < small && g1 < small) return true;
        if (!(g0 < skip && g1 < skip)) return false;
        const Complex middle = 0.5 * (samples.s[k] + samples.s[k + 1]);
        return gain(middle) < skip;
    }

    // The change of arg F along the polyline through the samples; the local minima of |F| met
    // where it is followed step by step go to `dips` as (|F|, s).
    double follow(const Samples& samples, std::vector<std::pair<double, Complex>>& dips) {
        constexpr double quarter_turn = std::numbers::pi / 4.0;
        const std::vector<Complex>& grid = samples.s;
        double theta = 0.0;
        Complex previous = determinant(loop_from(samples.m.front(), transfer, grid.front()));
        ++evaluations;
        double before = std::abs(previous), at = before;
        double argument_value = 0.0;
        std::size_t argument_at = grid.size();  // the grid point `argument_value` belongs to
        for (std::size_t k = 0; k + 1 < grid.size(); ++k) {
            const Complex a = grid[k], b = grid[k + 1];
            const double length = std::abs(b - a);
            if (!(length > 0.0)) continue;
            if (quiet(samples, k)) {
                // a run of quiet intervals: arg F changes by its ends' difference (the sum of the
                // eigenvalues' principal arguments is continuous along it)
                std::size_t end = k + 1;
                while (end + 1 < grid.size() && quiet(samples, end)) ++end;
                Complex value;
                if (argument_at != k) argument_value = argument(samples, k, value);
                const double next_argument = argument(samples, end, value);
                theta += next_argument - argument_value;
                argument_value = next_argument;
                argument_at = end;
                previous = value;
                before = at = std::abs(previous);
                k = end - 1;
                continue;
            }
            const Complex direction = (b - a) / length;
            double t = 0.0;
            while (t < length) {
                const Complex s = a + t * direction;
                const double distance = pole_distance(s);
                if (!panel.covers(a, direction, t))
                    prepare_panel(a, direction, t, std::min(length - t, 4.0 * distance));
                double h = std::min({length - t, 1.0 / std::max(tau_max, 1e-12), 0.25 * distance});
                for (;;) {
                    const double t_next = std::min(length, t + h);
                    const Complex next = t_next == length
                                             ? determinant(loop_from(samples.m[k + 1], transfer, b))
                                             : characteristic(a, direction, t_next);
                    if (t_next == length) ++evaluations;
                    if (evaluations > budget) {
                        failed = true;
                        return theta;
                    }
                    const double step = std::arg(next / previous);
                    if (std::abs(step) <= quarter_turn || h <= 1e-12 * std::max(1.0, std::abs(s))) {
                        theta += step;
                        const double after = std::abs(next);
                        if (at < before && at <= after) dips.push_back({at, s});
                        before = at;
                        at = after;
                        previous = next;
                        t = (length - t - h <= 1e-15 * length) ? length : t + h;
                        break;
                    }
                    h *= 0.5;
                }
            }
            argument_at = grid.size();
        }
        return theta;
    }
};

// The line's grid: log-spaced over 1e-2 .. 1e7 rad/s (60 a decade) and around every pole of A0
// (at 0, 1/4, 1/2, 1, 2 and 4 times its distance from the line), from omega = 0; sorted, unique.
std::vector<Complex> line_grid(const Eigen::VectorXcd& poles, double alpha) {
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
    std::vector<Complex> line;
    line.reserve(grid.size());
    for (double w : grid) line.emplace_back(alpha, w);
    return line;
}

// alpha moved off A0's poles by a hair where one sits on the line (F has them).
double off_line_poles(const Eigen::VectorXcd& poles, double alpha) {
    for (int attempt = 0; attempt < 8; ++attempt) {
        bool clear = true;
        for (Eigen::Index k = 0; k < poles.size(); ++k) {
            if (std::abs(poles(k).real() - alpha) <= 1e-9 * std::max(1.0, std::abs(poles(k))))
                clear = false;
        }
        if (clear) break;
        alpha += 1e-6 * std::max(1.0, std::abs(alpha));
    }
    return alpha;
}

}  // namespace

Complex delay_characteristic(const TransportTransfer& transfer, Complex s) {
    if (transfer.spans() == 0) return 1.0;
    return determinant(loop(transfer, s));
}

namespace {

// The line's start shared by the counts: alpha off A0's poles, A0's poles right of it; done
// (a count with no spans) or not.
bool line_prelude(const TransportTransfer& transfer, double& alpha, DelayRootCount& out) {
    if (!transfer.ok) {
        out.message = "no linearisation";
        return true;
    }
    const Eigen::VectorXcd& poles = transfer.poles;
    // the line must miss A0's poles (F has them): move it by a hair where one sits on it
    alpha = off_line_poles(poles, alpha);
    out.alpha = alpha;
    for (Eigen::Index k = 0; k < poles.size(); ++k)
        if (poles(k).real() > alpha) ++out.frozen_right;
    if (transfer.spans() == 0) {
        out.ok = true;
        out.count = out.frozen_right;
        return true;
    }
    return false;
}

// The count from the line's samples (its whole grid, or its loud stretches with the gaps
// between them given quiet).
DelayRootCount count_from_samples(ArgumentTracker& tracker, const ArgumentTracker::Samples& samples,
                                  DelayRootCount out) {
    if (samples.gain.back() >= ArgumentTracker::small) {
        out.message = "the loop gain does not fall below 1/2 by 1e7 rad/s";
        return out;
    }
    std::vector<std::pair<double, Complex>> dips;  // (|F|, s) at local minima
    double theta = tracker.follow(samples, dips);
    out.evaluations = tracker.evaluations;
    out.sampled = static_cast<int>(samples.s.size());
    if (tracker.failed) {
        out.message = "the argument principle needed more than 4e6 evaluations";
        return out;
    }
    // the tail: from the last point, where every eigenvalue of I - M E is within 1/2 of 1, to
    // infinity, where M = O(1/s^2) and F -> 1
    Complex last;
    theta -= tracker.argument(samples, samples.s.size() - 1, last);
    // omega = 0: F is real there, so arg F(alpha) is 0 or pi; the increments start from it
    const double winding = -theta / std::numbers::pi;
    const double total = out.frozen_right + winding;
    out.winding = winding;
    out.count = static_cast<int>(std::lround(total));
    out.integer_error = std::abs(total - out.count);
    out.ok = out.integer_error < 1e-2;
    std::sort(dips.begin(), dips.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    if (dips.size() > 16) dips.resize(16);
    for (const auto& dip : dips) out.dips.push_back(dip.second);
    out.message = out.ok ? "" : "the winding number is not an integer: F vanishes near the line";
    return out;
}

}  // namespace

DelayRootCount nominal_delay_root_count(const TransportTransfer& transfer, double alpha) {
    DelayRootCount out;
    if (line_prelude(transfer, alpha, out)) return out;
    ArgumentTracker tracker(transfer);
    return count_from_samples(tracker, tracker.sample(line_grid(transfer.poles, alpha)), out);
}

LoudStretches loud_stretches(const TransportTransfer& transfer, double alpha, double threshold) {
    LoudStretches out;
    DelayRootCount prelude;
    if (line_prelude(transfer, alpha, prelude)) {
        out.ok = prelude.ok;  // no spans: nothing is loud
        out.alpha = alpha;
        return out;
    }
    out.alpha = alpha;
    ArgumentTracker tracker(transfer);
    const ArgumentTracker::Samples samples = tracker.sample(line_grid(transfer.poles, alpha));
    if (samples.gain.back() >= ArgumentTracker::small) return out;
    // as ArgumentTracker::quiet with the threshold for 0.9: an interval is loud unless both ends
    // are below 1/2, or both ends and the middle below the threshold
    for (std::size_t k = 0; k + 1 < samples.s.size(); ++k) {
        const double g0 = samples.gain[k], g1 = samples.gain[k + 1];
        if (g0 < ArgumentTracker::small && g1 < ArgumentTracker::small) continue;
        if (g0 < threshold && g1 < threshold &&
            tracker.gain(0.5 * (samples.s[k] + samples.s[k + 1]), threshold) < threshold)
            continue;
        const double a = samples.s[k].imag(), b = samples.s[k + 1].imag();
        if (!out.omega.empty() && out.omega.back().second >= a) {
            out.omega.back().second = b;
        } else {
            out.omega.emplace_back(a, b);
        }
    }
    out.ok = true;
    return out;
}

LoudStretches loud_union(const LoudStretches& x, const LoudStretches& y) {
    LoudStretches out;
    out.ok = x.ok && y.ok && x.alpha == y.alpha;
    out.alpha = x.alpha;
    std::vector<std::pair<double, double>> all = x.omega;
    all.insert(all.end(), y.omega.begin(), y.omega.end());
    std::sort(all.begin(), all.end());
    for (const auto& [a, b] : all) {
        if (!out.omega.empty() && out.omega.back().second >= a) {
            out.omega.back().second = std::max(out.omega.back().second, b);
        } else {
            out.omega.emplace_back(a, b);
        }
    }
    return out;
}

DelayRootCount nominal_delay_root_count(const TransportTransfer& transfer, double alpha,
                                        const LoudStretches& loud) {
    DelayRootCount out;
    const double asked = alpha;
    if (line_prelude(transfer, alpha, out)) return out;
    if (!loud.ok || alpha != loud.alpha) return nominal_delay_root_count(transfer, asked);
    // this speed's grid: every point inside a stretch and its neighbours outside it, omega = 0
    // and the last; the gaps between them given quiet
    const std::vector<Complex> line = line_grid(transfer.poles, alpha);
    const auto inside = [&loud](double w) {
        for (const auto& [a, b] : loud.omega)
            if (w >= a && w <= b) return true;
        return false;
    };
    std::vector<char> keep(line.size(), 0);
    keep.front() = keep.back() = 1;
    for (std::size_t k = 0; k < line.size(); ++k) {
        if (!inside(line[k].imag())) continue;
        keep[k] = 1;
        if (k > 0) keep[k - 1] = 1;
        if (k + 1 < line.size()) keep[k + 1] = 1;
    }
    std::vector<Complex> kept;
    std::vector<char> gap;  // per kept interval: points of the grid skipped inside it
    for (std::size_t k = 0, previous = 0; k < line.size(); ++k) {
        if (keep[k] == 0) continue;
        if (!kept.empty()) gap.push_back(k > previous + 1 ? 1 : 0);
        kept.push_back(line[k]);
        previous = k;
    }
    ArgumentTracker tracker(transfer);
    ArgumentTracker::Samples samples = tracker.sample(kept);
    samples.given_quiet = std::move(gap);
    // a gap's ends must be quiet at this speed too, else the whole line is counted
    for (std::size_t k = 0; k < samples.given_quiet.size(); ++k) {
        if (samples.given_quiet[k] != 0 && (samples.gain[k] >= ArgumentTracker::skip ||
                                            samples.gain[k + 1] >= ArgumentTracker::skip))
            return nominal_delay_root_count(transfer, asked);
    }
    return count_from_samples(tracker, samples, out);
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

namespace {

// Points on [from, to] for an edge's gain grid: log-spaced (60 a decade) from `from` > 0, or
// `uniform` equal intervals, plus the points around each coordinate in `centres` at the given
// distances (as the line's grid has around A0's poles); sorted, unique.
std::vector<double> edge_grid(double from, double to, bool log_spaced, int uniform,
                              const std::vector<std::pair<double, double>>& centres) {
    std::vector<double> x{from, to};
    if (log_spaced) {
        const double start = std::max(from, 1e-2);
        if (start < to) {
            const int n = static_cast<int>(std::ceil(60.0 * std::log10(to / start)));
            for (int k = 0; k <= n; ++k)
                x.push_back(start * std::pow(to / start, static_cast<double>(k) / std::max(n, 1)));
        }
    } else {
        for (int k = 1; k < uniform; ++k)
            x.push_back(from + (to - from) * static_cast<double>(k) / uniform);
    }
    for (const auto& [centre, d] : centres)
        for (double f : {-4.0, -2.0, -1.0, -0.5, -0.25, 0.0, 0.25, 0.5, 1.0, 2.0, 4.0}) {
            const double y = centre + f * d;
            if (y > from && y < to) x.push_back(y);
        }
    std::sort(x.begin(), x.end());
    x.erase(std::unique(x.begin(), x.end()), x.end());
    while (!x.empty() && x.back() > to) x.pop_back();
    return x;
}

// Moves `value` upward by hairs until no pole's coordinate (`real` or imaginary part) lies on it.
double off_poles(const Eigen::VectorXcd& poles, double value, bool real) {
    for (int attempt = 0; attempt < 8; ++attempt) {
        bool clear = true;
        for (Eigen::Index k = 0; k < poles.size(); ++k) {
            const double c = real ? poles(k).real() : poles(k).imag();
            if (std::abs(c - value) <= 1e-9 * std::max(1.0, std::abs(poles(k)))) clear = false;
        }
        if (clear) break;
        value += 1e-6 * std::max(1.0, std::abs(value));
    }
    return value;
}

}  // namespace

BandRootCount band_root_count(const TransportTransfer& transfer, double omega_max, double alpha) {
    BandRootCount out;
    if (!transfer.ok) {
        out.message = "no linearisation";
        return out;
    }
    if (!(omega_max > 0.0) || !std::isfinite(omega_max)) {
        out.message = "the band's top frequency must be positive and finite";
        return out;
    }
    const Eigen::VectorXcd& poles = transfer.poles;
    alpha = off_poles(poles, alpha, true);
    omega_max = off_poles(poles, omega_max, false);
    double epsilon =
        off_poles(poles, 1e-6 * std::max(1.0, omega_max) / (2.0 * std::numbers::pi), false);
    out.alpha = alpha;
    out.omega_max = omega_max;
    out.epsilon = epsilon;
    if (!(epsilon < omega_max)) {
        out.ok = true;  // an empty band
        return out;
    }
    const auto inside = [&](Complex p, double right) {
        return p.real() > alpha && p.real() < right && p.imag() > epsilon && p.imag() < omega_max;
    };
    if (transfer.spans() == 0) {
        for (Eigen::Index k = 0; k < poles.size(); ++k)
            if (inside(poles(k), std::numeric_limits<double>::infinity())) ++out.frozen_inside;
        out.right = std::numeric_limits<double>::infinity();
        out.count = out.frozen_inside;
        out.ok = true;
        return out;
    }

    ArgumentTracker tracker(transfer);
    std::vector<std::pair<double, double>> pole_heights, pole_abscissae;  // (coordinate, distance)
    for (Eigen::Index k = 0; k < poles.size(); ++k) {
        const Complex p = poles(k);
        if (p.imag() < 0.0) continue;
        pole_heights.push_back(
            {p.imag(), std::max(std::abs(p.real() - alpha), 1e-9 * std::abs(p))});
    }
    const std::vector<double> heights = edge_grid(epsilon, omega_max, true, 0, pole_heights);

    // the right edge: doubled from A0's rightmost pole + 1 until the gain is below 1/2 on it
    double pole_right = alpha;
    for (Eigen::Index k = 0; k < poles.size(); ++k)
        pole_right = std::max(pole_right, poles(k).real());
    double right = pole_right + 1.0;
    bool small = false;
    for (int attempt = 0; attempt < 40 && !small; ++attempt) {
        right = off_poles(poles, right, true);
        small = true;
        for (double w : heights) {
            ++tracker.evaluations;
            if (!(tracker.gain({right, w}, ArgumentTracker::small) < ArgumentTracker::small)) {
                small = false;
                break;
            }
        }
        if (!small) right = alpha + 2.0 * (right - alpha);
    }
    out.right = right;
    if (!small) {
        out.message = "the loop gain does not fall below 1/2 on any right edge";
        return out;
    }
    for (Eigen::Index k = 0; k < poles.size(); ++k)
        if (inside(poles(k), right)) ++out.frozen_inside;

    // the horizontal edges' grids: 128 intervals and the points around A0's poles near them
    const auto abscissae = [&](double height) {
        std::vector<std::pair<double, double>> centres;
        for (Eigen::Index k = 0; k < poles.size(); ++k) {
            const Complex p = poles(k);
            centres.push_back(
                {p.real(), std::max(std::abs(p.imag() - height), 1e-9 * std::abs(p))});
        }
        return edge_grid(alpha, right, false, 128, centres);
    };
    const auto path = [](const std::vector<double>& x, auto point) {
        std::vector<Complex> p;
        p.reserve(x.size());
        for (double v : x) p.push_back(point(v));
        return p;
    };
    std::vector<std::pair<double, Complex>> left_dips, edge_dips;
    const auto follow = [&](const std::vector<Complex>& edge,
                            std::vector<std::pair<double, Complex>>& dips) {
        return tracker.follow(tracker.sample(edge), dips);
    };
    const double left =
        follow(path(heights, [&](double w) { return Complex(alpha, w); }), left_dips);
    const double right_edge =
        follow(path(heights, [&](double w) { return Complex(right, w); }), edge_dips);
    const double top = follow(
        path(abscissae(omega_max), [&](double x) { return Complex(x, omega_max); }), edge_dips);
    const double bottom =
        follow(path(abscissae(epsilon), [&](double x) { return Complex(x, epsilon); }), edge_dips);
    out.evaluations = tracker.evaluations;
    if (tracker.failed) {
        out.message = "the argument principle needed more than 4e6 evaluations";
        return out;
    }
    // counter-clockwise: bottom rightward, right edge upward, top leftward, left edge downward
    const double winding = (bottom + right_edge - top - left) / (2.0 * std::numbers::pi);
    const double total = out.frozen_inside + winding;
    out.winding = winding;
    out.count = static_cast<int>(std::lround(total));
    out.integer_error = std::abs(total - out.count);
    out.ok = out.integer_error < 1e-2;
    out.message = out.ok ? "" : "the winding number is not an integer: F vanishes near an edge";
    const auto by_value = [](const auto& x, const auto& y) { return x.first < y.first; };
    std::sort(left_dips.begin(), left_dips.end(), by_value);
    std::sort(edge_dips.begin(), edge_dips.end(), by_value);
    if (left_dips.size() > 16) left_dips.resize(16);
    if (edge_dips.size() > 8) edge_dips.resize(8);
    for (const auto& dip : left_dips) out.dips.push_back(dip.second);
    for (const auto& dip : edge_dips) out.dips.push_back(dip.second);
    return out;
}

RightmostDelayRoot band_rightmost_root(const TransportTransfer& transfer,
                                       const BandRootCount& count) {
    RightmostDelayRoot out;
    const double omega_max = count.omega_max;
    std::vector<Complex> starts = count.dips;
    for (Eigen::Index k = 0; k < transfer.poles.size(); ++k) {
        const Complex pole = transfer.poles(k);
        if (pole.imag() > 0.0 && pole.imag() < omega_max)
            starts.push_back(pole + std::max(1.0, 0.1 * std::abs(pole.real())));
    }
    for (int round = 0; round < 8 && !starts.empty(); ++round) {
        for (const Complex& start : starts) {
            ++out.starts;
            const DelayRoot root = delay_root(transfer, start);
            if (!root.converged || !(root.residual < 1e-8) || !(root.s.imag() > count.epsilon) ||
                !(root.s.imag() < omega_max))
                continue;
            if (!out.found || root.s.real() > out.root.s.real()) {
                out.found = true;
                out.root = root;
            }
        }
        if (!out.found && round == 0) {
            // no dip or pole led into the band: starts along the left edge, half a radian of
            // the longest delay's phase apart (at most 256)
            double tau_max = 0.0;
            for (double tau : transfer.delay) tau_max = std::max(tau_max, tau);
            const double row = std::max(omega_max / 256.0, 0.5 / std::max(tau_max, 1e-12));
            starts.clear();
            for (double w = 0.5 * row; w < omega_max; w += row) starts.emplace_back(count.alpha, w);
            continue;
        }
        if (!out.found) return out;
        const double beyond = out.root.s.real() + std::max(1e-3, 1e-9 * std::abs(out.root.s));
        const BandRootCount right = band_root_count(transfer, omega_max, beyond);
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
