#include "tools/reproduce_paper/boundary_friction.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/parallel_for.h"

namespace rollgap::tools::paper {

std::vector<SteadyBite> steady_bites(double asperity_factor, const core::Control& compute) {
    std::vector<SteadyBite> bites(std::size(force_speeds));
    core::parallel_for(static_cast<int>(bites.size()), compute, [&](int i) {
        const auto k = static_cast<std::size_t>(i);
        Scenario s;
        s.friction.asperity_factor = asperity_factor;
        s.rolls.speed = force_speeds[k];
        core::BiteOptions options;
        options.distributions = false;
        const core::BiteResult b = core::solve_roll_bite(s, core::steady_bite_state(s), options);
        SteadyBite& out = bites[k];
        out.speed = force_speeds[k];
        out.status = b.status;
        if (b.status == core::BiteStatus::ok) {
            out.force = b.force;
            out.mean_friction = b.mean_friction_coefficient;
        }
    });
    return bites;
}

FrictionVariant run_friction_variant(const std::vector<SweepFigure>& figures,
                                     double asperity_factor, const core::Control& compute) {
    const auto t0 = Clock::now();
    FrictionVariant v;
    v.asperity_factor = asperity_factor;
    for (const SweepFigure& fig : figures)
        v.sweeps.push_back(run_sweep(fig, InletFilmModel::paper, compute, asperity_factor));
    v.amplitude = run_amplitude(InletFilmModel::paper, compute, asperity_factor);
    v.cycles = run_cycles(InletFilmModel::paper, compute, asperity_factor);
    v.bites = steady_bites(asperity_factor, compute);
    v.seconds = seconds_since(t0);
    return v;
}

FrictionVariant paper_friction_reference(const std::vector<std::array<SweepRun, 2>>& sweeps,
                                         const AmplitudeRun& amplitude, const CycleRun& cycles,
                                         const core::Control& compute) {
    FrictionVariant v;
    for (const auto& runs : sweeps) v.sweeps.push_back(runs[0]);
    v.amplitude = amplitude;
    v.cycles = cycles;
    v.bites = steady_bites(1.0, compute);
    return v;
}

std::string friction_sweep_plot(const SweepFigure& fig) {
    return fig.id + "_boundary_friction.svg";
}

namespace {

const char* const variant_colors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728"};
const char* const variant_dashes[] = {"", "8,4", "3,3", "10,3,2,3"};

std::string variant_label(double m_a) {
    return m_a == 1.0 ? "m_a = 1 (the paper)" : "m_a = " + fmt(m_a, 1) + " (boundary friction)";
}

// "m_a = 1, 0.7, 0.3": short enough for a plot's title.
std::string asperity_factors_text(const std::vector<FrictionVariant>& variants) {
    std::string s = "m_a = ";
    for (std::size_t k = 0; k < variants.size(); ++k)
        s += (k ? ", " : "") + fmtg(variants[k].asperity_factor, 2);
    return s;
}

void plot_friction_sweep(Output& out, const SweepFigure& fig,
                         const std::vector<FrictionVariant>& variants, std::size_t index) {
    Plot plot = critical_speed_plot(fig, "paper film, " + asperity_factors_text(variants));
    for (std::size_t k = 0; k < variants.size(); ++k) {
        const SweepRun& run = variants[k].sweeps[index];
        Series s = critical_series(fig, run,
                                   "critical speed, " + variant_label(variants[k].asperity_factor));
        s.color = variant_colors[k % std::size(variant_colors)];
        s.dash = variant_dashes[k % std::size(variant_dashes)];
        plot.series.push_back(s);
        add_status_edges(plot, fig, run, " (m_a = " + fmtg(variants[k].asperity_factor, 2) + ")");
    }
    plot.notes.push_back(
        "Search range 1–60 m/s (0.5 m/s scan, refined to 1e-4). Points without a critical speed are markers on "
        "the edge. Only m_a differs between the curves (docs/model.md §10.4).");
    out.svg(friction_sweep_plot(fig), plot);
}

void plot_friction_amplitude(Output& out, const std::vector<FrictionVariant>& variants) {
    Plot plot;
    plot.title =
        "Fig. 13: vibration amplitude vs speed — paper film, " + asperity_factors_text(variants);
    plot.x_label = "roll speed v (m/s)";
    plot.y_label = "upper work roll x3, half peak-to-peak (µm)";
    plot.log_y = true;
    plot.x_min = 0.0;
    plot.x_max = 25.0;
    std::string critical;
    for (std::size_t k = 0; k < variants.size(); ++k) {
        const AmplitudeRun& run = variants[k].amplitude;
        const std::string color = variant_colors[k % std::size(variant_colors)];
        Series x3 = named("x3, " + variant_label(variants[k].asperity_factor) +
                          " (run completed the window)");
        x3.color = color;
        x3.dash = variant_dashes[k % std::size(variant_dashes)];
        Series limit = named("x3 when a physical limit ended the run, m_a = " +
                             fmtg(variants[k].asperity_factor, 2));
        limit.line = false;
        limit.marker = Marker::triangle_up;
        limit.color = color;
        for (const auto& a : run.results) {
            x3.x.push_back(a.speed);
            x3.y.push_back(completed(a) ? a.upper_roll * 1e6 : no_value);
            limit.x.push_back(a.speed);
            limit.y.push_back(a.status == core::AmplitudeStatus::limit_reached ? a.upper_roll * 1e6
                                                                               : no_value);
        }
        for (const Series* s : {&x3, &limit}) {
            if (std::any_of(s->y.begin(), s->y.end(), [](double y) { return std::isfinite(y); }))
                plot.series.push_back(*s);
        }
        // Unlabelled lines (the critical speeds lie too close for labels): the note names them.
        if (run.critical.status == CriticalSpeedStatus::found) {
            plot.vertical_lines.push_back({run.critical.critical_speed, "", color});
            critical += (critical.empty() ? "" : ", ") + fmt(run.critical.critical_speed, 2) +
                        " m/s (m_a = " + fmtg(variants[k].asperity_factor, 2) + ")";
        }
    }
    if (!critical.empty())
        plot.notes.push_back("Dotted lines, in the variants' colours: the critical speeds " +
                             critical + ".");
    plot.notes.push_back(
        "Excitation: 1 MPa back-tension ripple at the least-damped eigenfrequency of each speed; window 2 s.");
    out.svg(friction_amplitude_plot, plot);
}

}  // namespace

void write_friction_variant_outputs(Output& out, const std::vector<SweepFigure>& figures,
                                    const std::vector<FrictionVariant>& variants) {
    for (const FrictionVariant& v : variants) {
        if (v.asperity_factor == 1.0) continue;  // the main report's files
        for (std::size_t i = 0; i < figures.size(); ++i)
            write_sweep_csv(out, figures[i], v.sweeps[i]);
        write_amplitude_outputs(out, v.amplitude);
        write_cycle_outputs(out, v.cycles);
    }
    for (std::size_t i = 0; i < figures.size(); ++i)
        plot_friction_sweep(out, figures[i], variants, i);
    plot_friction_amplitude(out, variants);
    Csv forces({"asperity_factor", "speed_m_s", "status", "force_MN", "mean_friction_coefficient"});
    for (const FrictionVariant& v : variants) {
        for (const SteadyBite& b : v.bites) {
            forces.add({csv_number(v.asperity_factor), csv_number(b.speed),
                        core::to_string(b.status), csv_number(b.force * 1e-6),
                        csv_number(b.mean_friction)});
        }
    }
    out.csv("boundary_friction_forces.csv", forces);
}

}  // namespace rollgap::tools::paper
