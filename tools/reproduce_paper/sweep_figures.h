#pragma once
// Figs. 8-12: the critical speed against one scenario field, per inlet film model: the runs,
// their CSV tables and plots.
#include <functional>
#include <string>
#include <vector>

#include "core/control.h"
#include "core/stability.h"
#include "tools/reproduce_paper/common.h"
#include "tools/reproduce_paper/output.h"
#include "tools/reproduce_paper/trend.h"

namespace rollgap::tools::paper {

struct SweepFigure {
    int number;
    std::string id;        // fig08
    std::string quantity;  // what is varied, in words
    std::string x_symbol;  // η0
    std::string x_unit;    // mPa·s
    std::string x_column;  // CSV column name
    int x_decimals;
    std::vector<double> xs;
    std::function<void(Scenario&, double)> apply;
    int claimed_sign;         // sign of d v_c / dx the paper claims
    std::string claim_quote;  // the paper's words
    std::string claim;        // the claim as a direction of v_c(x)
    std::string setup;        // how the scenario is set

    std::string x_text(double x) const { return fmt(x, x_decimals) + " " + x_unit; }
    std::string x_label() const { return x_symbol + " (" + x_unit + ")"; }
};

// from, from + step, ... up to `to` (inclusive, with a tolerance).
std::vector<double> range(double from, double to, double step);
// The five figures: what is varied, how the scenario is set and what the paper claims.
std::vector<SweepFigure> sweep_figures();

struct GapModeCrossing {
    std::string status =
        "none";  // found, stable_in_range, unstable_at_lower_bound, none (no ~100 Hz branch)
    double speed = no_value;
    double frequency_Hz = no_value;
    double unstable_below =
        no_value;  // when the branch starts unstable and recovers: the speed where it does
};

// The ~100 Hz gap mode's own zero crossing over the scan (a secondary figure).
GapModeCrossing gap_mode_crossing(const core::CriticalSpeedResult& r);

struct SweepPoint {
    double x = 0.0;
    core::CriticalSpeedResult result;
    GapModeCrossing gap_mode;
    ModeDiagnostics diag;  // at the critical speed, for the crossing mode (found points only)
};

struct SweepRun {
    InletFilmModel film = InletFilmModel::paper;
    double asperity_factor = 1.0;  // m_a of the run (docs/model.md §4; 1 is the paper's)
    std::vector<SweepPoint> points;
    Trend trend;      // of the critical speed (censored points at the range ends)
    Trend gap_trend;  // of the gap-mode crossing
    int found = 0;
    double seconds = 0.0;
};

// The critical-speed search of every figure: 1-60 m/s, 0.5 m/s scan, 1e-4 relative.
inline const core::CriticalSpeedOptions search_options{};

double trend_value(const core::CriticalSpeedResult& r);
std::string speed_text(double v);
Series named(std::string label);
// asperity_factor: m_a of every scenario (1, the paper's, unless a labelled variant asks).
SweepRun run_sweep(const SweepFigure& fig, InletFilmModel film, const core::Control& compute,
                   double asperity_factor = 1.0);
void write_sweep_csv(Output& out, const SweepFigure& fig, const SweepRun& run);
void add_status_edges(Plot& plot, const SweepFigure& fig, const SweepRun& run,
                      const std::string& suffix);
Series critical_series(const SweepFigure& fig, const SweepRun& run, const std::string& label);
// The axes and title of a critical-speed plot of one of Figs. 8-12; `what` ends the title.
Plot critical_speed_plot(const SweepFigure& fig, const std::string& what);
void plot_sweep(Output& out, const SweepFigure& fig, const SweepRun& run, const SweepRun& paper,
                const SweepRun* fixed_friction, double fixed_mu);

}  // namespace rollgap::tools::paper
