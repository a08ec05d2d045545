#pragma once
// The report's building blocks: table cells, verdicts and the tables that recur in its sections.

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "tools/reproduce_paper/results.h"

namespace rollgap::tools::paper {

std::string status_cell(const core::CriticalSpeedResult& r);
// "0.52–3.10 (mixed)": the film ratio H_t over the bite and the lubrication regime it means.
std::string regime_text(double ht_min, double ht_max);
std::string verdict_cell(const Trend& t);

// Range of a value over the points that have one.
template <class F>
std::pair<double, double> span_of(const SweepRun& run, F&& value) {
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& p : run.points) {
        const double v = value(p);
        if (!std::isfinite(v)) continue;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    return {lo, hi};
}

std::string eulerian_summary(const SweepRun& run);
void md_sweep_table(std::ostringstream& md, const SweepFigure& fig, const Results& R,
                    std::size_t index);
void md_diag_row(std::ostringstream& md, const ModeDiagnostics& d, bool with_loop = true);

std::string short_direction(const Trend& t);
std::string extremum_text(const Trend& t, const SweepFigure& fig);

struct CycleChecks {
    bool available = false;
    double dP_high = no_value, dP_mid = no_value,
           dP_low = no_value;  // force(Rq 6) - force(Rq 1) at T = 0.25, 0.5, 0.75
    double mean_p_ratio_low = no_value, peak_p_ratio_low = no_value;  // Rq 6 / Rq 1 at T = 0.75
    bool rough_higher_everywhere = true;
    bool tension_lowers_pressure = true;  // force(T=.25) < force(T=.75) for both Rq
    double friction_ratio_min = INFINITY,
           friction_ratio_max = -INFINITY;           // mean |tau|, Rq 6 / Rq 1
    double tension_effect_on_friction = 0.0;         // largest |tau(T=.25) - tau(T=.75)| / tau
    double roughness_effect_on_friction = INFINITY;  // smallest |tau6 - tau1| / tau1
};

CycleChecks check_cycles(const CycleRun& run);
std::string fig14_verdict(const CycleChecks& c);
std::string fig15_verdict(const CycleChecks& c);
std::string bold(const std::string& verdict);
void md_cycle_table(std::ostringstream& md, const CycleRun& run);

}  // namespace rollgap::tools::paper
