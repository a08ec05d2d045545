// reproduce_paper: regenerates the paper's Figs. 8-15 (Wang et al., Tribology International 67
// (2013) 174-181) with the rollgap core, for both inlet film models (paper, eulerian), as CSV
// files and SVG plots, and writes docs/paper-reproduction.md: per figure the curve the model
// gives, the direction the paper claims, whether they agree and, where they do not, the
// mechanism (from the linearisation of the coupled model, see tools/diagnostics.h).
//
//   reproduce_paper [--out DIR] [--doc FILE] [--threads N]
//
// Defaults: --out docs/paper-reproduction, --doc docs/paper-reproduction.md, all hardware
// threads. Deterministic: every analysis is a pure function of its scenario and the sweeps put
// each result in its own slot, so only the runtime figures change from run to run.
// Nothing here tunes the model: every scenario is MODEL.md §8's default with the one field the
// figure varies (and the stated diagnostics variants, which are labelled as such).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/amplitude.h"
#include "core/inlet_film.h"
#include "core/parallel_for.h"
#include "core/roll_bite.h"
#include "core/scenario.h"
#include "core/stability.h"
#include "core/sweep.h"
#include "core/tension_cycle.h"
#include "tools/diagnostics.h"
#include "tools/svg_plot.h"

namespace fs = std::filesystem;
using namespace rollgap;
using core::CriticalSpeedStatus;
using core::InletFilmModel;
using core::Scenario;
using tools::EdgeMarkers;
using tools::Marker;
using tools::ModeDiagnostics;
using tools::Plot;
using tools::Series;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const InletFilmModel kFilmModels[] = {InletFilmModel::paper, InletFilmModel::eulerian};

// ---------------------------------------------------------------------------------------------
// Small utilities

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::mutex log_mutex;
void log(const std::string& message) {
    std::lock_guard<std::mutex> lock(log_mutex);
    std::fprintf(stderr, "reproduce_paper: %s\n", message.c_str());
    std::fflush(stderr);
}

std::string fmt(double v, int decimals) {
    if (!std::isfinite(v)) return "–";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
    std::string s = buffer;
    if (s.rfind("-0", 0) == 0 && std::strtod(s.c_str(), nullptr) == 0.0) s.erase(0, 1);
    return s;
}

std::string fmtg(double v, int significant = 3) {
    if (!std::isfinite(v)) return "–";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*g", significant, v);
    return buffer;
}

std::string csv_number(double v) {
    if (!std::isfinite(v)) return "";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.10g", v);
    return buffer;
}

std::string percent(double fraction, int decimals = 1) {
    return (fraction >= 0 ? "+" : "−") + fmt(std::abs(fraction) * 100.0, decimals) + " %";
}

const char* film_name(InletFilmModel m) { return m == InletFilmModel::paper ? "paper" : "eulerian"; }

class Csv {
public:
    explicit Csv(std::vector<std::string> header) : header_(std::move(header)) {}
    void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
    bool write(const fs::path& path) const {
        std::ofstream out(path, std::ios::binary);
        if (!out) return false;
        auto line = [&](const std::vector<std::string>& cells) {
            for (std::size_t i = 0; i < cells.size(); ++i) {
                if (i) out << ',';
                const bool quote = cells[i].find_first_of(",\"\n") != std::string::npos;
                if (quote) {
                    out << '"';
                    for (char c : cells[i]) out << (c == '"' ? "\"\"" : std::string(1, c));
                    out << '"';
                } else {
                    out << cells[i];
                }
            }
            out << '\n';
        };
        line(header_);
        for (const auto& r : rows_) line(r);
        return static_cast<bool>(out);
    }

private:
    std::vector<std::string> header_;
    std::vector<std::vector<std::string>> rows_;
};

struct Output {
    fs::path dir;        // CSV and SVG files
    fs::path doc;        // the markdown
    std::string link;    // dir relative to the markdown's folder, for image links
    std::vector<std::string> files;
    bool ok = true;

    void csv(const std::string& name, const Csv& table) {
        const fs::path path = dir / name;
        if (!table.write(path)) {
            log("cannot write " + path.string());
            ok = false;
        }
        files.push_back(name);
    }
    void svg(const std::string& name, const Plot& plot) {
        const fs::path path = dir / name;
        if (!tools::write_svg(path, plot)) {
            log("cannot write " + path.string());
            ok = false;
        }
        files.push_back(name);
    }
    std::string image(const std::string& name, const std::string& alt) const {
        return "![" + alt + "](" + link + "/" + name + ")";
    }
};

// ---------------------------------------------------------------------------------------------
// Trends: the direction of a curve, computed from the data, and the verdict against a claim.

struct Segment {
    double x0, x1, y0, y1;
    int sign;  // +1 rising, -1 falling
};

struct Trend {
    bool testable = false;
    std::vector<Segment> segments;
    double y_min = kNaN, y_max = kNaN, x_at_min = kNaN, x_at_max = kNaN;
    std::string direction;  // e.g. "decreasing", "non-monotone: ..."
    std::string verdict;    // "agrees", "disagrees", "partly agrees", "not testable"
    double agreeing_fraction = 0.0;  // of the x range
};

// Monotone runs with hysteresis: a reversal counts once the curve has moved back from its
// running extremum by more than `tolerance` (relative to the largest |y|), so that numerical
// noise does not split a run but a real small reversal does.
Trend trend_of(const std::vector<double>& xs, const std::vector<double>& ys, int claimed_sign,
               const std::function<std::string(double)>& x_text, const std::function<std::string(double)>& y_text,
               double tolerance = 2e-3) {
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
        t.direction = std::string(s.sign > 0 ? "increasing" : "decreasing") + " (" + y_text(s.y0) + " → " + y_text(s.y1) +
                      ", " + percent(s.y1 / s.y0 - 1.0) + ")";
    } else {
        std::string text = "non-monotone: ";
        for (std::size_t k = 0; k < t.segments.size(); ++k) {
            const Segment& s = t.segments[k];
            if (k) text += "; ";
            text += std::string(s.sign > 0 ? "rises" : "falls") + " from " + x_text(s.x0) + " to " + x_text(s.x1) + " (" +
                    y_text(s.y0) + " → " + y_text(s.y1) + ", " + percent(s.y1 / s.y0 - 1.0) + ")";
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
    if (variation < 0.1 && t.verdict != "disagrees") t.direction += " — nearly flat (total variation " + fmt(variation * 100, 1) + " %)";
    return t;
}

}  // namespace

namespace {

// ---------------------------------------------------------------------------------------------
// Figs. 8-12: critical speed against one scenario field

struct SweepFigure {
    int number;
    std::string id;         // fig08
    std::string quantity;   // what is varied, in words
    std::string x_symbol;   // η0
    std::string x_unit;     // mPa·s
    std::string x_column;   // CSV column name
    int x_decimals;
    std::vector<double> xs;
    std::function<void(Scenario&, double)> apply;
    int claimed_sign;        // sign of d v_c / dx the paper claims
    std::string claim_quote; // the paper's words
    std::string claim;       // the claim as a direction of v_c(x)
    std::string setup;       // how the scenario is set

    std::string x_text(double x) const { return fmt(x, x_decimals) + " " + x_unit; }
    std::string x_label() const { return x_symbol + " (" + x_unit + ")"; }
};

std::vector<double> range(double from, double to, double step) {
    std::vector<double> out;
    const int n = static_cast<int>(std::floor((to - from) / step + 1e-9));
    for (int i = 0; i <= n; ++i) out.push_back(from + i * step);
    return out;
}

std::vector<SweepFigure> sweep_figures() {
    std::vector<SweepFigure> figures;
    figures.push_back({8, "fig08", "the emulsion viscosity η0", "η0", "mPa·s", "eta0_mPa_s", 2, range(0.1, 2.0, 0.1),
                       [](Scenario& s, double x) { s.lubricant.viscosity = x * 1e-3; }, -1,
                       "It can be seen that the critical speed of the vibration decreases with increasing viscosity.",
                       "the critical speed falls as η0 rises",
                       "`lubricant.viscosity` = η0; everything else at the defaults (Rq = 2.0 µm, y1 = 1.6 mm, R = 0.15, a = 280 mm)"});
    std::vector<double> exit_thicknesses = range(1.10, 1.55, 0.025);
    exit_thicknesses.push_back(1.36);  // the default (R = 0.15)
    std::sort(exit_thicknesses.begin(), exit_thicknesses.end());
    figures.push_back({9, "fig09", "the exit thickness y2 (entry fixed at 1.6 mm)", "y2", "mm", "y2_mm", 3, exit_thicknesses,
                       [](Scenario& s, double x) { s.strip.reduction = 1.0 - x / 1.6; }, +1,
                       "It can be seen that the vibration critical speed decreases with increasing inlet thickness and "
                       "decreasing outlet thickness, respectively, indicating that self-excited vibration will easily occur.",
                       "the critical speed falls as the exit thickness falls (rises with y2)",
                       "y1 = 1.6 mm, `strip.reduction` = 1 − y2/y1 (R = 0.31 … 0.031)"});
    figures.push_back({10, "fig10", "the entry thickness y1 (exit fixed at 1.36 mm)", "y1", "mm", "y1_mm", 2, range(1.42, 2.0, 0.02),
                       [](Scenario& s, double x) {
                           s.strip.entry_thickness = x * 1e-3;
                           s.strip.reduction = 1.0 - 1.36 / x;
                       },
                       -1,
                       "It can be seen that the vibration critical speed decreases with increasing inlet thickness and "
                       "decreasing outlet thickness, respectively, indicating that self-excited vibration will easily occur.",
                       "the critical speed falls as the entry thickness rises",
                       "`strip.entry_thickness` = y1, `strip.reduction` = 1 − 1.36 mm / y1 (R = 0.042 … 0.32)"});
    figures.push_back({11, "fig11", "the composite roughness Rq", "Rq", "µm", "Rq_um", 2, range(0.5, 6.0, 0.25),
                       [](Scenario& s, double x) {
                           s.roughness.roll_rq = x * 1e-6;
                           s.roughness.strip_rq = 0.0;
                       },
                       +1,
                       "As shown in Fig. 11, the vibration critical speed of the rolling mill vertical system shows an "
                       "increasing trend towards roughness, indicating that the system does not easily experience vibration.",
                       "the critical speed rises with the roughness",
                       "`roughness.roll_rq` = Rq, `roughness.strip_rq` = 0 (composite Rq = Rq)"});
    figures.push_back({12, "fig12", "the work roll radius a", "a", "mm", "radius_mm", 0, range(150.0, 400.0, 10.0),
                       [](Scenario& s, double x) { s.rolls.radius = x * 1e-3; }, +1,
                       "It can be seen that a decrease in work roll radius induces decreased rolling mill vibration critical speed.",
                       "the critical speed rises with the roll radius",
                       "`rolls.radius` = a (the mill masses and stiffnesses are not changed with the radius)"});
    return figures;
}

struct GapModeCrossing {
    std::string status = "none";  // found, stable_in_range, unstable_at_lower_bound, none (no ~100 Hz branch)
    double speed = kNaN;
    double frequency_Hz = kNaN;
    double unstable_below = kNaN;  // when the branch starts unstable and recovers: the speed where it does
};

// The ~100 Hz gap mode (the stack's lowest mode with gap motion) followed over the 0.5 m/s scan
// by core's branch tracking: where its damping ratio crosses zero (linear interpolation between
// scan speeds). This is a secondary figure: the critical speed is the lowest crossing of ANY mode.
GapModeCrossing gap_mode_crossing(const core::CriticalSpeedResult& r) {
    GapModeCrossing out;
    const core::DampingBranch* branch = nullptr;
    for (const auto& b : r.branches) {
        const double f0 = b.frequency_Hz.front();
        if (f0 < 80.0 || f0 > 140.0) continue;
        if (!branch || std::abs(f0 - 105.0) < std::abs(branch->frequency_Hz.front() - 105.0)) branch = &b;
    }
    if (!branch || branch->speed.size() < 2) return out;
    const auto& v = branch->speed;
    const auto& z = branch->damping_ratio;
    std::size_t start = 0;
    if (z.front() <= 0.0) {
        // unstable at the lowest speeds (the eulerian squeeze at low speed): the first speed where
        // the branch is stable, if any, and then its crossing
        while (start < v.size() && z[start] <= 0.0) ++start;
        if (start == v.size()) {
            out.status = "unstable_at_lower_bound";
            out.frequency_Hz = branch->frequency_Hz.front();
            return out;
        }
        out.unstable_below = v[start];
    }
    for (std::size_t i = start; i + 1 < v.size(); ++i) {
        if (z[i] > 0.0 && z[i + 1] <= 0.0) {
            const double w = z[i] / (z[i] - z[i + 1]);
            out.status = "found";
            out.speed = v[i] + w * (v[i + 1] - v[i]);
            out.frequency_Hz = branch->frequency_Hz[i] + w * (branch->frequency_Hz[i + 1] - branch->frequency_Hz[i]);
            return out;
        }
    }
    out.status = "stable_in_range";
    return out;
}

struct SweepPoint {
    double x = 0.0;
    core::CriticalSpeedResult result;
    GapModeCrossing gap_mode;
    ModeDiagnostics diag;  // at the critical speed, for the crossing mode (found points only)
};

struct SweepRun {
    InletFilmModel film = InletFilmModel::paper;
    std::vector<SweepPoint> points;
    Trend trend;      // of the critical speed (censored points at the range ends)
    Trend gap_trend;  // of the gap-mode crossing
    int found = 0;
    double seconds = 0.0;
};

const core::CriticalSpeedOptions kSearch{};  // 1-60 m/s, 0.5 m/s scan, 1e-4 relative

// The value a critical-speed point contributes to the trend: the critical speed, or the end of
// the search range it lies beyond (stable_in_range: >= 60 m/s; unstable_at_lower_bound: <= 1 m/s).
double trend_value(const core::CriticalSpeedResult& r) {
    switch (r.status) {
        case CriticalSpeedStatus::found: return r.critical_speed;
        case CriticalSpeedStatus::stable_in_range: return kSearch.speed_max;
        case CriticalSpeedStatus::unstable_at_lower_bound: return kSearch.speed_min;
        default: return kNaN;
    }
}

std::string speed_text(double v) { return fmt(v, 2) + " m/s"; }

Series named(std::string label) {
    Series s;
    s.label = std::move(label);
    return s;
}

SweepRun run_sweep(const SweepFigure& fig, InletFilmModel film, int threads) {
    const auto t0 = Clock::now();
    SweepRun run;
    run.film = film;
    std::vector<Scenario> scenarios;
    for (double x : fig.xs) {
        Scenario s;
        s.inlet_film = film;
        fig.apply(s, x);
        scenarios.push_back(s);
    }
    std::vector<core::CriticalSpeedResult> results = core::sweep_critical_speed(scenarios, kSearch, threads);
    run.points.resize(fig.xs.size());
    core::parallel_for(static_cast<int>(fig.xs.size()), threads, [&](int i) {
        const auto k = static_cast<std::size_t>(i);
        SweepPoint& p = run.points[k];
        p.x = fig.xs[k];
        p.result = std::move(results[k]);
        p.gap_mode = gap_mode_crossing(p.result);
        if (p.result.status == CriticalSpeedStatus::found) {
            Scenario s = scenarios[k];
            s.rolls.speed = p.result.critical_speed;
            p.diag = tools::diagnose(s, p.result.unstable_mode.frequency_Hz);
        }
    });
    std::vector<double> values, gap_values;
    bool any_found = false;
    for (const SweepPoint& p : run.points) {
        values.push_back(trend_value(p.result));
        if (p.result.status == CriticalSpeedStatus::found) {
            any_found = true;
            ++run.found;
        }
        gap_values.push_back(p.gap_mode.status == "found" ? p.gap_mode.speed
                             : p.gap_mode.status == "stable_in_range" ? kSearch.speed_max
                                                                        : kNaN);
    }
    auto xt = [&](double x) { return fig.x_text(x); };
    if (any_found) {
        run.trend = trend_of(fig.xs, values, fig.claimed_sign, xt, speed_text);
    } else {
        run.trend.direction = "no critical speed at any point";
        run.trend.verdict = "not testable";
    }
    run.gap_trend = trend_of(fig.xs, gap_values, fig.claimed_sign, xt, speed_text);
    run.seconds = seconds_since(t0);
    return run;
}

void write_sweep_csv(Output& out, const SweepFigure& fig, const SweepRun& run) {
    Csv csv({fig.x_column, "status", "critical_speed_m_s", "mode_frequency_Hz", "mode_growth_rate_per_s",
             "gap_mode_status", "gap_mode_crossing_m_s", "gap_mode_frequency_Hz", "gap_mode_unstable_below_m_s", "mean_friction_coefficient",
             "film_ratio_min", "film_ratio_max", "contact_ratio_max", "inlet_film_um", "inlet_angle_mrad",
             "strip_stiffness_GN_m", "gap_mass_t", "growth_constant_tension_per_s", "growth_frozen_film_per_s",
             "loop_damping_MN_s_m", "film_damping_MN_s_m", "dP_dsb_m2", "du1_dg_over_v_per_y1"});
    for (const SweepPoint& p : run.points) {
        const auto& r = p.result;
        const bool found = r.status == CriticalSpeedStatus::found;
        const bool has_mode = found || r.status == CriticalSpeedStatus::unstable_at_lower_bound;
        const ModeDiagnostics& d = p.diag;
        const double v = found ? r.critical_speed : kNaN;
        Scenario s;
        fig.apply(s, p.x);
        csv.add({csv_number(p.x), core::to_string(r.status), csv_number(v),
                 has_mode ? csv_number(r.unstable_mode.frequency_Hz) : "",
                 r.status == CriticalSpeedStatus::unstable_at_lower_bound ? csv_number(r.unstable_mode.eigenvalue.real()) : "",
                 p.gap_mode.status, csv_number(p.gap_mode.speed), csv_number(p.gap_mode.frequency_Hz), csv_number(p.gap_mode.unstable_below),
                 csv_number(d.mean_friction), csv_number(d.film_ratio_min), csv_number(d.film_ratio_max),
                 csv_number(d.contact_ratio_max), csv_number(d.inlet_film * 1e6), csv_number(d.inlet_angle * 1e3),
                 csv_number(d.strip_stiffness * 1e-9), csv_number(d.gap_mass * 1e-3), csv_number(d.growth_constant_tension),
                 csv_number(d.growth_frozen_film), csv_number(d.loop_damping * 1e-6), csv_number(d.film_damping * 1e-6),
                 csv_number(d.dP_dback), csv_number(d.du1_dgap * s.strip.entry_thickness / std::max(v, 1e-300))});
    }
    out.csv(fig.id + "_" + film_name(run.film) + ".csv", csv);
}

void add_status_edges(Plot& plot, const SweepFigure& fig, const SweepRun& run, const std::string& suffix) {
    EdgeMarkers stable{"stable up to 60 m/s (no critical speed in the range)" + suffix, {}, EdgeMarkers::Edge::top,
                       Marker::triangle_up, "#2ca02c"};
    EdgeMarkers lower{"unstable already at 1 m/s (unstable_at_lower_bound)" + suffix, {}, EdgeMarkers::Edge::bottom,
                      Marker::triangle_down, "#d62728"};
    EdgeMarkers none{"no steady state (skidding / contact lost)" + suffix, {}, EdgeMarkers::Edge::bottom, Marker::cross,
                     "#555555"};
    for (std::size_t i = 0; i < fig.xs.size(); ++i) {
        switch (run.points[i].result.status) {
            case CriticalSpeedStatus::stable_in_range: stable.x.push_back(fig.xs[i]); break;
            case CriticalSpeedStatus::unstable_at_lower_bound: lower.x.push_back(fig.xs[i]); break;
            case CriticalSpeedStatus::found: break;
            default: none.x.push_back(fig.xs[i]); break;
        }
    }
    for (auto* e : {&stable, &lower, &none}) {
        if (!e->x.empty()) plot.edges.push_back(*e);
    }
}

Series critical_series(const SweepFigure& fig, const SweepRun& run, const std::string& label) {
    Series s;
    s.label = label;
    for (std::size_t i = 0; i < fig.xs.size(); ++i) {
        s.x.push_back(fig.xs[i]);
        s.y.push_back(run.points[i].result.status == CriticalSpeedStatus::found ? run.points[i].result.critical_speed : kNaN);
    }
    return s;
}

void plot_sweep(Output& out, const SweepFigure& fig, const SweepRun& run, const SweepRun& paper, const SweepRun* fixed_friction,
                double fixed_mu) {
    Plot plot;
    plot.title = "Fig. " + std::to_string(fig.number) + ": critical speed vs " + fig.x_symbol + " — " +
                 film_name(run.film) + " inlet film";
    plot.x_label = fig.x_label();
    plot.y_label = "critical speed (m/s)";
    plot.y_min = 0.0;
    plot.y_max = 62.0;
    const double pad = 0.02 * (fig.xs.back() - fig.xs.front());
    plot.x_min = fig.xs.front() - pad;
    plot.x_max = fig.xs.back() + pad;
    if (run.film == InletFilmModel::paper) {
        Series main = critical_series(fig, run, "critical speed");
        main.color = "#1f77b4";
        plot.series.push_back(main);
        Series high = main;
        high.label = "… where a 400–550 Hz mode crosses first";
        high.line = false;
        high.marker = Marker::diamond;
        high.color = "#ff7f0e";
        high.marker_size = 5.5;
        for (std::size_t i = 0; i < fig.xs.size(); ++i) {
            const auto& r = run.points[i].result;
            if (!(r.status == CriticalSpeedStatus::found && r.unstable_mode.frequency_Hz > 200.0)) high.y[i] = kNaN;
        }
        if (std::any_of(high.y.begin(), high.y.end(), [](double v) { return std::isfinite(v); })) plot.series.push_back(high);
        if (fixed_friction) {
            Series fixed = critical_series(fig, *fixed_friction,
                                           "diagnostic, not the model: friction fixed at μ = " + fmt(fixed_mu, 2) + " (Coulomb)");
            fixed.color = "#888888";
            fixed.dash = "5,4";
            fixed.marker = Marker::none;
            fixed.line_width = 1.5;
            plot.series.push_back(fixed);
        }
        add_status_edges(plot, fig, run, "");
    } else {
        Series reference = critical_series(fig, paper, "critical speed, paper film (reference)");
        reference.color = "#aaaaaa";
        reference.marker = Marker::none;
        reference.line_width = 1.5;
        Series main = critical_series(fig, run, "critical speed (eulerian film)");
        main.color = "#1f77b4";
        Series gap;
        gap.label = "~100 Hz gap mode crosses zero (secondary: not the critical speed)";
        gap.color = "#9467bd";
        gap.dash = "6,4";
        gap.marker = Marker::square;
        gap.marker_size = 3.0;
        for (std::size_t i = 0; i < fig.xs.size(); ++i) {
            gap.x.push_back(fig.xs[i]);
            gap.y.push_back(run.points[i].gap_mode.speed);
        }
        plot.series.push_back(reference);
        if (run.found > 0) plot.series.push_back(main);
        plot.series.push_back(gap);
        add_status_edges(plot, fig, run, " (eulerian)");
    }
    plot.notes.push_back("Search range 1–60 m/s (0.5 m/s scan, refined to 1e-4). Every point of the sweep is shown: with a "
                         "critical speed on the curve, without one as a marker on the edge.");
    out.svg(fig.id + "_" + film_name(run.film) + ".svg", plot);
}

}  // namespace

