#pragma once
// Trends: the direction of a curve, computed from the data, and the verdict against a claim.

#include <functional>
#include <string>
#include <vector>

#include "tools/reproduce_paper/common.h"

namespace rollgap::tools::paper {

struct Segment {
    double x0, x1, y0, y1;
    int sign;  // +1 rising, -1 falling
};

struct Trend {
    bool testable = false;
    std::vector<Segment> segments;
    double y_min = no_value, y_max = no_value, x_at_min = no_value, x_at_max = no_value;
    std::string direction;           // e.g. "decreasing", "non-monotone: ..."
    std::string verdict;             // "agrees", "disagrees", "partly agrees", "not testable"
    double agreeing_fraction = 0.0;  // of the x range
};

// Monotone runs with hysteresis: a reversal counts once the curve has moved back from its
// running extremum by more than `tolerance` (relative to the largest |y|), so that numerical
// noise does not split a run but a real small reversal does.
Trend trend_of(const std::vector<double>& xs, const std::vector<double>& ys, int claimed_sign,
               const std::function<std::string(double)>& x_text,
               const std::function<std::string(double)>& y_text, double tolerance = 2e-3);

}  // namespace rollgap::tools::paper
