#include "tools/reproduce_paper/trend.h"

#include <algorithm>
#include <cmath>

namespace rollgap::tools::paper {

Trend trend_of(const std::vector<double>& xs, const std::vector<double>& ys, int claimed_sign,
               const std::function<std::string(double)>& x_text,
               const std::function<std::string(double)>& y_text, double tolerance) {
    Trend t;
    std::vector<double> x, y;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        if (std::isfinite(ys[i])) {
            x.push_back(xs[i]);
            y.push_back(ys[i]);
        }
    }
    if (x.size() < 2) {
        t.direction = "no curve (fewer than two points with a value)";
        t.verdict = "not testable";
        return t;
    }
    t.testable = true;
    double scale = 0.0;
    for (double v : y) scale = std::max(scale, std::abs(v));
    const double tol = tolerance * scale;
    std::size_t start = 0, ext = 0;
    int dir = 0;
    for (std::size_t i = 1; i < x.size(); ++i) {
        if (dir == 0) {
            if (std::abs(y[i] - y[start]) > tol) {
                dir = y[i] > y[start] ? 1 : -1;
                ext = i;
            }
        } else if ((y[i] - y[ext]) * dir >= 0.0) {
            ext = i;
        } else if (std::abs(y[i] - y[ext]) > tol) {
            t.segments.push_back({x[start], x[ext], y[start], y[ext], dir});
            start = ext;
            dir = -dir;
            ext = i;
        }
    }
    if (dir != 0) t.segments.push_back({x[start], x[ext], y[start], y[ext], dir});
    // a flat tail after the last extremum joins the last segment's x range
    if (!t.segments.empty()) t.segments.back().x1 = std::max(t.segments.back().x1, x[ext]);
    const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
    t.y_min = *lo;
    t.y_max = *hi;
    t.x_at_min = x[static_cast<std::size_t>(lo - y.begin())];
    t.x_at_max = x[static_cast<std::size_t>(hi - y.begin())];

    const double range = x.back() - x.front();
    if (t.segments.empty()) {
        t.direction = "flat (within " + fmt(tolerance * 100, 1) + " %)";
        t.verdict = "disagrees";
        return t;
    }
    if (t.segments.size() == 1) {
        const Segment& s = t.segments.front();
        t.direction = std::string(s.sign > 0 ? "increasing" : "decreasing") + " (" + y_text(s.y0) +
                      " → " + y_text(s.y1) + ", " + percent(s.y1 / s.y0 - 1.0) + ")";
    } else {
        std::string text = "non-monotone: ";
        for (std::size_t k = 0; k < t.segments.size(); ++k) {
            const Segment& s = t.segments[k];
            if (k) text += "; ";
            text += std::string(s.sign > 0 ? "rises" : "falls") + " from " + x_text(s.x0) + " to " +
                    x_text(s.x1) + " (" + y_text(s.y0) + " → " + y_text(s.y1) + ", " +
                    percent(s.y1 / s.y0 - 1.0) + ")";
        }
        // the interior extremum
        const bool interior_min = t.x_at_min > x.front() && t.x_at_min < x.back();
        const bool interior_max = t.x_at_max > x.front() && t.x_at_max < x.back();
        if (interior_min) text += "; minimum " + y_text(t.y_min) + " at " + x_text(t.x_at_min);
        if (interior_max) text += "; maximum " + y_text(t.y_max) + " at " + x_text(t.x_at_max);
        t.direction = text;
    }
    double agreeing = 0.0;
    for (const Segment& s : t.segments) {
        if (s.sign == claimed_sign) agreeing += s.x1 - s.x0;
    }
    t.agreeing_fraction = range > 0.0 ? agreeing / range : 0.0;
    bool any_agree = false, any_disagree = false;
    for (const Segment& s : t.segments) (s.sign == claimed_sign ? any_agree : any_disagree) = true;
    t.verdict = any_agree && !any_disagree ? "agrees" : !any_agree ? "disagrees" : "partly agrees";
    const double variation = (t.y_max - t.y_min) / std::max(std::abs(t.y_max), 1e-300);
    if (variation < 0.1 && t.verdict != "disagrees")
        t.direction += " — nearly flat (total variation " + fmt(variation * 100, 1) + " %)";
    return t;
}

}  // namespace rollgap::tools::paper