namespace {

// ---------------------------------------------------------------------------------------------
// Fig. 13: vibration amplitude against rolling speed

struct AmplitudeRun {
    InletFilmModel film = InletFilmModel::paper;
    std::vector<double> speeds;
    std::vector<core::AmplitudeResult> results;
    core::CriticalSpeedResult critical;  // of the default scenario, for the reference line
    Trend trend;                         // of x3 over the runs that completed the window
    double seconds = 0.0;
};

bool completed(const core::AmplitudeResult& a) { return a.end_status == core::DynamicsStatus::ok; }

AmplitudeRun run_amplitude(InletFilmModel film, int threads) {
    const auto t0 = Clock::now();
    AmplitudeRun run;
    run.film = film;
    run.speeds = range(2.0, 24.0, 1.0);
    std::vector<Scenario> scenarios;
    for (double v : run.speeds) {
        Scenario s;
        s.inlet_film = film;
        s.rolls.speed = v;
        scenarios.push_back(s);
    }
    core::AmplitudeOptions options;  // window 2 s, 1 MPa at the least-damped eigenfrequency
    run.results = core::sweep_amplitude(scenarios, options, threads);
    Scenario s;
    s.inlet_film = film;
    core::CriticalSpeedOptions search = kSearch;
    search.threads = threads;
    run.critical = core::critical_speed(s, search);
    std::vector<double> x3;
    for (const auto& a : run.results) x3.push_back(completed(a) ? a.upper_roll * 1e6 : kNaN);
    run.trend = trend_of(run.speeds, x3, +1, speed_text, [](double v) { return fmtg(v, 3) + " µm"; });
    run.seconds = seconds_since(t0);
    return run;
}

void write_amplitude_outputs(Output& out, const AmplitudeRun& run) {
    Csv csv({"speed_m_s", "status", "upper_roll_um", "gap_um", "force_kN", "excitation_frequency_Hz",
             "least_damped_growth_rate_per_s", "window_growth_rate_per_s", "end_time_s", "settled", "end_status", "message"});
    for (const auto& a : run.results) {
        csv.add({csv_number(a.speed), core::to_string(a.status), csv_number(a.upper_roll * 1e6), csv_number(a.gap * 1e6),
                 csv_number(a.force * 1e-3), csv_number(a.excitation_frequency_Hz), csv_number(a.least_damped_growth_rate),
                 csv_number(a.growth_rate), csv_number(a.end_time), a.settled ? "true" : "false",
                 core::to_string(a.end_status), a.message});
    }
    out.csv(std::string("fig13_") + film_name(run.film) + ".csv", csv);

    Plot plot;
    plot.title = std::string("Fig. 13: vibration amplitude vs rolling speed — ") + film_name(run.film) + " inlet film";
    plot.x_label = "roll speed v (m/s)";
    plot.y_label = "amplitude, half peak-to-peak (µm)";
    plot.log_y = true;
    plot.x_min = 0.0;
    plot.x_max = 25.0;
    Series x3 = named("upper work roll x3 (run completed the 2 s window)");
    Series gap = named("roll gap g (run completed the 2 s window)");
    x3.color = "#1f77b4";
    gap.color = "#2ca02c";
    gap.dash = "6,4";
    gap.marker = Marker::square;
    gap.marker_size = 3.0;
    Series unsettled = named("… not settled within the window (decaying / growing)");
    unsettled.line = false;
    unsettled.hollow = true;
    unsettled.color = "#1f77b4";
    unsettled.marker_size = 7.0;
    Series limit = named("x3 when a physical limit ended the run (limit_reached)");
    limit.line = false;
    limit.marker = Marker::triangle_up;
    limit.color = "#d62728";
    limit.marker_size = 5.0;
    Series failure = named("x3 when the run ended with solver_failure");
    failure.line = false;
    failure.marker = Marker::cross;
    failure.color = "#555555";
    for (const auto& a : run.results) {
        const bool done = completed(a);
        x3.x.push_back(a.speed);
        x3.y.push_back(done ? a.upper_roll * 1e6 : kNaN);
        gap.x.push_back(a.speed);
        gap.y.push_back(done ? a.gap * 1e6 : kNaN);
        unsettled.x.push_back(a.speed);
        unsettled.y.push_back(done && !a.settled ? a.upper_roll * 1e6 : kNaN);
        limit.x.push_back(a.speed);
        limit.y.push_back(a.status == core::AmplitudeStatus::limit_reached ? a.upper_roll * 1e6 : kNaN);
        failure.x.push_back(a.speed);
        failure.y.push_back(a.status == core::AmplitudeStatus::solver_failure ? a.upper_roll * 1e6 : kNaN);
    }
    for (const Series* s : {&x3, &gap, &unsettled, &limit, &failure}) {
        if (std::any_of(s->y.begin(), s->y.end(), [](double v) { return std::isfinite(v); })) plot.series.push_back(*s);
    }
    if (run.critical.status == CriticalSpeedStatus::found) {
        plot.vertical_lines.push_back({run.critical.critical_speed, "critical speed " + fmt(run.critical.critical_speed, 1) + " m/s"});
    } else {
        plot.notes.push_back(std::string("No critical speed at the defaults with this film model: ") +
                             core::to_string(run.critical.status) + ".");
    }
    plot.notes.push_back("Excitation: 1 MPa back-tension ripple at the least-damped eigenfrequency of each speed; window 2 s; "
                         "amplitude over the last 10 % of the window (or of the run, when a limit ended it).");
    out.svg(std::string("fig13_") + film_name(run.film) + ".svg", plot);
}

// ---------------------------------------------------------------------------------------------
// Figs. 14-15: distributions over a sinusoidal back-tension cycle

struct PhaseSummary {
    double phase, back_tension, gap, inlet_film, force, peak_pressure, mean_pressure, peak_friction, mean_friction_stress;
    double film_ratio_min, film_ratio_max, contact_ratio_max, neutral_point, contact_length;
};

struct CycleCase {
    double rq_um = 0.0;
    core::TensionCycleResult result;
    core::SpeedStability input_tension;  // linear stability with the back tension as an input (no span state)
    std::vector<PhaseSummary> phases;
};

struct CycleRun {
    InletFilmModel film = InletFilmModel::paper;
    std::vector<CycleCase> cases;  // Rq = 1, 6 µm
    double seconds = 0.0;
};

Scenario cycle_scenario(InletFilmModel film, double rq_um) {
    Scenario s;
    s.inlet_film = film;
    s.roughness.roll_rq = rq_um * 1e-6;
    s.roughness.strip_rq = 0.0;
    s.tensions.back.stress = 18e6;    // 18 +- 9 MPa at 10 Hz (Section 6.2; MODEL.md §6 defaults)
    s.tensions.back.amplitude = 9e6;
    s.tensions.back.frequency = 10.0;
    return s;
}

CycleRun run_cycles(InletFilmModel film, int threads) {
    const auto t0 = Clock::now();
    CycleRun run;
    run.film = film;
    run.cases.resize(2);
    run.cases[0].rq_um = 1.0;
    run.cases[1].rq_um = 6.0;
    core::parallel_for(2, threads, [&](int i) {
        CycleCase& c = run.cases[static_cast<std::size_t>(i)];
        const Scenario s = cycle_scenario(film, c.rq_um);
        c.result = core::tension_cycle(s);  // 2 cycles, T = 0.25, 0.5, 0.75 of the last
        Scenario input = s;
        input.tensions.back.mode = core::TensionMode::constant;
        c.input_tension = core::stability_at(input);
        for (const auto& p : c.result.phases) {
            PhaseSummary m{};
            const auto& b = p.bite;
            m.phase = p.phase;
            m.back_tension = p.back_tension;
            m.gap = p.gap;
            m.inlet_film = p.inlet_film;
            m.force = b.force;
            m.contact_length = b.contact_length;
            m.neutral_point = b.neutral_point;
            m.mean_pressure = b.force / (s.strip.width * b.contact_length);
            m.mean_friction_stress = b.mean_friction_coefficient * m.mean_pressure;
            m.film_ratio_min = INFINITY;
            m.film_ratio_max = -INFINITY;
            for (const auto& q : b.distribution) {
                m.peak_pressure = std::max(m.peak_pressure, q.pressure);
                m.peak_friction = std::max(m.peak_friction, std::abs(q.friction));
                m.film_ratio_min = std::min(m.film_ratio_min, q.film_ratio);
                m.film_ratio_max = std::max(m.film_ratio_max, q.film_ratio);
                m.contact_ratio_max = std::max(m.contact_ratio_max, q.contact_ratio);
            }
            c.phases.push_back(m);
        }
    });
    run.seconds = seconds_since(t0);
    return run;
}

std::string rq_label(double rq) { return "Rq = " + fmt(rq, 0) + " µm"; }

void write_cycle_outputs(Output& out, const CycleRun& run) {
    const std::string film = film_name(run.film);
    Csv pressure({"Rq_um", "T", "back_tension_MPa", "x_mm", "pressure_MPa", "film_ratio", "contact_ratio", "regime"});
    Csv friction({"Rq_um", "T", "back_tension_MPa", "x_mm", "friction_MPa", "strip_speed_m_s", "film_ratio", "contact_ratio", "regime"});
    Csv summary({"Rq_um", "T", "status", "back_tension_MPa", "gap_um", "inlet_film_um", "force_MN", "peak_pressure_MPa",
                 "mean_pressure_MPa", "peak_friction_MPa", "mean_friction_MPa", "film_ratio_min", "film_ratio_max",
                 "contact_ratio_max", "neutral_point_mm", "contact_length_mm"});
    for (const CycleCase& c : run.cases) {
        for (std::size_t k = 0; k < c.result.phases.size(); ++k) {
            const auto& p = c.result.phases[k];
            for (const auto& q : p.bite.distribution) {
                pressure.add({csv_number(c.rq_um), csv_number(p.phase), csv_number(p.back_tension * 1e-6), csv_number(q.x * 1e3),
                              csv_number(q.pressure * 1e-6), csv_number(q.film_ratio), csv_number(q.contact_ratio),
                              core::to_string(q.regime)});
                friction.add({csv_number(c.rq_um), csv_number(p.phase), csv_number(p.back_tension * 1e-6), csv_number(q.x * 1e3),
                              csv_number(q.friction * 1e-6), csv_number(q.strip_speed), csv_number(q.film_ratio),
                              csv_number(q.contact_ratio), core::to_string(q.regime)});
            }
            const PhaseSummary& m = c.phases[k];
            summary.add({csv_number(c.rq_um), csv_number(m.phase), core::to_string(c.result.status), csv_number(m.back_tension * 1e-6),
                         csv_number(m.gap * 1e6), csv_number(m.inlet_film * 1e6), csv_number(m.force * 1e-6),
                         csv_number(m.peak_pressure * 1e-6), csv_number(m.mean_pressure * 1e-6), csv_number(m.peak_friction * 1e-6),
                         csv_number(m.mean_friction_stress * 1e-6), csv_number(m.film_ratio_min), csv_number(m.film_ratio_max),
                         csv_number(m.contact_ratio_max), csv_number(m.neutral_point * 1e3), csv_number(m.contact_length * 1e3)});
        }
        if (c.result.phases.empty()) {
            summary.add({csv_number(c.rq_um), "", core::to_string(c.result.status), "", "", "", "", "", "", "", "", "", "", "", "", ""});
        }
    }
    out.csv("fig14_" + film + ".csv", pressure);
    out.csv("fig15_" + film + ".csv", friction);
    out.csv("fig14-15_summary_" + film + ".csv", summary);

    for (int figure : {14, 15}) {
        Plot plot;
        plot.title = "Fig. " + std::to_string(figure) + ": " + (figure == 14 ? "compressive stress" : "friction stress") +
                     " over a back-tension cycle — " + film + " inlet film";
        plot.x_label = "x (mm), from the exit (0) to the entry";
        plot.y_label = figure == 14 ? "compressive stress p (MPa)" : "friction stress τ on the strip (MPa)";
        plot.x_min = 0.0;
        for (const CycleCase& c : run.cases) {
            for (const auto& p : c.result.phases) {
                Series s;
                s.label = rq_label(c.rq_um) + ", T = " + fmt(p.phase, 2) + " (s_b = " + fmt(p.back_tension * 1e-6, 1) + " MPa)";
                s.color = c.rq_um < 3.0 ? "#1f77b4" : "#d62728";
                s.dash = p.phase < 0.3 ? "" : p.phase < 0.6 ? "9,5" : "2,3";
                s.marker = Marker::none;
                for (const auto& q : p.bite.distribution) {
                    s.x.push_back(q.x * 1e3);
                    s.y.push_back((figure == 14 ? q.pressure : q.friction) * 1e-6);
                }
                plot.series.push_back(s);
            }
            if (c.result.phases.empty()) {
                plot.notes.push_back(rq_label(c.rq_um) + ": no distributions — the coupled run ended before the first phase: " +
                                     core::to_string(c.result.status) + " (\"" + c.result.message + "\"). With the back tension " +
                                     "as an input this case has an unstable mode at " + fmt(c.input_tension.least_damped.frequency_Hz, 0) +
                                     " Hz growing at " + fmt(c.input_tension.max_real_part, 0) + " 1/s.");
            }
        }
        plot.notes.push_back("Back tension 18 ± 9 MPa at 10 Hz, sinusoid (T = 0.25: highest, 0.5: mean, 0.75: lowest); v = 19 m/s, "
                             "R = 0.15; distributions at the phases of the second cycle of the coupled run.");
        out.svg("fig" + std::to_string(figure) + "_" + film + ".svg", plot);
    }
}

// ---------------------------------------------------------------------------------------------
// Mechanism studies

struct Variant {
    std::string label;
    std::function<void(Scenario&)> apply;
};

struct VariantResult {
    std::string label;
    core::CriticalSpeedResult result;
};

std::vector<VariantResult> run_variants(const std::vector<Variant>& variants, int threads) {
    std::vector<Scenario> scenarios;
    for (const Variant& v : variants) {
        Scenario s;
        v.apply(s);
        scenarios.push_back(s);
    }
    auto results = core::sweep_critical_speed(scenarios, kSearch, threads);
    std::vector<VariantResult> out;
    for (std::size_t i = 0; i < variants.size(); ++i) out.push_back({variants[i].label, std::move(results[i])});
    return out;
}

std::string critical_text(const core::CriticalSpeedResult& r) {
    switch (r.status) {
        case CriticalSpeedStatus::found:
            return fmt(r.critical_speed, 2) + " m/s (" + fmt(r.unstable_mode.frequency_Hz, 0) + " Hz)";
        case CriticalSpeedStatus::stable_in_range: return "stable to 60 m/s";
        case CriticalSpeedStatus::unstable_at_lower_bound:
            return "unstable at 1 m/s (" + fmt(r.unstable_mode.frequency_Hz, 0) + " Hz, " +
                   fmt(r.unstable_mode.eigenvalue.real(), 0) + " 1/s)";
        default: return core::to_string(r.status);
    }
}

struct SpeedDiagnostics {
    InletFilmModel film;
    std::vector<ModeDiagnostics> rows;
};

// The coupled model at the defaults over speed, following the mode nearest `frequency_Hz`
// (<= 0: the least-damped one).
SpeedDiagnostics diagnose_over_speed(InletFilmModel film, const std::vector<double>& speeds, double frequency_Hz,
                                     const std::function<void(Scenario&)>& apply, int threads) {
    SpeedDiagnostics out{film, std::vector<ModeDiagnostics>(speeds.size())};
    core::parallel_for(static_cast<int>(speeds.size()), threads, [&](int i) {
        Scenario s;
        s.inlet_film = film;
        if (apply) apply(s);
        s.rolls.speed = speeds[static_cast<std::size_t>(i)];
        out.rows[static_cast<std::size_t>(i)] = tools::diagnose(s, frequency_Hz);
    });
    return out;
}

struct StabilityMap {
    std::vector<std::string> labels;
    std::vector<core::CriticalSpeedResult> results;
};

StabilityMap stability_map(int threads) {
    StabilityMap map;
    std::vector<Scenario> scenarios;
    for (InletFilmModel film : kFilmModels) {
        for (bool span : {true, false}) {
            Scenario s;
            s.inlet_film = film;
            if (!span) s.tensions.back.mode = core::TensionMode::constant;
            scenarios.push_back(s);
            map.labels.push_back(std::string(film_name(film)) + " film, " + (span ? "entry-span tension (default)" : "constant back tension"));
        }
    }
    map.results = core::sweep_critical_speed(scenarios, kSearch, threads);
    return map;
}

void write_stability_map(Output& out, const StabilityMap& map) {
    std::vector<std::string> header{"speed_m_s"};
    for (const char* film : {"paper", "eulerian"}) {
        for (const char* tension : {"span", "constant"}) {
            header.push_back(std::string("max_real_part_") + film + "_" + tension + "_per_s");
            header.push_back(std::string("least_damped_frequency_") + film + "_" + tension + "_Hz");
        }
    }
    Csv csv(header);
    const auto& scan0 = map.results[0].scan;
    for (std::size_t i = 0; i < scan0.size(); ++i) {
        std::vector<std::string> row{csv_number(scan0[i].speed)};
        for (const auto& r : map.results) {
            const bool ok = i < r.scan.size() && r.scan[i].status == core::DynamicsStatus::ok;
            row.push_back(ok ? csv_number(r.scan[i].max_real_part) : "");
            row.push_back(ok ? csv_number(r.scan[i].least_damped.frequency_Hz) : "");
        }
        csv.add(row);
    }
    out.csv("stability_defaults.csv", csv);

    Plot plot;
    plot.title = "Largest growth rate over speed at the defaults — both film models";
    plot.x_label = "roll speed v (m/s)";
    plot.y_label = "max Re λ (1/s); > 0 is unstable";
    plot.y_min = -40.0;
    plot.y_max = 200.0;
    plot.x_min = 0.0;
    plot.x_max = 60.0;
    const char* colors[] = {"#1f77b4", "#17becf", "#d62728", "#ff7f0e"};
    for (std::size_t k = 0; k < map.results.size(); ++k) {
        Series s;
        s.label = map.labels[k];
        s.color = colors[k];
        s.marker = Marker::none;
        s.dash = k % 2 ? "7,4" : "";
        for (const auto& p : map.results[k].scan) {
            s.x.push_back(p.speed);
            s.y.push_back(p.status == core::DynamicsStatus::ok ? p.max_real_part : kNaN);
        }
        plot.series.push_back(s);
    }
    Series zero = named("stability limit (Re λ = 0)");
    zero.x = {0.0, 60.0};
    zero.y = {0.0, 0.0};
    zero.color = "#333333";
    zero.line_width = 1.0;
    zero.marker = Marker::none;
    plot.series.push_back(zero);
    plot.notes.push_back("The eulerian curves leave the plot at low speed (up to " +
                         fmt(std::max(map.results[2].scan.front().max_real_part, map.results[3].scan.front().max_real_part), 0) +
                         " 1/s at 1 m/s); the CSV has every value. Scan step 0.5 m/s.");
    out.svg("stability_defaults.svg", plot);
}

}  // namespace

