#pragma once
// A time series' envelope for identity 8 (docs/model.md §12.8): the growth rate of a mill's gap
// after a kick against the rightmost delay root's real part. Shared by the verification report
// (tools/verify_mill) and its test (tests/core/test_mill_time.cpp).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <numbers>
#include <vector>

#include "core/mill/mill_stability.h"
#include "core/mill/mill_time.h"
#include "tools/verify_mill/mills.h"

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

// Identity 8 on one mill: its rightmost delay root at its speed, a kick on stand 1's gap run for
// `end` seconds (output 60 samples a period of the root), and each stand's gap envelope over
// [from, end] with the largest gap change of the run.
struct KickCase {
    core::Mill mill;
    double kick = 1e-9;             // m, on stand 1's gap
    double tolerance_scale = 1e-3;  // MillTimeOptions::absolute_tolerance_scale
    double from = 0.05, end = 0.1;  // s
};

struct KickFit {
    core::MillSpeedStability at;
    std::complex<double> root;  // 1/s, the rightmost delay root (when at.rightmost.found)
    double frequency = 0.0;     // Hz
    core::MillTimeResult run;   // status `invalid` when no root was found
    std::vector<Envelope> stands;
    std::vector<double> largest;  // |gap change| over the run, m, per stand
};

inline KickFit fit_kick(const KickCase& c) {
    KickFit out;
    out.at = core::mill_stability_at(c.mill);
    if (!out.at.rightmost.found) {
        out.run.status = core::MillTimeStatus::invalid;
        return out;
    }
    out.root = out.at.rightmost.root.s;
    out.frequency = out.root.imag() / (2.0 * std::numbers::pi);
    core::MillKick kick;
    kick.stand = 0;
    kick.gap = c.kick;
    core::MillTimeOptions options;
    options.absolute_tolerance_scale = c.tolerance_scale;
    out.run = core::mill_time_domain(c.mill, out.at.steady, kick,
                                     grid(1.0 / (60.0 * out.frequency), c.end), options);
    if (out.run.status != core::MillTimeStatus::ok) return out;
    for (int k = 0; k < c.mill.size(); ++k) {
        std::vector<double> t, g;
        gap_series(out.run, k, t, g);
        out.stands.push_back(envelope(t, g, c.from, c.end));
        double largest = 0.0;
        for (double x : g) largest = std::max(largest, std::abs(x));
        out.largest.push_back(largest);
    }
    return out;
}

// The three cases of identity 8 the report prints and tests/core/test_mill_time.cpp checks.
// Growing: two stands with a 0.05 m span at 9 m/s (tau = 6.2 ms), the rightmost root (~82 /s at
// ~505 Hz) more than 60 /s right of every other but its conjugate.
inline KickCase growing_case() {
    KickCase c;
    c.mill = mills::two_stand_mill(0.05);
    c.mill.speed = 9.0;
    return c;  // 1e-9 m, tolerances x 1e-3 (1e-13 m on 1e-9 m), 0.05-0.1 s
}

// Decaying: the same with the stands' structural damping at 0.2 of critical (0.04 by default):
// rho < 1, stable for every set of delays, the rightmost root (~ -15 /s at ~505 Hz) more than
// 20 /s right of every other. Fitted over 0.1-0.4 s with the tolerances x 1e-7 (1e-17 m): they
// must stay far below the motion, which ends at ~3e-12 m (x 1e-3: 13 % off).
inline KickCase decaying_case() {
    KickCase c = growing_case();
    for (core::Scenario& stand : c.mill.stands) stand.structure.rayleigh_damping_ratio = 0.2;
    c.tolerance_scale = 1e-7;
    c.from = 0.1;
    c.end = 0.4;
    return c;
}

// Under segments: the growing case with each span cut into two segments (three states per
// span), the segments model's root (~95 /s at ~513 Hz) more than 60 /s right of every other; a
// kick of 1e-10 m keeps the faster growth linear to the end, 0.09 s.
inline KickCase segments_case() {
    KickCase c = growing_case();
    c.mill.span_model = core::SpanModel::segments;
    c.mill.span_segments = 2;
    c.kick = 1e-10;
    c.end = 0.09;
    return c;
}

}  // namespace rollgap::tools::envelope
