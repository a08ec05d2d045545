#include "tools/reproduce_paper/sweep_figures.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/parallel_for.h"
#include "core/sweep.h"

namespace rollgap::tools::paper {

std::vector<double> range(double from, double to, double step) {
    std::vector<double> out;
    const int n = static_cast<int>(std::floor((to - from) / step + 1e-9));
    for (int i = 0; i <= n; ++i) out.push_back(from + i * step);
    return out;
}

std::vector<SweepFigure> sweep_figures() {
    std::vector<SweepFigure> figures;
    figures.push_back(
        {8, "fig08", "the emulsion viscosity η0", "η0", "mPa·s", "eta0_mPa_s", 2,
         range(0.1, 2.0, 0.1), [](Scenario& s, double x) { s.lubricant.viscosity = x * 1e-3; }, -1,
         "It can be seen that the critical speed of the vibration decreases with increasing viscosity.",
         "the critical speed falls as η0 rises",
         "`lubricant.viscosity` = η0; everything else at the defaults (Rq = 2.0 µm, y1 = 1.6 mm, R = 0.15, a = 280 mm)"});
    std::vector<double> exit_thicknesses = range(1.10, 1.55, 0.025);
    exit_thicknesses.push_back(1.36);  // the default (R = 0.15)
    std::sort(exit_thicknesses.begin(), exit_thicknesses.end());
    figures.push_back(
        {9, "fig09", "the exit thickness y2 (entry fixed at 1.6 mm)", "y2", "mm", "y2_mm", 3,
         exit_thicknesses, [](Scenario& s, double x) { s.strip.reduction = 1.0 - x / 1.6; }, +1,
         "It can be seen that the vibration critical speed decreases with increasing inlet thickness and "
         "decreasing outlet thickness, respectively, indicating that self-excited vibration will easily occur.",
         "the critical speed falls as the exit thickness falls (rises with y2)",
         "y1 = 1.6 mm, `strip.reduction` = 1 − y2/y1 (R = 0.31 … 0.031)"});
    figures.push_back(
        {10, "fig10", "the entry thickness y1 (exit fixed at 1.36 mm)", "y1", "mm", "y1_mm", 2,
         range(1.42, 2.0, 0.02),
         [](Scenario& s, double x) {
             s.strip.entry_thickness = x * 1e-3;
             s.strip.reduction = 1.0 - 1.36 / x;
         },
         -1,
         "It can be seen that the vibration critical speed decreases with increasing inlet thickness and "
         "decreasing outlet thickness, respectively, indicating that self-excited vibration will easily occur.",
         "the critical speed falls as the entry thickness rises",
         "`strip.entry_thickness` = y1, `strip.reduction` = 1 − 1.36 mm / y1 (R = 0.042 … 0.32)"});
    figures.push_back(
        {11, "fig11", "the composite roughness Rq", "Rq", "µm", "Rq_um", 2, range(0.5, 6.0, 0.25),
         [](Scenario& s, double x) {
             s.roughness.roll_rq = x * 1e-6;
             s.roughness.strip_rq = 0.0;
         },
         +1,
         "As shown in Fig. 11, the vibration critical speed of the rolling mill vertical system shows an "
         "increasing trend towards roughness, indicating that the system does not easily experience vibration.",
         "the critical speed rises with the roughness",
         "`roughness.roll_rq` = Rq, `roughness.strip_rq` = 0 (composite Rq = Rq)"});
    figures.push_back(
        {12, "fig12", "the work roll radius a", "a", "mm", "radius_mm", 0,
         range(150.0, 400.0, 10.0), [](Scenario& s, double x) { s.rolls.radius = x * 1e-3; }, +1,
         "It can be seen that a decrease in work roll radius induces decreased rolling mill vibration critical speed.",
         "the critical speed rises with the roll radius",
         "`rolls.radius` = a (the mill masses and stiffnesses are not changed with the radius)"});
    return figures;
}

// The ~100 Hz gap mode (the stack's lowest mode with gap motion) followed over the 0.5 m/s scan
// by core's branch tracking: where its damping ratio crosses zero (linear interpolation between
// scan speeds). This is a secondary figure: the critical speed is the lowest crossing of ANY mode.
GapModeCrossing gap_mode_crossing(const core::CriticalSpeedResult& r) {
    GapModeCrossing out;
    const core::DampingBranch* branch = nullptr;
    for (const auto& b : r.branches) {
        const double f0 = b.frequency_Hz.front();
        if (f0 < 80.0 || f0 > 140.0) continue;
        if (!branch || std::abs(f0 - 105.0) < std::abs(branch->frequency_Hz.front() - 105.0))
            branch = &b;
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
            out.frequency_Hz = branch->frequency_Hz[i] +
                               w * (branch->frequency_Hz[i + 1] - branch->frequency_Hz[i]);
            return out;
        }
    }
    out.status = "stable_in_range";
    return out;
}