namespace {

// ---------------------------------------------------------------------------------------------
// The markdown

struct Results {
    std::vector<SweepFigure> figures;
    std::vector<std::array<SweepRun, 2>> sweeps;     // per figure: paper, eulerian
    std::map<int, SweepRun> coulomb;                 // Figs. 9, 10, 12 with a fixed friction coefficient
    double coulomb_mu = 0.07;
    std::array<AmplitudeRun, 2> amplitude;
    std::array<CycleRun, 2> cycles;
    SpeedDiagnostics defaults_gap_mode;              // paper film, ~104 Hz mode over speed
    std::vector<VariantResult> variants;
    std::vector<double> coulomb_mus;
    std::vector<VariantResult> coulomb_variants;
    std::vector<ModeDiagnostics> coulomb_diag;       // at 15 m/s, ~104 Hz mode
    SpeedDiagnostics high_mode_eulerian, high_mode_paper;  // the eulerian's least-damped mode, both films
    StabilityMap map;
    double seconds = 0.0;
    int threads = 1;
};

std::string status_cell(const core::CriticalSpeedResult& r) {
    switch (r.status) {
        case CriticalSpeedStatus::found: return "found";
        case CriticalSpeedStatus::stable_in_range: return "stable to 60 m/s";
        case CriticalSpeedStatus::unstable_at_lower_bound: return "unstable at 1 m/s";
        default: return core::to_string(r.status);
    }
}

std::string regime_text(double ht_min, double ht_max) {
    if (!std::isfinite(ht_min)) return "–";
    const char* regime = ht_min > 3.0 ? "full film" : ht_max < 0.5 ? "boundary" : "mixed";
    return fmt(ht_min, 2) + "–" + fmt(ht_max, 2) + " (" + regime + ")";
}

std::string verdict_cell(const Trend& t) {
    if (t.verdict == "agrees") return "**agrees**";
    if (t.verdict == "disagrees") return "**disagrees**";
    if (t.verdict == "partly agrees") return "**partly** (" + fmt(t.agreeing_fraction * 100, 0) + " % of the range)";
    return t.verdict;
}

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

std::string eulerian_summary(const SweepRun& run) {
    int lower = 0;
    double f_lo = INFINITY, f_hi = -INFINITY, g_lo = INFINITY, g_hi = -INFINITY;
    for (const auto& p : run.points) {
        if (p.result.status != CriticalSpeedStatus::unstable_at_lower_bound) continue;
        ++lower;
        f_lo = std::min(f_lo, p.result.unstable_mode.frequency_Hz);
        f_hi = std::max(f_hi, p.result.unstable_mode.frequency_Hz);
        g_lo = std::min(g_lo, p.result.unstable_mode.eigenvalue.real());
        g_hi = std::max(g_hi, p.result.unstable_mode.eigenvalue.real());
    }
    std::string text;
    if (run.found > 0) text += std::to_string(run.found) + " of " + std::to_string(run.points.size()) + " points have a critical speed; ";
    if (lower > 0) {
        text += std::to_string(lower) + " of " + std::to_string(run.points.size()) +
                " points are unstable already at the lower bound 1 m/s (mode " + fmt(f_lo, 0) + "–" + fmt(f_hi, 0) +
                " Hz, growth rate " + fmt(g_lo, 0) + "–" + fmt(g_hi, 0) + " 1/s at 1 m/s)";
    }
    return text;
}

void md_sweep_table(std::ostringstream& md, const SweepFigure& fig, const Results& R, std::size_t index) {
    const SweepRun& paper = R.sweeps[index][0];
    const SweepRun& euler = R.sweeps[index][1];
    const auto coulomb = R.coulomb.find(fig.number);
    const bool with_coulomb = coulomb != R.coulomb.end();
    md << "| " << fig.x_label() << " | paper film: status | v_c (m/s) | mode (Hz) | μ at v_c | H_t at v_c | A max | "
       << "k4 (GN/m) | gap mass (t) | Re λ, tension held (1/s) |";
    if (with_coulomb) md << " v_c, Coulomb μ = " << fmt(R.coulomb_mu, 2) << " (m/s) |";
    md << " eulerian film: status | mode at 1 m/s: Hz, 1/s | ~100 Hz mode crosses (m/s) |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|" << (with_coulomb ? "---|" : "") << "---|---|---|\n";
    for (std::size_t i = 0; i < fig.xs.size(); ++i) {
        const SweepPoint& p = paper.points[i];
        const SweepPoint& e = euler.points[i];
        const ModeDiagnostics& d = p.diag;
        const bool found = p.result.status == CriticalSpeedStatus::found;
        md << "| " << fmt(fig.xs[i], fig.x_decimals) << " | " << status_cell(p.result) << " | "
           << (found ? fmt(p.result.critical_speed, 2) : "–") << " | "
           << (found || p.result.status == CriticalSpeedStatus::unstable_at_lower_bound ? fmt(p.result.unstable_mode.frequency_Hz, 0) : "–")
           << " | " << fmt(d.mean_friction, 3) << " | " << regime_text(d.film_ratio_min, d.film_ratio_max) << " | "
           << fmt(d.contact_ratio_max, 3) << " | " << fmt(d.strip_stiffness * 1e-9, 1) << " | " << fmt(d.gap_mass * 1e-3, 0)
           << " | " << fmt(d.growth_constant_tension, 1) << " |";
        if (with_coulomb) {
            const auto& c = coulomb->second.points[i].result;
            md << " " << (c.status == CriticalSpeedStatus::found ? fmt(c.critical_speed, 2) : status_cell(c)) << " |";
        }
        md << " " << status_cell(e.result) << " | ";
        if (e.result.status == CriticalSpeedStatus::unstable_at_lower_bound) {
            md << fmt(e.result.unstable_mode.frequency_Hz, 0) << ", " << fmt(e.result.unstable_mode.eigenvalue.real(), 0);
        } else if (e.result.status == CriticalSpeedStatus::found) {
            md << "v_c = " << fmt(e.result.critical_speed, 2) << " m/s";
        } else {
            md << "–";
        }
        md << " | "
           << (e.gap_mode.status == "found"
                   ? fmt(e.gap_mode.speed, 1) +
                         (std::isfinite(e.gap_mode.unstable_below) ? " (also unstable below " + fmt(e.gap_mode.unstable_below, 1) + ")" : "")
               : e.gap_mode.status == "stable_in_range" ? "> 60"
               : e.gap_mode.status == "unstable_at_lower_bound" ? "< 1"
                                                              : "–")
           << " |\n";
    }
    md << "\n";
}

void md_diag_row(std::ostringstream& md, const ModeDiagnostics& d, bool with_loop = true) {
    md << "| " << fmt(d.speed, 2) << " | " << fmt(d.frequency_Hz, 1) << " | " << fmt(d.mean_friction, 3) << " | "
       << regime_text(d.film_ratio_min, d.film_ratio_max) << " | " << fmt(d.contact_ratio_max, 3) << " | "
       << fmt(d.inlet_film * 1e6, 2) << " | " << fmt(d.strip_stiffness * 1e-9, 1) << " | " << fmt(d.gap_mass * 1e-3, 0) << " | "
       << fmt(d.growth_rate, 2) << " | " << fmt(d.growth_constant_tension, 2) << " | " << fmt(d.growth_frozen_film, 2) << " | ";
    if (with_loop) md << fmt(d.loop_damping * 1e-6, 2) << " | ";
    md << fmt(d.film_damping * 1e-6, 2) << " |\n";
}

}  // namespace

