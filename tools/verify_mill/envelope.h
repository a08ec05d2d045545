#pragma once
// A time series' envelope for identity 8 (docs/model.md §12.8): the growth rate of a mill's gap
// after a kick against the rightmost delay root's real part. Shared by the verification report
// (tools/verify_mill) and its test (tests/core/test_mill_time.cpp).
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/mill/mill_time.h"

namespace rollgap::tools::envelope {

// The envelope's growth rate (least squares on the log of the positive peaks of g, each peak
// refined by the parabola through its three samples) and the frequency (upward zero crossings)
// over [from, to].
struct Envelope {
    double growth_rate = 0.0;  // 1/s
    double frequency = 0.0;    // Hz
    int peaks = 0;
};

inline Envelope envelope(const std::vector<double>& t, const std::vector<double>& g, double from,
                         double to) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    Envelope e;
    std::vector<double> crossings;
    for (std::size_t i = 1; i + 1 < g.size(); ++i) {
        if (t[i] < from || t[i] > to) continue;
        if (g[i] > 0 && g[i] > g[i - 1] && g[i] >= g[i + 1]) {
            const double curvature = g[i - 1] - 2 * g[i] + g[i + 1];
            const double shift = 0.5 * (g[i - 1] - g[i + 1]) / curvature;  // in samples
            const double peak = g[i] - 0.25 * (g[i - 1] - g[i + 1]) * shift;
            const double tp = t[i] + shift * (t[i + 1] - t[i]);
            const double y = std::log(peak);
            sx += tp;
            sy += y;
            sxx += tp * tp;
            sxy += tp * y;
            ++e.peaks;
        }
        if (g[i - 1] < 0 && g[i] >= 0)
            crossings.push_back(t[i - 1] + (t[i] - t[i - 1]) * (-g[i - 1]) / (g[i] - g[i - 1]));
    }
    e.growth_rate = (e.peaks * sxy - sx * sy) / (e.peaks * sxx - sx * sx);
    if (crossings.size() > 1)
        e.frequency =
            static_cast<double>(crossings.size() - 1) / (crossings.back() - crossings.front());
    return e;
}

// Output times dt, 2 dt, ... up to end.
inline std::vector<double> grid(double dt, double end) {
    std::vector<double> times;
    for (int i = 1; i * dt <= end + 1e-15; ++i) times.push_back(i * dt);
    return times;
}

// Stand k's gap over the run.
inline void gap_series(const core::MillTimeResult& run, int k, std::vector<double>& t,
                       std::vector<double>& g) {
    t.clear();
    g.clear();
    for (const core::MillTimeSample& s : run.samples) {
        t.push_back(s.t);
        g.push_back(s.stands[static_cast<std::size_t>(k)].gap);
    }
}

}  // namespace rollgap::tools::envelope