// The value a critical-speed point contributes to the trend: the critical speed, or the end of
// the search range it lies beyond (stable_in_range: >= 60 m/s; unstable_at_lower_bound: <= 1 m/s).
double trend_value(const core::CriticalSpeedResult& r) {
    switch (r.status) {
        case CriticalSpeedStatus::found: return r.critical_speed;
        case CriticalSpeedStatus::stable_in_range: return search_options.speed_max;
        case CriticalSpeedStatus::unstable_at_lower_bound: return search_options.speed_min;
        default: return no_value;
    }
}

std::string speed_text(double v) { return fmt(v, 2) + " m/s"; }

Series named(std::string label) {
    Series s;
    s.label = std::move(label);
    return s;
}

SweepRun run_sweep(const SweepFigure& fig, InletFilmModel film, const core::Control& compute,
                   double asperity_factor) {
    const auto t0 = Clock::now();
    SweepRun run;
    run.film = film;
    run.asperity_factor = asperity_factor;
    std::vector<Scenario> scenarios;
    for (double x : fig.xs) {
        Scenario s;
        s.inlet_film = film;
        s.friction.asperity_factor = asperity_factor;
        fig.apply(s, x);
        scenarios.push_back(s);
    }
    std::vector<core::CriticalSpeedResult> results =
        core::sweep_critical_speed(scenarios, search_options, compute);
    run.points.resize(fig.xs.size());
    core::parallel_for(static_cast<int>(fig.xs.size()), compute, [&](int i) {
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
        gap_values.push_back(p.gap_mode.status == "found"             ? p.gap_mode.speed
                             : p.gap_mode.status == "stable_in_range" ? search_options.speed_max
                                                                      : no_value);
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
    Csv csv({fig.x_column,
             "status",
             "critical_speed_m_s",
             "mode_frequency_Hz",
             "mode_growth_rate_per_s",
             "gap_mode_status",
             "gap_mode_crossing_m_s",
             "gap_mode_frequency_Hz",
             "gap_mode_unstable_below_m_s",
             "mean_friction_coefficient",
             "film_ratio_min",
             "film_ratio_max",
             "contact_ratio_max",
             "inlet_film_um",
             "inlet_angle_mrad",
             "strip_stiffness_GN_m",
             "gap_mass_t",
             "growth_constant_tension_per_s",
             "growth_frozen_film_per_s",
             "loop_damping_MN_s_m",
             "film_damping_MN_s_m",
             "dP_dsb_m2",
             "du1_dg_over_v_per_y1"});
    for (const SweepPoint& p : run.points) {
        const auto& r = p.result;
        const bool found = r.status == CriticalSpeedStatus::found;
        const bool has_mode = found || r.status == CriticalSpeedStatus::unstable_at_lower_bound;
        const ModeDiagnostics& d = p.diag;
        const double v = found ? r.critical_speed : no_value;
        Scenario s;
        fig.apply(s, p.x);
        csv.add({csv_number(p.x),
                 core::to_string(r.status),
                 csv_number(v),
                 has_mode ? csv_number(r.unstable_mode.frequency_Hz) : "",
                 r.status == CriticalSpeedStatus::unstable_at_lower_bound
                     ? csv_number(r.unstable_mode.eigenvalue.real())
                     : "",
                 p.gap_mode.status,
                 csv_number(p.gap_mode.speed),
                 csv_number(p.gap_mode.frequency_Hz),
                 csv_number(p.gap_mode.unstable_below),
                 csv_number(d.mean_friction),
                 csv_number(d.film_ratio_min),
                 csv_number(d.film_ratio_max),
                 csv_number(d.contact_ratio_max),
                 csv_number(d.inlet_film * 1e6),
                 csv_number(d.inlet_angle * 1e3),
                 csv_number(d.strip_stiffness * 1e-9),
                 csv_number(d.gap_mass * 1e-3),
                 csv_number(d.growth_constant_tension),
                 csv_number(d.growth_frozen_film),
                 csv_number(d.loop_damping * 1e-6),
                 csv_number(d.film_damping * 1e-6),
                 csv_number(d.dP_dback),
                 csv_number(d.du1_dgap * s.strip.entry_thickness / std::max(v, 1e-300))});
    }
    out.csv(fig.id + "_" + film_name(run.film) + variant_suffix(run.asperity_factor) + ".csv", csv);
}

void add_status_edges(Plot& plot, const SweepFigure& fig, const SweepRun& run,
                      const std::string& suffix) {
    EdgeMarkers stable{"stable up to 60 m/s (no critical speed in the range)" + suffix,
                       {},
                       EdgeMarkers::Edge::top,
                       Marker::triangle_up,
                       "#2ca02c"};
    EdgeMarkers lower{"unstable already at 1 m/s (unstable_at_lower_bound)" + suffix,
                      {},
                      EdgeMarkers::Edge::bottom,
                      Marker::triangle_down,
                      "#d62728"};
    EdgeMarkers none{"no steady state (skidding / contact lost)" + suffix,
                     {},
                     EdgeMarkers::Edge::bottom,
                     Marker::cross,
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
        s.y.push_back(run.points[i].result.status == CriticalSpeedStatus::found
                          ? run.points[i].result.critical_speed
                          : no_value);
    }
    return s;
}

Plot critical_speed_plot(const SweepFigure& fig, const std::string& what) {
    Plot plot;
    plot.title =
        "Fig. " + std::to_string(fig.number) + ": critical speed vs " + fig.x_symbol + " — " + what;
    plot.x_label = fig.x_label();
    plot.y_label = "critical speed (m/s)";
    plot.y_min = 0.0;
    plot.y_max = 62.0;
    const double pad = 0.02 * (fig.xs.back() - fig.xs.front());
    plot.x_min = fig.xs.front() - pad;
    plot.x_max = fig.xs.back() + pad;
    return plot;
}

void plot_sweep(Output& out, const SweepFigure& fig, const SweepRun& run, const SweepRun& paper,
                const SweepRun* fixed_friction, double fixed_mu) {
    Plot plot = critical_speed_plot(fig, std::string(film_name(run.film)) + " inlet film");
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
            if (!(r.status == CriticalSpeedStatus::found && r.unstable_mode.frequency_Hz > 200.0))
                high.y[i] = no_value;
        }
        if (std::any_of(high.y.begin(), high.y.end(), [](double v) { return std::isfinite(v); }))
            plot.series.push_back(high);
        if (fixed_friction) {
            Series fixed = critical_series(fig, *fixed_friction,
                                           "diagnostic, not the model: friction fixed at μ = " +
                                               fmt(fixed_mu, 2) + " (Coulomb)");
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
    plot.notes.push_back(
        "Search range 1–60 m/s (0.5 m/s scan, refined to 1e-4). Every point of the sweep is shown: with a "
        "critical speed on the curve, without one as a marker on the edge.");
    out.svg(fig.id + "_" + film_name(run.film) + ".svg", plot);
}

}  // namespace rollgap::tools::paper