namespace {

std::string md_figure_mechanism(const SweepFigure& fig, const Results& R, std::size_t index) {
    const SweepRun& paper = R.sweeps[index][0];
    std::ostringstream md;
    const Scenario defaults;
    const SweepPoint* def = nullptr;  // the point at the default scenario, if the sweep has it
    for (const auto& p : paper.points) {
        Scenario s;
        fig.apply(s, p.x);
        const Scenario& d = defaults;
        if (std::abs(s.strip.entry_thickness - d.strip.entry_thickness) < 1e-9 && std::abs(s.strip.reduction - d.strip.reduction) < 1e-9 &&
            std::abs(s.rolls.radius - d.rolls.radius) < 1e-9 && std::abs(s.lubricant.viscosity - d.lubricant.viscosity) < 1e-12 &&
            std::abs(std::hypot(s.roughness.roll_rq, s.roughness.strip_rq) - std::hypot(d.roughness.roll_rq, d.roughness.strip_rq)) < 1e-9) {
            def = &p;
        }
    }
    auto point_text = [&](const SweepPoint& p) {
        const ModeDiagnostics& d = p.diag;
        std::string text = fig.x_symbol + " = " + fig.x_text(p.x) + ": v_c = " + fmt(p.result.critical_speed, 2) + " m/s";
        if (p.result.unstable_mode.frequency_Hz > 200.0) text += " (" + fmt(p.result.unstable_mode.frequency_Hz, 0) + " Hz mode)";
        return text + ", θ = " + fmt(d.inlet_angle * 1e3, 1) + " mrad, h00 = " + fmt(d.inlet_film * 1e6, 2) + " µm, H_t = " +
               fmt(d.film_ratio_min, 2) + "–" + fmt(d.film_ratio_max, 2) + ", A ≤ " + fmt(d.contact_ratio_max, 3) + ", μ = " +
               fmt(d.mean_friction, 3) + ", k4 = " + fmt(d.strip_stiffness * 1e-9, 1) + " GN/m, gap mass " +
               fmt(d.gap_mass * 1e-3, 0) + " t, |∂P/∂s_b| = " + fmt(std::abs(d.dP_dback) * 1e3, 1) + "·10⁻³ m²";
    };
    const Trend& t = paper.trend;
    const auto coulomb = R.coulomb.find(fig.number);
    std::string coulomb_text;
    if (coulomb != R.coulomb.end()) {
        coulomb_text = "With the friction coefficient held fixed (verification friction law `coulomb`, μ = " + fmt(R.coulomb_mu, 2) +
                       "; a diagnostic variant, not the model) the critical speed is " + coulomb->second.trend.direction +
                       ", i.e. it **" + (coulomb->second.trend.verdict == "agrees" ? "follows" : "does not follow") +
                       "** the paper's direction.";
    }
    // found points in x order; the first and last, the lowest, and the first/last crossing through the ~100 Hz mode
    std::vector<const SweepPoint*> found;
    for (const auto& p : paper.points) {
        if (p.result.status == CriticalSpeedStatus::found) found.push_back(&p);
    }
    if (found.empty()) return "";
    const SweepPoint* first = found.front();
    const SweepPoint* last = found.back();
    const SweepPoint* lowest = *std::min_element(found.begin(), found.end(), [](const SweepPoint* a, const SweepPoint* b) {
        return a->result.critical_speed < b->result.critical_speed;
    });
    const SweepPoint* first_gap = nullptr;
    for (const SweepPoint* p : found) {
        if (p->result.unstable_mode.frequency_Hz < 200.0) {
            first_gap = p;
            break;
        }
    }
    // the band around the defaults within +-2 % of the default critical speed
    std::string band;
    if (def && def->result.status == CriticalSpeedStatus::found) {
        const double v0 = def->result.critical_speed;
        std::size_t k = static_cast<std::size_t>(def - paper.points.data());
        std::size_t lo = k, hi = k;
        auto within = [&](std::size_t i) {
            return paper.points[i].result.status == CriticalSpeedStatus::found && std::abs(paper.points[i].result.critical_speed / v0 - 1.0) <= 0.02;
        };
        while (lo > 0 && within(lo - 1)) --lo;
        while (hi + 1 < paper.points.size() && within(hi + 1)) ++hi;
        band = fig.x_symbol + " = " + fmt(paper.points[lo].x, fig.x_decimals) + "–" + fig.x_text(paper.points[hi].x);
    }

    switch (fig.number) {
        case 8: {
            md << "**Why (paper film).** The viscosity acts only through the inlet film (MODEL.md §4: with the printed γ the "
                  "fluid shear in the bite is capped at λ_L·p everywhere). A thicker film means fewer asperity contacts and a "
                  "lower friction coefficient, and a lower friction coefficient lowers the critical speed (see *What sets the "
                  "critical speed*): ";
            if (first_gap) md << point_text(*first_gap) << "; ";
            md << point_text(*last) << ". That is the paper's chain (film ↑ → contact ratio ↓ → stability ↓), but the "
                  "destabilising element is the entry-span tension loop; friction decides how much of the gap mode it can "
                  "reach. Once the bite is in full film at the critical speed (A → 0, μ → λ_L = 0.05) the curve runs into a "
                  "floor of ≈ " << fmt(last->result.critical_speed, 1)
               << " m/s, the full-film critical speed: beyond that, η0 changes nothing the dynamics depend on.";
            if (first->result.unstable_mode.frequency_Hz > 200.0) {
                md << " At " << fig.x_text(first->x) << " the friction is so high (μ = " << fmt(first->diag.mean_friction, 3)
                   << ") that the ~104 Hz mode stays stable beyond " << fmt(first->result.critical_speed, 0) << " m/s and the "
                   << fmt(first->result.unstable_mode.frequency_Hz, 0)
                   << " Hz mode (the two work rolls moving against each other, gap mass " << fmt(first->diag.gap_mass * 1e-3, 0)
                   << " t) crosses first.";
            }
            md << "\n\n";
            break;
        }
        case 9:
        case 10: {
            // Fig. 9: small y2 = large reduction (the first point); Fig. 10: large y1 = large reduction (the last)
            const SweepPoint* large = fig.number == 9 ? first : last;
            const SweepPoint* small = fig.number == 9 ? last : first;
            if (t.verdict == "agrees") {
                md << "**Why (paper film).** " << coulomb_text << "\n\n";
                break;
            }
            md << "**Mechanism of the disagreement (paper film).** The curve has a minimum of " << speed_text(t.y_min) << " at "
               << fig.x_text(t.x_at_min) << ". On its " << (fig.number == 9 ? "thin-exit" : "thick-entry")
               << " side — the larger reductions — the critical speed rises again, against the paper. Two effects of the "
                  "reduction compete:\n\n"
               << "1. *Geometry (the paper's mechanism).* A larger reduction lengthens the contact (x_w = √(a·Δy)), so the back "
                  "tension moves the force more (|∂P/∂s_b| grows with x_w) and the entry-span tension loop pushes harder. "
               << coulomb_text << " The paper's reasoning is therefore present in the model.\n"
               << "2. *Lubrication (what the paper's explanation leaves out).* A larger reduction also steepens the inlet "
                  "(θ = √(Δy/a)), and the Wilson–Walowit film h00 ∝ η0·ū1/θ gets thinner; the film ratio H_t falls, more "
                  "asperities touch (A rises) and the friction coefficient rises. Higher friction makes the strip stiffer "
                  "(k4 = −∂P/∂y2), which moves the ~104 Hz mode towards the heavy backup rolls (larger modal gap mass), so the "
                  "same loop force reaches less of the mode and a higher speed is needed (see *What sets the critical speed*).\n\n";
            md << "Numbers at the critical speed — largest reduction: " << point_text(*large) << "; at the minimum: "
               << point_text(*lowest);
            if (def) md << "; at the defaults: " << point_text(*def);
            md << "; smallest reduction: " << point_text(*small) << ".\n\n";
            md << "At large reductions the friction effect outweighs the geometric one. At small reductions the bite is in "
                  "full film already (A = 0, μ = λ_L): friction cannot fall any further, the geometric effect is all that is "
                  "left, and the model agrees with the paper, steeply — until, at the smallest reductions, the "
               << fmt(small->result.unstable_mode.frequency_Hz, 0) << " Hz work-roll mode crosses first or no mode crosses "
                  "below 60 m/s. In between, around the defaults, the two effects almost cancel";
            if (!band.empty()) md << ": the critical speed stays within ±2 % of the default's for " << band;
            md << ".\n\n";
            break;
        }
        case 11: {
            md << "**Why (paper film).** Roughness acts only through the film ratio H_t = h/Rq: a rougher surface at the same "
                  "film has more asperity contact (A), a higher friction coefficient, a stiffer strip and a higher critical "
                  "speed (the friction lever of *What sets the critical speed*): "
               << point_text(*first) << "; " << point_text(*last)
               << ". This is the paper's explanation (\"both the contact area ration … and the shear stress … will increase, "
                  "and an improved stability … will be obtained\"). For the smoothest surfaces the bite is in full film at "
                  "the critical speed and the curve flattens towards the full-film floor (≈ "
               << fmt(first->result.critical_speed, 2) << " m/s, the same floor as in Fig. 8).\n\n";
            break;
        }
        case 12: {
            md << "**Mechanism (paper film).** The model's curve is " << t.direction << ". The radius has the same two "
                  "competing effects as the reduction (Figs. 9–10). A larger radius lengthens the contact (x_w = √(a·Δy)), "
                  "which strengthens the back-tension lever. " << coulomb_text << " But a larger radius also flattens the inlet "
                  "(θ = √(Δy/a)), thickens the film (h00 ∝ 1/θ ∝ √a), reduces asperity contact and friction, and lower "
                  "friction lowers the critical speed. In the mixed-lubrication model the two nearly cancel: "
               << point_text(*first) << "; " << point_text(*last)
               << ". (The mill's masses and stiffnesses are kept at the 2800 mm mill's values for every radius; the paper "
                  "does not say whether it changed them.)\n\n";
            break;
        }
        default: break;
    }
    return md.str();
}

}  // namespace

