#pragma once
// Golden-section search for the minimum of a unimodal function on a bracket: the one minimiser
// the mill's regenerative margin uses for the frequency of the bound's peak and the structured
// bound for each diagonal scaling (docs/model.md §12.5).

namespace rollgap::core {

struct GoldenSectionResult {
    double x = 0.0;       // the midpoint of the last bracket
    int evaluations = 0;  // f evaluated
};

// Shrinks [lo, hi] by the golden ratio at most `iterations` times, while it is wider than
// `width`, keeping the side with the smaller of the two inner values (the right one on a tie);
// one evaluation a step after the first two.
template <class F>
GoldenSectionResult golden_section_minimum(F&& f, double lo, double hi, int iterations,
                                           double width = 0.0) {
    constexpr double golden = 0.6180339887498949;
    GoldenSectionResult out;
    double c = hi - golden * (hi - lo), d = lo + golden * (hi - lo);
    double fc = f(c), fd = f(d);
    out.evaluations = 2;
    for (int k = 0; k < iterations && hi - lo > width; ++k) {
        if (fc < fd) {
            hi = d;
            d = c;
            fd = fc;
            c = hi - golden * (hi - lo);
            fc = f(c);
        } else {
            lo = c;
            c = d;
            fc = fd;
            d = lo + golden * (hi - lo);
            fd = f(d);
        }
        ++out.evaluations;
    }
    out.x = 0.5 * (lo + hi);
    return out;
}

}  // namespace rollgap::core