namespace {

std::string short_direction(const Trend& t) {
    if (!t.testable) return t.direction;
    std::string s;
    if (t.segments.empty()) return "flat";
    if (t.segments.size() == 1) {
        s = t.segments.front().sign > 0 ? "increasing" : "decreasing";
    } else {
        s = "non-monotone";
    }
    const double variation = (t.y_max - t.y_min) / std::max(std::abs(t.y_max), 1e-300);
    if (variation < 0.1) s += ", nearly flat (" + fmt(variation * 100, 1) + " %)";
    return s;
}

std::string extremum_text(const Trend& t, const SweepFigure& fig) {
    if (t.segments.size() < 2) return "";
    const bool interior_min = t.segments.front().sign < 0;
    return interior_min ? "minimum " + speed_text(t.y_min) + " at " + fig.x_text(t.x_at_min)
                        : "maximum " + speed_text(t.y_max) + " at " + fig.x_text(t.x_at_max);
}

struct CycleChecks {
    bool available = false;
    double dP_high = kNaN, dP_mid = kNaN, dP_low = kNaN;          // force(Rq 6) - force(Rq 1) at T = 0.25, 0.5, 0.75
    double mean_p_ratio_low = kNaN, peak_p_ratio_low = kNaN;      // Rq 6 / Rq 1 at T = 0.75
    bool rough_higher_everywhere = true;
    bool tension_lowers_pressure = true;                          // force(T=.25) < force(T=.75) for both Rq
    double friction_ratio_min = INFINITY, friction_ratio_max = -INFINITY;  // mean |tau|, Rq 6 / Rq 1
    double tension_effect_on_friction = 0.0;                      // largest |tau(T=.25) - tau(T=.75)| / tau
    double roughness_effect_on_friction = INFINITY;               // smallest |tau6 - tau1| / tau1
};

CycleChecks check_cycles(const CycleRun& run) {
    CycleChecks c;
    if (run.cases.size() != 2 || run.cases[0].phases.size() != 3 || run.cases[1].phases.size() != 3) return c;
    c.available = true;
    const auto& a = run.cases[0].phases;  // Rq 1
    const auto& b = run.cases[1].phases;  // Rq 6
    c.dP_high = b[0].force - a[0].force;
    c.dP_mid = b[1].force - a[1].force;
    c.dP_low = b[2].force - a[2].force;
    c.mean_p_ratio_low = b[2].mean_pressure / a[2].mean_pressure;
    c.peak_p_ratio_low = b[2].peak_pressure / a[2].peak_pressure;
    for (int k = 0; k < 3; ++k) {
        if (!(b[k].force > a[k].force && b[k].mean_pressure > a[k].mean_pressure)) c.rough_higher_everywhere = false;
        const double ratio = b[k].mean_friction_stress / a[k].mean_friction_stress;
        c.friction_ratio_min = std::min(c.friction_ratio_min, ratio);
        c.friction_ratio_max = std::max(c.friction_ratio_max, ratio);
        c.roughness_effect_on_friction = std::min(c.roughness_effect_on_friction, ratio - 1.0);
    }
    for (const auto* p : {&a, &b}) {
        if (!((*p)[0].force < (*p)[2].force)) c.tension_lowers_pressure = false;
        c.tension_effect_on_friction = std::max(c.tension_effect_on_friction,
                                                std::abs((*p)[0].mean_friction_stress - (*p)[2].mean_friction_stress) / (*p)[1].mean_friction_stress);
    }
    return c;
}

std::string fig14_verdict(const CycleChecks& c) {
    if (!c.available) return "not testable";
    const bool sensitivity_falls = c.dP_high > 1.1 * c.dP_low;
    const bool coincide = std::abs(c.mean_p_ratio_low - 1.0) < 0.05;
    if (c.rough_higher_everywhere && sensitivity_falls && coincide) return "agrees";
    if (!c.rough_higher_everywhere) return "disagrees";
    return "partly agrees";
}

std::string fig15_verdict(const CycleChecks& c) {
    if (!c.available) return "not testable";
    const bool rises = c.friction_ratio_min > 1.0;
    const bool strong = c.roughness_effect_on_friction > c.tension_effect_on_friction;
    return rises && strong ? "agrees" : rises || strong ? "partly agrees" : "disagrees";
}

std::string bold(const std::string& verdict) { return "**" + verdict + "**"; }

void md_cycle_table(std::ostringstream& md, const CycleRun& run) {
    md << "| Rq (µm) | T | s_b (MPa) | gap (µm) | h0 (µm) | H_t | A max | force (MN) | mean p (MPa) | peak p (MPa) | "
          "mean abs(τ) (MPa) | peak abs(τ) (MPa) | x_n (mm) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const CycleCase& c : run.cases) {
        if (c.phases.empty()) {
            md << "| " << fmt(c.rq_um, 0) << " | no result: " << core::to_string(c.result.status)
               << " | – | – | – | – | – | – | – | – | – | – | – |\n";
            continue;
        }
        for (const PhaseSummary& m : c.phases) {
            md << "| " << fmt(c.rq_um, 0) << " | " << fmt(m.phase, 2) << " | " << fmt(m.back_tension * 1e-6, 1) << " | "
               << fmt(m.gap * 1e6, 2) << " | " << fmt(m.inlet_film * 1e6, 3) << " | " << fmt(m.film_ratio_min, 2) << "–"
               << fmt(m.film_ratio_max, 2) << " | " << fmt(m.contact_ratio_max, 3) << " | " << fmt(m.force * 1e-6, 3) << " | "
               << fmt(m.mean_pressure * 1e-6, 1) << " | " << fmt(m.peak_pressure * 1e-6, 1) << " | "
               << fmt(m.mean_friction_stress * 1e-6, 1) << " | " << fmt(m.peak_friction * 1e-6, 1) << " | "
               << fmt(m.neutral_point * 1e3, 2) << " |\n";
        }
    }
    md << "\n";
}

std::string write_markdown(const Results& R, const Output& out) {
    std::ostringstream md;
    const Scenario defaults;
    const SweepRun* default_paper = nullptr;
    const core::CriticalSpeedResult& vc_default = R.variants.front().result;

    md << "# Paper reproduction: Wang et al. (2013), Figs. 8–15\n\n";
    md << "*Generated by `scripts/reproduce-paper.sh` (the `reproduce_paper` tool, `tools/reproduce_paper.cpp`); do not "
          "edit by hand — rerun the script. Runtime of this run: "
       << fmt(R.seconds, 1) << " s on " << R.threads << " threads.*\n\n";
    md << "This document runs rollgap's model — the paper (Wang, Jiang, Zhao & Fang, *Tribology International* 67 (2013) "
          "174–181) as specified by MODEL.md — over the parameter ranges of the paper's Figs. 8–15, and compares the "
          "**direction** of each curve with what the paper says about it. The paper's figures are images without "
          "published data, so magnitudes cannot be compared; the paper's claims (Section 6 and the Conclusions) are "
          "statements of direction, and those are what is checked. Nothing was tuned towards the paper: every scenario is "
          "MODEL.md §8's default with the one field the figure varies. Where the model disagrees, the mechanism was "
          "traced in the linearised coupled model (`core::linearise`): which coupling destabilises the mode, how much "
          "damping it has to overcome, and what state the lubrication is in.\n\n";
    md << "Every figure is run with both inlet film models of MODEL.md §2: `paper` (eq. 11 as printed, the default) and "
          "`eulerian` (the frame-corrected squeeze term). What was run:\n\n"
       << "- Figs. 8–12: `core::sweep_critical_speed` (search 1–60 m/s, 0.5 m/s scan, refined to 1e-4) over η0 (0.1–2.0 "
          "mPa·s), exit thickness y2 (1.10–1.55 mm at y1 = 1.6 mm), entry thickness y1 (1.42–2.00 mm at y2 = 1.36 mm), "
          "composite roughness Rq (0.5–6 µm as roll roughness, strip smooth) and roll radius a (150–400 mm). Every point "
          "keeps its status: `found`, `stable_in_range` (no critical speed up to 60 m/s), `unstable_at_lower_bound` "
          "(unstable already at 1 m/s) or `no_steady_state`; points without a critical speed are drawn as markers on the "
          "plot's edge, never dropped.\n"
       << "- Fig. 13: `core::sweep_amplitude` at 2–24 m/s (1 MPa back-tension ripple at the least-damped eigenfrequency, "
          "2 s window).\n"
       << "- Figs. 14–15: `core::tension_cycle` at the defaults (v = 19 m/s, R = 0.15) with back tension 18 ± 9 MPa at "
          "10 Hz, Rq = 1 and 6 µm, distributions at T = 0.25, 0.5, 0.75 of the second cycle.\n"
       << "- Diagnostics (labelled as such; none of them is a model change): the Jacobian at selected points with single "
          "states removed, equivalent dampers of each coupling path, and variants of the assumptions MODEL.md added to "
          "the paper.\n\n";
    md << "Command: `bash scripts/reproduce-paper.sh` (builds the `reproduce_paper` target in `build/` and runs "
          "`build/tools/reproduce_paper --out docs/paper-reproduction --doc docs/paper-reproduction.md`). The CSV and "
          "SVG files are in `"
       << out.link << "/`. The results are deterministic (independent of the thread count); only the runtime changes.\n\n";

    // ----- Summary
    md << "## Summary\n\n";
    md << "| Fig. | the paper says | paper film: the model gives | verdict | eulerian film: the model gives | verdict |\n"
          "|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < R.figures.size(); ++i) {
        const SweepFigure& fig = R.figures[i];
        const SweepRun& p = R.sweeps[i][0];
        const SweepRun& e = R.sweeps[i][1];
        std::string pm = short_direction(p.trend);
        const std::string ext = extremum_text(p.trend, fig);
        if (!ext.empty()) pm += "; " + ext;
        std::string em = e.found == 0 ? "no critical speed: unstable at 1 m/s at every point" : short_direction(e.trend);
        em += " (the ~100 Hz gap mode's own crossing: " + short_direction(e.gap_trend) + ")";
        md << "| " << fig.number << " | " << fig.claim << " | " << pm << " | " << verdict_cell(p.trend) << " | " << em
           << " | not testable (gap mode: " << e.gap_trend.verdict << ") |\n";
    }
    {
        const AmplitudeRun& p = R.amplitude[0];
        const AmplitudeRun& e = R.amplitude[1];
        int e_completed = 0;
        for (const auto& a : e.results) e_completed += completed(a) ? 1 : 0;
        md << "| 13 | the amplitude rises with speed | " << short_direction(p.trend)
           << " below the critical speed; above it every run ends at a physical limit | " << verdict_cell(p.trend) << " | "
           << (e_completed == 0 ? "every run ends at a limit within milliseconds (film-squeeze mode)" : short_direction(e.trend))
           << " | " << (e_completed == 0 ? "not testable" : verdict_cell(e.trend)) << " |\n";
        const CycleChecks cp = check_cycles(R.cycles[0]);
        const CycleChecks ce = check_cycles(R.cycles[1]);
        auto missing = [](const CycleRun& run) {
            std::string text;
            for (const CycleCase& k : run.cases) {
                if (k.phases.empty()) text += (text.empty() ? "" : ", ") + rq_label(k.rq_um) + ": no result (" + core::to_string(k.result.status) + ")";
            }
            return text + "; nothing to compare";
        };
        auto f14 = [&](const CycleChecks& c, const CycleRun& run) {
            if (!c.available) return missing(run);
            return std::string("compressive stress ") + (c.rough_higher_everywhere ? "higher" : "not higher") +
                   " for Rq = 6 µm at every T; the roughness effect on the force hardly changes over the cycle (" +
                   fmt(c.dP_high * 1e-6, 2) + " → " + fmt(c.dP_low * 1e-6, 2) + " MN from T = 0.25 to 0.75); the curves do " +
                   (std::abs(c.mean_p_ratio_low - 1.0) < 0.05 ? "" : "**not** ") + "coincide at T = 0.75 (mean p " +
                   percent(c.mean_p_ratio_low - 1.0, 0) + ")";
        };
        auto f15 = [&](const CycleChecks& c, const CycleRun& run) {
            if (!c.available) return missing(run);
            return "mean friction stress ×" + fmt(c.friction_ratio_min, 1) + "–" + fmt(c.friction_ratio_max, 1) +
                   " for Rq = 6 vs 1 µm; back tension changes it by ≤ " + fmt(c.tension_effect_on_friction * 100, 1) + " %";
        };
        md << "| 14 | compressive stress rises with roughness, strongly at high back tension; the curves coincide at T = 0.75 | "
           << f14(cp, R.cycles[0]) << " | " << bold(fig14_verdict(cp)) << " | " << f14(ce, R.cycles[1]) << " | " << bold(fig14_verdict(ce)) << " |\n";
        md << "| 15 | friction stress rises with roughness and is more sensitive to it than to back tension | " << f15(cp, R.cycles[0])
           << " | " << bold(fig15_verdict(cp)) << " | " << f15(ce, R.cycles[1]) << " | " << bold(fig15_verdict(ce)) << " |\n\n";
    }
    md << "\"Partly\" gives the share of the swept range over which the model moves in the paper's direction. The "
          "eulerian film model has no critical speed anywhere (see [Paper vs eulerian film](#paper-vs-eulerian-inlet-film)); "
          "its secondary curve is where the ~100 Hz gap mode alone crosses zero.\n\n";

    // ----- What sets the critical speed
    md << "## What sets the critical speed (≈ 20 m/s at the defaults)\n\n";
    {
        const auto& rows = R.defaults_gap_mode.rows;
        md << "At the defaults (paper film) the critical speed is " << critical_text(vc_default)
           << ". The mode that crosses is the stand's lowest mode with gap motion: the upper and lower halves of the stand "
              "moving against each other on the strip (the 64 Hz mode below it has no gap motion and never couples to the "
              "bite). The table follows that mode over speed.\n\n";
        md << "| v (m/s) | mode (Hz) | μ | H_t | A max | h00 (µm) | k4 (GN/m) | gap mass (t) | Re λ (1/s) | Re λ, tension held "
              "(1/s) | Re λ, film held (1/s) | tension-loop damper (MN·s/m) | film-path damper (MN·s/m) |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (const auto& d : rows) md_diag_row(md, d);
        md << "\n*Re λ, tension held*: the same Jacobian with the span-tension state removed (back tension constant); "
              "*film held*: with the film state removed (h0 = h00). *Dampers*: the force each path produces across the gap "
              "for a harmonic gap motion at the mode's frequency, as an equivalent damper (positive dissipates). *Gap mass*: "
              "1/(φ3 − φ4)² of the mass-normalised natural mode, i.e. the mass a damper across the gap has to move.\n\n";
        const ModeDiagnostics* at_vc = nullptr;
        for (const auto& d : rows) {
            if (std::abs(d.speed - vc_default.critical_speed) < 1e-9) at_vc = &d;
        }
        double held_lo = INFINITY, held_hi = -INFINITY;
        for (const auto& d : rows) {
            held_lo = std::min(held_lo, d.growth_constant_tension);
            held_hi = std::max(held_hi, d.growth_constant_tension);
        }
        md << "Reading the table:\n\n";
        md << "1. **The destabilising element is the entry-span tension loop** (MODEL.md §6 [extension], the \"negative damping "
              "generated by the inlet tension\" of the paper's Section 6.1). With the back tension held constant the mode's "
              "growth rate is " << fmt(held_lo, 1) << " to " << fmt(held_hi, 1)
           << " 1/s at every speed — essentially the structure's own damping (Rayleigh ζ = 0.04 at 100 Hz: ζω ≈ 26 1/s). "
              "The bite's direct rate term ∂P/∂ġ is small";
        if (at_vc) {
            md << " (" << fmt(at_vc->direct_damping * 1e-6, 2) << " MN·s/m at v_c)";
        }
        md << ", and the film path damps a little (the *film held* column is higher than Re λ; it fades as A → 0).\n";
        if (at_vc) {
            const double EL = defaults.strip.youngs_modulus / defaults.tensions.back.span_length;
            const double w = 2.0 * std::numbers::pi * at_vc->frequency_Hz;
            const double estimate = std::abs(at_vc->dP_dback) * EL * at_vc->du1_dgap / (w * w);
            md << "2. **How the loop destabilises.** A gap that opens by g lets more strip through: the entry speed changes by "
                  "∂u1/∂g = " << fmt(at_vc->du1_dgap * defaults.strip.entry_thickness / at_vc->speed, 2)
               << "·v/y1 (mass flow). The entry span integrates the speed difference, ṡ_b = (E/L_b)(u1 − u1_ref) with "
                  "E/L_b = " << fmt(EL * 1e-9, 0) << " GPa/m, so the back tension lags the gap by about a quarter period "
                  "(the span's own relaxation, " << fmt(at_vc->tension_pole, 0) << " 1/s, is slow against ω = "
               << fmt(w, 0) << " 1/s). A higher back tension lowers the force (∂P/∂s_b = " << fmtg(at_vc->dP_dback, 3)
               << " m², about " << fmt(std::abs(at_vc->dP_dback) / (defaults.strip.width * at_vc->contact_length), 2)
               << "·w·x_w). A force that lags the gap by 90° and pushes it further open is a negative damper: "
                  "|∂P/∂s_b|·(E/L_b)·(∂u1/∂g)/ω² ≈ " << fmt(estimate * 1e-6, 1) << " MN·s/m at v_c (the full calculation, "
                  "with the span relaxation and the film coupling: " << fmt(at_vc->loop_damping * 1e-6, 1)
               << " MN·s/m). Because ∂u1/∂g ∝ v, **the loop's negative damping grows in proportion to the speed**; the "
                  "critical speed is where it has eaten the structure's damping. The mode's growth rate moves by about "
                  "−c/(2·m_gap) = " << fmt(-at_vc->loop_damping / (2.0 * at_vc->gap_mass), 0) << " 1/s for the loop's c "
               << "(the eigenvalue calculation: " << fmt(at_vc->growth_rate - at_vc->growth_constant_tension, 1) << " 1/s).\n";
        }
        md << "3. **The number 20 m/s comes from MODEL.md's assumptions, not from the paper.** The balance is between the "
              "structural damping (Rayleigh, an [extension]) and the loop gain E/L_b (the entry-span length L_b = 5 m is an "
              "[extension] as well):\n\n";
        md << "| variant (diagnostic, not the model) | critical speed |\n|---|---|\n";
        for (const auto& v : R.variants) md << "| " << v.label << " | " << critical_text(v.result) << " |\n";
        md << "\n4. **Friction sets the loop's leverage.** With a fixed friction coefficient (verification law `coulomb`) "
              "the critical speed rises steeply with μ; the table gives the ~104 Hz mode at 15 m/s for each μ:\n\n";
        md << "| Coulomb μ | critical speed | k4 at 15 m/s (GN/m) | gap mass (t) | tension-loop damper (MN·s/m) | "
              "Re λ (1/s) | Re λ, tension held (1/s) |\n|---|---|---|---|---|---|---|\n";
        for (std::size_t k = 0; k < R.coulomb_mus.size(); ++k) {
            const ModeDiagnostics& d = R.coulomb_diag[k];
            md << "| " << fmt(R.coulomb_mus[k], 2) << " | " << critical_text(R.coulomb_variants[k].result) << " | "
               << fmt(d.strip_stiffness * 1e-9, 1) << " | " << fmt(d.gap_mass * 1e-3, 0) << " | " << fmt(d.loop_damping * 1e-6, 2)
               << " | " << fmt(d.growth_rate, 1) << " | " << fmt(d.growth_constant_tension, 1) << " |\n";
        }
        if (!R.coulomb_diag.empty()) {
            const auto& lo = R.coulomb_diag.front();
            const auto& hi = R.coulomb_diag.back();
            md << "\nThe loop's damper barely changes with friction (" << fmt(lo.loop_damping * 1e-6, 1) << " → "
               << fmt(hi.loop_damping * 1e-6, 1) << " MN·s/m), but the strip stiffness does (" << fmt(lo.strip_stiffness * 1e-9, 1)
               << " → " << fmt(hi.strip_stiffness * 1e-9, 1) << " GN/m): with more friction the force depends more on the exit "
                  "thickness (a steeper friction hill). A stiffer strip couples the work rolls more rigidly, the ~104 Hz mode "
                  "becomes a motion of the heavy backup rolls and crossheads with less relative work-roll motion — the gap mass "
               << "rises from " << fmt(lo.gap_mass * 1e-3, 0) << " to " << fmt(hi.gap_mass * 1e-3, 0)
               << " t — and the same damper across the gap moves the mode less.\n\n";
        }
        md << "5. **Consequence for Figs. 8–12.** In the mixed-lubrication model the friction coefficient at the critical "
              "speed is set by the lubrication regime: film thickness h00 ∝ η0·ū1/θ against roughness Rq. Everything that "
              "thickens the film relative to the roughness (higher η0, smoother surfaces, a flatter inlet from a smaller "
              "reduction or a larger radius, and the speed itself) lowers the friction and the critical speed, down to the "
              "full-film floor where A = 0 and μ = λ_L = 0.05 (the Coulomb μ = 0.05 row). At the defaults the bite at "
              "20 m/s is in the mixed regime close to full film (H_t ≈ 1.7–1.8, A ≤ 0.05, μ ≈ 0.07); around this point "
              "the geometric effect of reduction and radius and their effect on the film nearly cancel, which is why "
              "so many scenarios end up near 20 m/s.\n\n";
    }

    // ----- Figs. 8-12
    for (std::size_t i = 0; i < R.figures.size(); ++i) {
        const SweepFigure& fig = R.figures[i];
        const SweepRun& p = R.sweeps[i][0];
        const SweepRun& e = R.sweeps[i][1];
        if (fig.number == 8) default_paper = &p;
        md << "## Fig. " << fig.number << ": critical speed vs " << fig.quantity << "\n\n";
        md << "**The paper:** \"" << fig.claim_quote << "\" — i.e. " << fig.claim << ".\n\n";
        md << "**Setup:** " << fig.setup << ".\n\n";
        md << out.image(fig.id + "_paper.svg", "Fig. " + std::to_string(fig.number) + ", paper film") << "\n"
           << out.image(fig.id + "_eulerian.svg", "Fig. " + std::to_string(fig.number) + ", eulerian film") << "\n\n";
        md << "**Paper film — the model:** " << p.trend.direction << ". **Verdict: " << p.trend.verdict << "**";
        if (p.trend.verdict == "partly agrees") md << " (the paper's direction over " << fmt(p.trend.agreeing_fraction * 100, 0) << " % of the range)";
        md << ".";
        int not_found = 0;
        for (const auto& q : p.points) not_found += q.result.status == CriticalSpeedStatus::found ? 0 : 1;
        if (not_found > 0) md << " Points without a critical speed (counted at the end of the search range for the direction): " << not_found << ".";
        md << "\n\n";
        md << "**Eulerian film — the model:** " << eulerian_summary(e) << ". No critical speed to compare: **not testable**. "
           << "The ~100 Hz gap mode on its own crosses zero at a speed that is " << e.gap_trend.direction << " ("
           << e.gap_trend.verdict << " with the paper's direction).\n\n";
        md << md_figure_mechanism(fig, R, i);
        md << "<details><summary>Table: the curve and the state at the critical speed (CSV: `" << fig.id << "_paper.csv`, `"
           << fig.id << "_eulerian.csv`)</summary>\n\n";
        md_sweep_table(md, fig, R, i);
        md << "</details>\n\n";
    }
    (void)default_paper;

    // ----- Fig. 13
    {
        const AmplitudeRun& p = R.amplitude[0];
        const AmplitudeRun& e = R.amplitude[1];
        md << "## Fig. 13: vibration amplitude vs rolling speed\n\n";
        md << "**The paper:** \"It can be seen that the vibration amplitude increases with increasing rolling speed.\"\n\n";
        md << "**Setup:** defaults, v = 2–24 m/s; `core::vibration_amplitude` excites the bite with a 1 MPa back-tension "
              "ripple at the least-damped eigenfrequency of each speed and integrates the nonlinear coupled model for 2 s "
              "(MODEL.md §7.4). Amplitude: half peak-to-peak over the last 10 % of the window, or of the run when a "
              "physical limit ended it.\n\n";
        md << out.image("fig13_paper.svg", "Fig. 13, paper film") << "\n" << out.image("fig13_eulerian.svg", "Fig. 13, eulerian film") << "\n\n";
        md << "**Paper film — the model:** over the runs that complete the window the upper work roll amplitude is "
           << p.trend.direction << ". **Verdict: " << p.trend.verdict << "**. ";
        int limit = 0;
        double first_limit = kNaN;
        for (const auto& a : p.results) {
            if (a.status == core::AmplitudeStatus::limit_reached) {
                ++limit;
                if (!std::isfinite(first_limit)) first_limit = a.speed;
            }
        }
        if (limit > 0) {
            md << "From " << fmt(first_limit, 0) << " m/s on (" << limit << " speeds) the run ends at a physical limit — ";
            for (const auto& a : p.results) {
                if (a.status == core::AmplitudeStatus::limit_reached) {
                    md << "\"" << a.message << "\"";
                    break;
                }
            }
            md << " — after " << [&] {
                double lo = INFINITY, hi = 0;
                for (const auto& a : p.results) {
                    if (a.status == core::AmplitudeStatus::limit_reached) {
                        lo = std::min(lo, a.end_time);
                        hi = std::max(hi, a.end_time);
                    }
                }
                return fmt(lo, 2) + "–" + fmt(hi, 2) + " s";
            }() << ", with the gap swinging by ±" << [&] {
                double lo = INFINITY, hi = 0;
                for (const auto& a : p.results) {
                    if (a.status == core::AmplitudeStatus::limit_reached) {
                        lo = std::min(lo, a.gap * 1e6);
                        hi = std::max(hi, a.gap * 1e6);
                    }
                }
                return fmt(lo, 0) + "–" + fmt(hi, 0) + " µm";
            }() << ". The model has no limit cycle below the physical limits: above the critical speed the vibration grows "
                   "until the entry strip goes slack. ";
        }
        md << "The rise below the critical speed is resonance: the excitation sits on the least-damped mode, and the "
              "~104 Hz gap mode's damping falls towards zero as the speed approaches v_c ("
           << critical_text(p.critical) << "), so the forced response grows roughly as 1/|Re λ|";
        {
            const core::AmplitudeResult* a10 = nullptr;
            const core::AmplitudeResult* a18 = nullptr;
            for (const auto& a : p.results) {
                if (std::abs(a.speed - 10.0) < 1e-9) a10 = &a;
                if (std::abs(a.speed - 18.0) < 1e-9) a18 = &a;
            }
            if (a10 && a18 && completed(*a10) && completed(*a18)) {
                md << " (10 m/s: Re λ = " << fmt(a10->least_damped_growth_rate, 1) << " 1/s, x3 = " << fmtg(a10->upper_roll * 1e6, 3)
                   << " µm; 18 m/s: Re λ = " << fmt(a18->least_damped_growth_rate, 1) << " 1/s, x3 = " << fmtg(a18->upper_roll * 1e6, 3)
                   << " µm)";
            }
        }
        md << ". Even a linearly stable point just below v_c can reach the slack-strip limit: the 1 MPa ripple on a mode "
              "with ζ ≈ 0.0003 is amplified enormously.\n\n";
        // the low-speed step
        {
            const core::AmplitudeResult* before = nullptr;
            const core::AmplitudeResult* after = nullptr;
            for (std::size_t k = 0; k + 1 < p.results.size(); ++k) {
                if (p.results[k].excitation_frequency_Hz < 80.0 && p.results[k + 1].excitation_frequency_Hz > 80.0) {
                    before = &p.results[k];
                    after = &p.results[k + 1];
                }
            }
            if (before && after) {
                md << "*Note on the step between " << fmt(before->speed, 0) << " and " << fmt(after->speed, 0)
                   << " m/s:* below " << fmt(after->speed, 0) << " m/s the least-damped eigenvalue is the "
                   << fmt(before->excitation_frequency_Hz, 1)
                   << " Hz mode, which has no gap motion (upper and lower halves in phase) and cannot be excited through the "
                      "bite; the excitation then drives the gap mode off resonance and the amplitude is small ("
                   << fmtg(before->upper_roll * 1e6, 3) << " µm). At " << fmt(after->speed, 0) << " m/s the ~"
                   << fmt(after->excitation_frequency_Hz, 0) << " Hz gap mode becomes the least damped, the excitation moves "
                      "onto it and the amplitude jumps to " << fmtg(after->upper_roll * 1e6, 3)
                   << " µm. The step is a property of MODEL.md §7.4's choice of excitation frequency, not of the mill; it "
                      "does not change the direction.\n\n";
            }
        }
        int e_completed = 0;
        double end_lo = INFINITY, end_hi = 0;
        std::map<std::string, int> statuses;
        for (const auto& a : e.results) {
            e_completed += completed(a) ? 1 : 0;
            end_lo = std::min(end_lo, a.end_time);
            end_hi = std::max(end_hi, a.end_time);
            statuses[std::string(core::to_string(a.status)) + " (\"" + a.message + "\")"]++;
        }
        md << "**Eulerian film — the model:** ";
        if (e_completed == 0) {
            md << "no run completes the window; every run ends after " << fmt(end_lo * 1e3, 0) << "–" << fmt(end_hi * 1e3, 0)
               << " ms: ";
            bool comma = false;
            for (const auto& [s, n] : statuses) {
                md << (comma ? ", " : "") << n << "× " << s;
                comma = true;
            }
            md << ". The film-squeeze mode (" << fmt(e.results.front().excitation_frequency_Hz, 0) << "–"
               << fmt(e.results.back().excitation_frequency_Hz, 0) << " Hz, growth rate "
               << fmt(e.results.back().least_damped_growth_rate, 0) << "–" << fmt(e.results.front().least_damped_growth_rate, 0)
               << " 1/s) is unstable at every speed. **Not testable.** The `solver_failure` runs are film collapses: the "
                  "squeeze term drives h0 to zero and the right-hand side refuses a non-positive film (see [Notes for the "
                  "core](#notes-for-the-core)).\n\n";
        } else {
            md << p.trend.direction << ".\n\n";
        }
        md << "<details><summary>Table (CSV: `fig13_paper.csv`, `fig13_eulerian.csv`)</summary>\n\n";
        md << "| v (m/s) | paper: status | x3 (µm) | gap (µm) | excitation (Hz) | Re λ (1/s) | run ended (s) | eulerian: status | "
              "x3 (µm) | excitation (Hz) | Re λ (1/s) | run ended (s) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (std::size_t k = 0; k < p.results.size(); ++k) {
            const auto& a = p.results[k];
            const auto& b = e.results[k];
            md << "| " << fmt(a.speed, 0) << " | " << core::to_string(a.status) << " | " << fmtg(a.upper_roll * 1e6, 3) << " | "
               << fmtg(a.gap * 1e6, 3) << " | " << fmt(a.excitation_frequency_Hz, 1) << " | " << fmt(a.least_damped_growth_rate, 2)
               << " | " << fmt(a.end_time, 3) << " | " << core::to_string(b.status) << " | " << fmtg(b.upper_roll * 1e6, 3) << " | "
               << fmt(b.excitation_frequency_Hz, 1) << " | " << fmt(b.least_damped_growth_rate, 1) << " | " << fmt(b.end_time, 4)
               << " |\n";
        }
        md << "\n</details>\n\n";
    }

    // ----- Figs. 14-15
    {
        const CycleRun& p = R.cycles[0];
        const CycleRun& e = R.cycles[1];
        const CycleChecks c = check_cycles(p);
        const CycleChecks ce = check_cycles(e);
        md << "## Figs. 14–15: compressive and friction stress over a back-tension cycle\n\n";
        md << "**The paper (Fig. 14):** \"Fig. 14 shows that, when the rough surfaces contact, compressive stress is also "
              "increased with the increase of surface roughness. Under the condition of higher back tension (T = 0.25), "
              "when Rq = 6 μm, the compressive stress value in the deformation area is far greater than the value of the "
              "compressive stress in the deformation area when Rq = 1 μm. [...] However, when the back tension is reduced, "
              "the compressive stress on the surface roughness becomes less sensitive. When T = 0.75, back tension reaches "
              "a minimum, where the compressive stress distribution curve coincides at Rq = 1 μm and Rq = 6 μm.\"\n\n";
        md << "**The paper (Fig. 15):** \"Fig. 15 indicates that the surface roughness has a significant effect on the "
              "distribution of frictional stress in the deformation area. When having larger back tension, the "
              "compressive stress in the roll gap is lower (Fig. 14), but the frictional stress distribution is very "
              "sensitive to the surface roughness at this time. The influence of the surface roughness on the frictional "
              "stress is more pronounced than that of the back tension.\" Conclusion (2) adds: \"with an increase of "
              "surface roughness, the frictional stress in the roll gap also increases.\"\n\n";
        md << "**Setup:** defaults (v = 19 m/s, R = 0.15), roll roughness Rq = 1 or 6 µm with a smooth strip, back tension "
              "18 ± 9 MPa at 10 Hz as a prescribed sinusoid (`core::tension_cycle`, 2 cycles, the phases of the second).\n\n";
        md << out.image("fig14_paper.svg", "Fig. 14, paper film") << "\n" << out.image("fig15_paper.svg", "Fig. 15, paper film") << "\n"
           << out.image("fig14_eulerian.svg", "Fig. 14, eulerian film") << "\n" << out.image("fig15_eulerian.svg", "Fig. 15, eulerian film")
           << "\n\n";
        md << "**Paper film — the model:**\n\n";
        md_cycle_table(md, p);
        if (c.available) {
            const auto& a = p.cases[0].phases;
            const auto& b = p.cases[1].phases;
            md << "- *Compressive stress rises with roughness:* " << (c.rough_higher_everywhere ? "yes, at every phase" : "no")
               << " — the force is " << fmt(b[1].force * 1e-6, 2) << " MN for Rq = 6 µm against " << fmt(a[1].force * 1e-6, 2)
               << " MN for 1 µm at T = 0.5, the peak pressure " << fmt(b[1].peak_pressure * 1e-6, 0) << " against "
               << fmt(a[1].peak_pressure * 1e-6, 0) << " MPa. **Agrees.**\n";
            md << "- *Higher back tension, lower compressive stress:* "
               << (c.tension_lowers_pressure ? "yes for both roughnesses" : "no") << " (force at T = 0.25 vs 0.75: "
               << fmt(a[0].force * 1e-6, 3) << " vs " << fmt(a[2].force * 1e-6, 3) << " MN for 1 µm, " << fmt(b[0].force * 1e-6, 3)
               << " vs " << fmt(b[2].force * 1e-6, 3) << " MN for 6 µm). **" << (c.tension_lowers_pressure ? "Agrees" : "Disagrees")
               << ".**\n";
            const bool falls = c.dP_high > 1.1 * c.dP_low;
            md << "- *The roughness effect is strong at high back tension and fades at low back tension:* the force difference "
                  "Rq 6 − Rq 1 is " << fmt(c.dP_high * 1e-6, 3) << " MN at T = 0.25, " << fmt(c.dP_mid * 1e-6, 3) << " MN at "
                  "T = 0.5 and " << fmt(c.dP_low * 1e-6, 3) << " MN at T = 0.75 (" << percent(c.dP_low / c.dP_high - 1.0)
               << "). The sign of the trend is the paper's, but the effect is " << (falls ? "large." : "negligible.")
               << " **" << (falls ? "Agrees" : "Disagrees") << ".**\n";
            const bool coincide = std::abs(c.mean_p_ratio_low - 1.0) < 0.05;
            md << "- *The curves coincide at T = 0.75:* the mean pressure for Rq = 6 µm is " << percent(c.mean_p_ratio_low - 1.0, 0)
               << " and the peak " << percent(c.peak_p_ratio_low - 1.0, 0) << " of the Rq = 1 µm values at T = 0.75. **"
               << (coincide ? "Agrees" : "Disagrees") << ".**\n";
            md << "- *Friction stress (Fig. 15):* the mean friction stress is ×" << fmt(c.friction_ratio_min, 1) << "–"
               << fmt(c.friction_ratio_max, 1) << " higher for Rq = 6 µm at every phase; over the cycle it changes by at most "
               << fmt(c.tension_effect_on_friction * 100, 1) << " %. Roughness dominates back tension. **"
               << (fig15_verdict(c) == "agrees" ? "Agrees" : "Partly agrees") << ".**\n\n";
            md << "**Verdict: Fig. 14 " << fig14_verdict(c) << ", Fig. 15 " << fig15_verdict(c) << ".**\n\n";
            if (!coincide || !falls) {
                const double gamma = defaults.lubricant.pressure_viscosity;
                const double sigma = defaults.strip.flow_stress;
                const double hi_sb = a[0].back_tension, lo_sb = a[2].back_tension;
                md << "**Mechanism of the disagreement.** In this model back tension cannot switch the roughness effect off, "
                      "because nothing it changes reaches the lubrication regime:\n\n";
                md << "1. *The inlet film does not see the back tension.* The Wilson–Walowit film divides by "
                      "1 − exp(−γ(σ − s_b)); with the printed γ = 1.7 MPa⁻¹ the exponent is γ(σ − s_b) = "
                   << fmt(gamma * (sigma - hi_sb), 0) << " at s_b = " << fmt(hi_sb * 1e-6, 0) << " MPa and "
                   << fmt(gamma * (sigma - lo_sb), 0) << " at " << fmt(lo_sb * 1e-6, 0) << " MPa, so the factor is 1 − "
                   << fmtg(std::exp(-gamma * (sigma - lo_sb)), 2) << " at both. The film over the cycle changes only "
                   << "through the entry speed (h0 = " << fmt(a[0].inlet_film * 1e6, 3) << " → " << fmt(a[2].inlet_film * 1e6, 3)
                   << " µm for Rq = 1 µm), and the film ratio and contact ratio stay where the roughness put them: H_t = "
                   << fmt(a[0].film_ratio_min, 2) << "–" << fmt(a[0].film_ratio_max, 2) << ", A = " << fmt(a[0].contact_ratio_max, 3)
                   << " for Rq = 1 µm (full film: the asperities do not touch at 19 m/s) and H_t = " << fmt(b[0].film_ratio_min, 2)
                   << "–" << fmt(b[0].film_ratio_max, 2) << ", A ≤ " << fmt(b[0].contact_ratio_max, 3)
                   << " for Rq = 6 µm, at every phase.\n";
                md << "2. *Back tension enters the bite only as a boundary value.* p(x_w) = σ − s_b moves by ±9 MPa (±2.5 % of "
                      "σ) and the neutral point shifts a little (x_n = " << fmt(a[0].neutral_point * 1e3, 2) << " → "
                   << fmt(a[2].neutral_point * 1e3, 2) << " mm for Rq = 1 µm); the force changes by "
                   << percent(a[2].force / a[0].force - 1.0) << " (Rq = 1) and " << percent(b[2].force / b[0].force - 1.0)
                   << " (Rq = 6) between T = 0.25 and 0.75. The roughness, by contrast, puts "
                   << fmt(b[0].contact_ratio_max * 100, 0) << " % of the area into sticking asperity contact (τ_a = σ/2 = 190 "
                      "MPa) and raises the friction hill, the force by " << percent(b[1].force / a[1].force - 1.0)
                   << ". A ±9 MPa change at the boundary cannot undo that.\n";
                md << "3. *The cycle is quasi-static for the mill.* 10 Hz is far below the ~104 Hz gap mode; the gap follows "
                      "the force change (" << fmt(a[0].gap * 1e6, 1) << " to " << fmt(a[2].gap * 1e6, 1)
                   << " µm for Rq = 1 µm), which does not alter the regime either.\n\n";
                md << "For the paper's curves to coincide at low back tension, the lubrication regime would have to depend on "
                      "the back tension — e.g. an inlet film that thickens strongly as s_b falls, which needs "
                      "γ(σ − s_b) of order 1 (an oil-typical γ ≈ 0.017 MPa⁻¹ gives ≈ 6; MODEL.md §8 explains why the printed "
                      "value is kept). The model is not tuned towards this.\n\n";
            }
        }
        md << "**Eulerian film — the model:**\n\n";
        md_cycle_table(md, e);
        for (const CycleCase& k : e.cases) {
            if (!k.phases.empty()) continue;
            md << "For Rq = " << fmt(k.rq_um, 0) << " µm the coupled run has no distributions: " << core::to_string(k.result.status)
               << " (\"" << k.result.message << "\"). With the back tension as an input (as here) the eulerian model at this "
                  "roughness has a mode at " << fmt(k.input_tension.least_damped.frequency_Hz, 0) << " Hz growing at "
               << fmt(k.input_tension.max_real_part, 0) << " 1/s (doubling every " << fmt(std::log(2.0) / k.input_tension.max_real_part * 1e3, 1)
               << " ms): the bite is in the mixed regime (A > 0), the film squeeze drives the work-roll mode unstable and the "
                  "film collapses long before the first phase at t = 0.125 s. (The paper film at the same point: largest Re λ = "
               << fmt(p.cases[&k - &e.cases[0]].input_tension.max_real_part, 1) << " 1/s, stable.)\n\n";
        }
        for (const CycleCase& k : e.cases) {
            if (k.phases.empty()) continue;
            const CycleCase& q = p.cases[static_cast<std::size_t>(&k - &e.cases[0])];
            if (q.phases.size() != k.phases.size()) continue;
            double diff = 0.0;
            for (std::size_t j = 0; j < k.phases.size(); ++j) diff = std::max(diff, std::abs(k.phases[j].force / q.phases[j].force - 1.0));
            md << "For Rq = " << fmt(k.rq_um, 0) << " µm the eulerian distributions match the paper film's (force within "
               << fmtg(diff * 100, 2) << " %): the bite is in full film (A = " << fmt(k.phases[0].contact_ratio_max, 3)
               << "), so the force does not depend on the film thickness and the squeeze term has nothing to act on.\n\n";
        }
        md << "**Verdict (eulerian): Fig. 14 " << fig14_verdict(ce) << ", Fig. 15 " << fig15_verdict(ce) << ".**\n\n";
    }

    // ----- Paper vs eulerian
    {
        md << "## Paper vs eulerian inlet film\n\n";
        md << out.image("stability_defaults.svg", "growth rate over speed at the defaults") << "\n\n";
        const auto& m = R.map;
        md << "| configuration (defaults) | critical speed | largest Re λ over 1–60 m/s | smallest Re λ over 1–60 m/s |\n|---|---|---|---|\n";
        for (std::size_t k = 0; k < m.results.size(); ++k) {
            double lo = INFINITY, hi = -INFINITY, v_lo = kNaN, v_hi = kNaN;
            for (const auto& q : m.results[k].scan) {
                if (q.status != core::DynamicsStatus::ok) continue;
                if (q.max_real_part < lo) {
                    lo = q.max_real_part;
                    v_lo = q.speed;
                }
                if (q.max_real_part > hi) {
                    hi = q.max_real_part;
                    v_hi = q.speed;
                }
            }
            md << "| " << m.labels[k] << " | " << critical_text(m.results[k]) << " | " << fmt(hi, 1) << " 1/s at " << fmt(v_hi, 1)
               << " m/s | " << fmt(lo, 1) << " 1/s at " << fmt(v_lo, 1) << " m/s |\n";
        }
        // where the eulerian with constant tension becomes stable
        double restabilise = kNaN;
        {
            const auto& scan = m.results[3].scan;
            for (std::size_t k = 1; k < scan.size(); ++k) {
                if (!scan[k - 1].stable && scan[k].stable) {
                    restabilise = scan[k].speed;
                    break;
                }
            }
        }
        md << "\nMODEL.md §2 predicts that the eulerian film makes a ~450 Hz mode unstable at every speed at the defaults. "
              "**Confirmed, with a qualification:** with the default entry-span tension no speed in 1–60 m/s is stable "
              "(in the table above, even the smallest of the largest growth rates is positive). The unstable mode is the two work rolls moving "
              "against each other between the backup rolls ";
        const auto& he = R.high_mode_eulerian.rows;
        const auto& hp = R.high_mode_paper.rows;
        if (!he.empty()) md << "(" << fmt(he.back().frequency_Hz, 0) << "–" << fmt(he.front().frequency_Hz, 0) << " Hz over the speeds below)";
        md << ". With a constant back tension the film squeeze alone is unstable from 1 m/s up to ";
        md << (std::isfinite(restabilise) ? fmt(restabilise, 1) + " m/s, where the bite approaches full film and it becomes stable"
                                          : "the end of the range")
           << "; with the entry span, the ~104 Hz gap mode becomes unstable from " << fmt(gap_mode_crossing(m.results[2]).speed, 1)
           << " m/s (and later the ~400 Hz mode), before the squeeze instability has ended: the two overlap and leave no "
              "stable window (smallest largest growth rate " << [&] {
                  double lo = INFINITY;
                  for (const auto& q : m.results[2].scan) {
                      if (q.status == core::DynamicsStatus::ok) lo = std::min(lo, q.max_real_part);
                  }
                  return fmt(lo, 1);
              }() << " 1/s).\n\n";
        md << "| v (m/s) | mode (Hz) | A max | Re λ eulerian (1/s) | Re λ paper, same mode (1/s) | film-path damper eulerian "
              "(MN·s/m) | film-path damper paper (MN·s/m) | squeeze estimate abs(∂P/∂h0)·h0/(2θū1) (MN·s/m) | gap mass (t) |\n"
              "|---|---|---|---|---|---|---|---|---|\n";
        for (std::size_t k = 0; k < he.size() && k < hp.size(); ++k) {
            md << "| " << fmt(he[k].speed, 0) << " | " << fmt(he[k].frequency_Hz, 0) << " | " << fmt(he[k].contact_ratio_max, 3)
               << " | " << fmt(he[k].growth_rate, 1) << " | " << fmt(hp[k].growth_rate, 1) << " | " << fmt(he[k].film_damping * 1e-6, 2)
               << " | " << fmt(hp[k].film_damping * 1e-6, 2) << " | " << fmt(he[k].squeeze_estimate * 1e-6, 2) << " | "
               << fmt(he[k].gap_mass * 1e-3, 1) << " |\n";
        }
        md << "\n**Mechanism.** The eulerian film equation has the squeeze term −ẏc/2: an opening gap thins the inlet film, a "
              "thinner film raises asperity contact and friction, and the force rises while the gap opens — a negative "
              "damper across the gap of about abs(∂P/∂h0)·h0/(2θū1) (MODEL.md §2; the *squeeze estimate* column, which the "
              "full film-path calculation reproduces). The paper film's path damps instead (its θ̇ term is tiny). ";
        const ModeDiagnostics* e19 = nullptr;
        const ModeDiagnostics* p19 = nullptr;
        for (std::size_t k = 0; k < he.size() && k < hp.size(); ++k) {
            if (std::abs(he[k].speed - 19.0) < 1e-9) {
                e19 = &he[k];
                p19 = &hp[k];
            }
        }
        if (e19 && p19) {
            const double shift = -(e19->film_damping - p19->film_damping) / (2.0 * e19->gap_mass);
            md << "At 19 m/s the squeeze damper is only " << fmt(-e19->film_damping * 1e-6, 2)
               << " MN·s/m — a sixth of the tension loop's — but it acts on the " << fmt(e19->frequency_Hz, 0)
               << " Hz mode of the two work rolls moving against each other, whose gap mass is " << fmt(e19->gap_mass * 1e-3, 1)
               << " t (against ≈ 170 t for the ~104 Hz mode): the change of film-path damper from the paper film to the "
                  "eulerian film, " << fmt((p19->film_damping - e19->film_damping) * 1e-6, 2) << " MN·s/m, shifts that mode's "
                  "growth rate by about Δc/(2·m_gap) = " << fmt(shift, 0) << " 1/s (the eigenvalues: " << fmt(p19->growth_rate, 1)
               << " → " << fmt(e19->growth_rate, 1) << " 1/s), far beyond its structural damping. ";
        }
        md << "The lever ∂P/∂h0 is large in the mixed regime at low speed (large A) and vanishes in full film (A → 0), hence "
              "the growth rate falls with speed, and rough surfaces keep the instability to higher speeds than smooth ones.\n\n";
        md << "**Where the two film models differ in the figures:**\n\n";
        md << "- Figs. 8–12: the paper film has a critical speed at almost every point; the eulerian film has none (unstable at "
              "1 m/s everywhere). The ~100 Hz gap mode alone crosses zero somewhat earlier with the eulerian film (e.g. ";
        {
            const GapModeCrossing q = gap_mode_crossing(m.results[2]);
            md << fmt(q.speed, 1) << " against " << fmt(m.results[0].critical_speed, 1) << " m/s at the defaults";
        }
        md << "): its squeeze damper removes damping from that mode as well.\n";
        md << "- Fig. 13: no eulerian run lasts longer than a few tens of milliseconds.\n";
        md << "- Figs. 14–15: identical where the bite is in full film (Rq = 1 µm); no result where it is mixed (Rq = 6 µm).\n\n";
        md << "Real mills roll at these conditions without a 450–550 Hz instability, so the eulerian variant — as MODEL.md "
              "says — needs calibration (e.g. of how quickly the inlet film can follow the gap) before it can be used for "
              "critical speeds.\n\n";
    }

    // ----- Notes
    md << "## Notes for the core\n\n";
    md << "- **Film collapse.** When the eulerian film is driven to h0 ≤ 0, `CoupledModel::rhs` has no state and "
          "the run ends as `solver_failure` with the message \"the model has no state here: the inlet film collapsed or "
          "the roll bite did not solve\" (Fig. 13 eulerian at low speed, Figs. 14–15 eulerian at Rq = 6 µm).\n";
    md << "- **Amplitude excitation at low speed.** MODEL.md §7.4 excites at the least-damped eigenfrequency; below ≈ 8 m/s "
          "that is the 64 Hz mode, which has no gap motion and cannot be excited through the bite (the step in Fig. 13). "
          "Choosing the least-damped mode *with gap participation* would give a continuous curve; rollgap follows "
          "MODEL.md as written, and `excitation_frequency_Hz` lets a user excite the gap mode explicitly.\n\n";

    md << "## Files\n\n";
    md << "All in `" << out.link << "/`: ";
    for (std::size_t k = 0; k < out.files.size(); ++k) md << (k ? ", " : "") << "`" << out.files[k] << "`";
    md << ". CSV columns carry their units; empty cells are values that do not exist for that point (e.g. no critical "
          "speed).\n";
    return md.str();
}

}  // namespace

int main(int argc, char** argv) {
    fs::path out_dir = "docs/paper-reproduction";
    fs::path doc = "docs/paper-reproduction.md";
    int threads = core::default_thread_count();
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "reproduce_paper: %s needs a value\n", arg.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (arg == "--out") {
            out_dir = value();
        } else if (arg == "--doc") {
            doc = value();
        } else if (arg == "--threads") {
            threads = std::max(1, std::atoi(value().c_str()));
        } else if (arg == "--help" || arg == "-h") {
            std::printf("usage: reproduce_paper [--out DIR] [--doc FILE] [--threads N]\n"
                        "Regenerates the paper's Figs. 8-15 (CSV + SVG in DIR, default docs/paper-reproduction)\n"
                        "and writes the comparison FILE (default docs/paper-reproduction.md). Progress on stderr.\n");
            return 0;
        } else {
            std::fprintf(stderr, "reproduce_paper: unknown argument %s (try --help)\n", arg.c_str());
            return 2;
        }
    }
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (!doc.parent_path().empty()) fs::create_directories(doc.parent_path(), ec);
    Output out;
    out.dir = out_dir;
    out.doc = doc;
    {
        const fs::path base = doc.parent_path().empty() ? fs::path(".") : doc.parent_path();
        out.link = fs::relative(fs::absolute(out_dir), fs::absolute(base), ec).generic_string();
        if (ec || out.link.empty()) out.link = fs::absolute(out_dir).generic_string();
    }

    const auto t0 = Clock::now();
    Results R;
    R.threads = threads;
    R.figures = sweep_figures();
    log("threads: " + std::to_string(threads) + "; output: " + out_dir.string() + ", " + doc.string());

    // Figs. 8-12
    for (const SweepFigure& fig : R.figures) {
        std::array<SweepRun, 2> runs;
        for (std::size_t k = 0; k < 2; ++k) {
            runs[k] = run_sweep(fig, kFilmModels[k], threads);
            log("Fig. " + std::to_string(fig.number) + " (" + film_name(kFilmModels[k]) + " film): " +
                std::to_string(fig.xs.size()) + " critical speeds, " + std::to_string(runs[k].found) + " found, " +
                fmt(runs[k].seconds, 1) + " s");
        }
        R.sweeps.push_back(std::move(runs));
    }
    // Diagnostic: Figs. 9, 10, 12 with a fixed friction coefficient
    for (const SweepFigure& fig : R.figures) {
        if (fig.number != 9 && fig.number != 10 && fig.number != 12) continue;
        SweepFigure fixed = fig;
        const double mu = R.coulomb_mu;
        fixed.apply = [apply = fig.apply, mu](Scenario& s, double x) {
            apply(s, x);
            s.friction.model = core::FrictionModel::coulomb;
            s.friction.coulomb_coefficient = mu;
        };
        R.coulomb[fig.number] = run_sweep(fixed, InletFilmModel::paper, threads);
        log("Fig. " + std::to_string(fig.number) + " diagnostic (Coulomb μ = " + fmt(mu, 2) + "): " +
            fmt(R.coulomb[fig.number].seconds, 1) + " s");
    }
    // Fig. 13
    for (std::size_t k = 0; k < 2; ++k) {
        R.amplitude[k] = run_amplitude(kFilmModels[k], threads);
        log(std::string("Fig. 13 (") + film_name(kFilmModels[k]) + " film): " + std::to_string(R.amplitude[k].speeds.size()) +
            " amplitude runs, " + fmt(R.amplitude[k].seconds, 1) + " s");
    }
    // Figs. 14-15
    for (std::size_t k = 0; k < 2; ++k) {
        R.cycles[k] = run_cycles(kFilmModels[k], threads);
        log(std::string("Figs. 14-15 (") + film_name(kFilmModels[k]) + " film): " + fmt(R.cycles[k].seconds, 1) + " s");
    }
    // Mechanism studies
    {
        const auto t1 = Clock::now();
        const std::vector<Variant> variants = {
            {"defaults: Rayleigh ζ = 0.04 at 100 and 400 Hz, entry span L_b = 5 m, λ_L = 0.05", [](Scenario&) {}},
            {"Rayleigh ζ = 0.02", [](Scenario& s) { s.mill.rayleigh_damping_ratio = 0.02; }},
            {"Rayleigh ζ = 0.08", [](Scenario& s) { s.mill.rayleigh_damping_ratio = 0.08; }},
            {"no Rayleigh damping (only c1, c2, as in the paper)", [](Scenario& s) { s.mill.rayleigh = false; }},
            {"entry span L_b = 2.5 m", [](Scenario& s) { s.tensions.back.span_length = 2.5; }},
            {"entry span L_b = 10 m", [](Scenario& s) { s.tensions.back.span_length = 10.0; }},
            {"entry span L_b = 20 m", [](Scenario& s) { s.tensions.back.span_length = 20.0; }},
            {"constant back tension (no span state)", [](Scenario& s) { s.tensions.back.mode = core::TensionMode::constant; }},
            {"limiting shear λ_L = 0.03", [](Scenario& s) { s.lubricant.limiting_shear_coefficient = 0.03; }},
            {"limiting shear λ_L = 0.08", [](Scenario& s) { s.lubricant.limiting_shear_coefficient = 0.08; }},
        };
        R.variants = run_variants(variants, threads);
        R.coulomb_mus = {0.03, 0.05, 0.07, 0.10, 0.13, 0.16};
        std::vector<Variant> coulomb;
        for (double mu : R.coulomb_mus) {
            coulomb.push_back({"Coulomb μ = " + fmt(mu, 2), [mu](Scenario& s) {
                                   s.friction.model = core::FrictionModel::coulomb;
                                   s.friction.coulomb_coefficient = mu;
                               }});
        }
        R.coulomb_variants = run_variants(coulomb, threads);
        R.coulomb_diag.resize(R.coulomb_mus.size());
        core::parallel_for(static_cast<int>(R.coulomb_mus.size()), threads, [&](int i) {
            Scenario s;
            s.friction.model = core::FrictionModel::coulomb;
            s.friction.coulomb_coefficient = R.coulomb_mus[static_cast<std::size_t>(i)];
            s.rolls.speed = 15.0;
            R.coulomb_diag[static_cast<std::size_t>(i)] = tools::diagnose(s, 104.0);
        });
        std::vector<double> speeds = {5.0, 10.0, 15.0, 25.0, 30.0};
        const auto& vc = R.variants.front().result;
        if (vc.status == CriticalSpeedStatus::found) speeds.push_back(vc.critical_speed);
        std::sort(speeds.begin(), speeds.end());
        R.defaults_gap_mode = diagnose_over_speed(InletFilmModel::paper, speeds,
                                                  vc.status == CriticalSpeedStatus::found ? vc.unstable_mode.frequency_Hz : 104.0,
                                                  {}, threads);
        const std::vector<double> high_speeds = {2.0, 5.0, 10.0, 15.0, 19.0, 25.0, 30.0};
        R.high_mode_eulerian = diagnose_over_speed(InletFilmModel::eulerian, high_speeds, -1.0, {}, threads);
        R.high_mode_paper.film = InletFilmModel::paper;
        R.high_mode_paper.rows.resize(high_speeds.size());
        core::parallel_for(static_cast<int>(high_speeds.size()), threads, [&](int i) {
            Scenario s;
            s.rolls.speed = high_speeds[static_cast<std::size_t>(i)];
            R.high_mode_paper.rows[static_cast<std::size_t>(i)] =
                tools::diagnose(s, R.high_mode_eulerian.rows[static_cast<std::size_t>(i)].frequency_Hz);
        });
        R.map = stability_map(threads);
        log("mechanism diagnostics: " + fmt(seconds_since(t1), 1) + " s");
    }

    // Outputs
    for (std::size_t i = 0; i < R.figures.size(); ++i) {
        for (std::size_t k = 0; k < 2; ++k) {
            write_sweep_csv(out, R.figures[i], R.sweeps[i][k]);
            const auto fixed = R.coulomb.find(R.figures[i].number);
            plot_sweep(out, R.figures[i], R.sweeps[i][k], R.sweeps[i][0],
                       k == 0 && fixed != R.coulomb.end() ? &fixed->second : nullptr, R.coulomb_mu);
        }
    }
    for (const auto& [number, run] : R.coulomb) {
        for (const SweepFigure& fig : R.figures) {
            if (fig.number != number) continue;
            Csv csv({fig.x_column, "status", "critical_speed_m_s", "mode_frequency_Hz"});
            for (const auto& p : run.points) {
                csv.add({csv_number(p.x), core::to_string(p.result.status),
                         csv_number(p.result.status == CriticalSpeedStatus::found ? p.result.critical_speed : kNaN),
                         csv_number(p.result.status == CriticalSpeedStatus::found ? p.result.unstable_mode.frequency_Hz : kNaN)});
            }
            out.csv(fig.id + "_diagnostic_coulomb_mu" + fmt(R.coulomb_mu, 2) + ".csv", csv);
        }
    }
    {
        Csv csv({"speed_m_s", "mode_frequency_Hz", "mean_friction_coefficient", "film_ratio_min", "film_ratio_max",
                 "contact_ratio_max", "inlet_film_um", "strip_stiffness_GN_m", "gap_mass_t", "growth_rate_per_s",
                 "growth_constant_tension_per_s", "growth_frozen_film_per_s", "direct_damping_MN_s_m", "loop_damping_MN_s_m",
                 "film_damping_MN_s_m", "dP_dsb_m2", "du1_dg_per_s", "tension_pole_per_s"});
        for (const auto& d : R.defaults_gap_mode.rows) {
            csv.add({csv_number(d.speed), csv_number(d.frequency_Hz), csv_number(d.mean_friction), csv_number(d.film_ratio_min),
                     csv_number(d.film_ratio_max), csv_number(d.contact_ratio_max), csv_number(d.inlet_film * 1e6),
                     csv_number(d.strip_stiffness * 1e-9), csv_number(d.gap_mass * 1e-3), csv_number(d.growth_rate),
                     csv_number(d.growth_constant_tension), csv_number(d.growth_frozen_film), csv_number(d.direct_damping * 1e-6),
                     csv_number(d.loop_damping * 1e-6), csv_number(d.film_damping * 1e-6), csv_number(d.dP_dback),
                     csv_number(d.du1_dgap), csv_number(d.tension_pole)});
        }
        out.csv("mechanism_gap_mode_over_speed.csv", csv);
        Csv variants({"variant", "status", "critical_speed_m_s", "mode_frequency_Hz"});
        for (const auto* list : {&R.variants, &R.coulomb_variants}) {
            for (const auto& v : *list) {
                variants.add({v.label, core::to_string(v.result.status),
                              csv_number(v.result.status == CriticalSpeedStatus::found ? v.result.critical_speed : kNaN),
                              csv_number(v.result.status == CriticalSpeedStatus::found ? v.result.unstable_mode.frequency_Hz : kNaN)});
            }
        }
        out.csv("mechanism_variants.csv", variants);
    }
    for (std::size_t k = 0; k < 2; ++k) write_amplitude_outputs(out, R.amplitude[k]);
    for (std::size_t k = 0; k < 2; ++k) write_cycle_outputs(out, R.cycles[k]);
    write_stability_map(out, R.map);

    R.seconds = seconds_since(t0);
    const std::string markdown = write_markdown(R, out);
    {
        std::ofstream file(doc, std::ios::binary);
        file << markdown;
        if (!file) {
            log("cannot write " + doc.string());
            out.ok = false;
        }
    }
    log("done in " + fmt(R.seconds, 1) + " s: " + std::to_string(out.files.size()) + " files in " + out_dir.string() + ", " +
        doc.string());
    return out.ok ? 0 : 1;
}
