#include "tools/reproduce_paper/cycle_figures.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/parallel_for.h"
#include "core/roll_bite.h"

namespace rollgap::tools::paper {

Scenario cycle_scenario(InletFilmModel film, double rq_um, double asperity_factor) {
    Scenario s;
    s.inlet_film = film;
    s.friction.asperity_factor = asperity_factor;
    s.roughness.roll_rq = rq_um * 1e-6;
    s.roughness.strip_rq = 0.0;
    s.tensions.back.stress = 18e6;  // 18 +- 9 MPa at 10 Hz (Section 6.2; docs/model.md §6 defaults)
    s.tensions.back.amplitude = 9e6;
    s.tensions.back.frequency = 10.0;
    return s;
}

CycleRun run_cycles(InletFilmModel film, const core::Control& compute, double asperity_factor) {
    const auto t0 = Clock::now();
    CycleRun run;
    run.film = film;
    run.asperity_factor = asperity_factor;
    run.cases.resize(2);
    run.cases[0].rq_um = 1.0;
    run.cases[1].rq_um = 6.0;
    core::parallel_for(2, compute, [&](int i) {
        CycleCase& c = run.cases[static_cast<std::size_t>(i)];
        const Scenario s = cycle_scenario(film, c.rq_um, asperity_factor);
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
    const std::string film = film_name(run.film) + variant_suffix(run.asperity_factor);
    Csv pressure({"Rq_um", "T", "back_tension_MPa", "x_mm", "pressure_MPa", "film_ratio",
                  "contact_ratio", "regime"});
    Csv friction({"Rq_um", "T", "back_tension_MPa", "x_mm", "friction_MPa", "strip_speed_m_s",
                  "film_ratio", "contact_ratio", "regime"});
    Csv summary({"Rq_um", "T", "status", "back_tension_MPa", "gap_um", "inlet_film_um", "force_MN",
                 "peak_pressure_MPa", "mean_pressure_MPa", "peak_friction_MPa", "mean_friction_MPa",
                 "film_ratio_min", "film_ratio_max", "contact_ratio_max", "neutral_point_mm",
                 "contact_length_mm"});
    for (const CycleCase& c : run.cases) {
        for (std::size_t k = 0; k < c.result.phases.size(); ++k) {
            const auto& p = c.result.phases[k];
            for (const auto& q : p.bite.distribution) {
                pressure.add({csv_number(c.rq_um), csv_number(p.phase),
                              csv_number(p.back_tension * 1e-6), csv_number(q.x * 1e3),
                              csv_number(q.pressure * 1e-6), csv_number(q.film_ratio),
                              csv_number(q.contact_ratio), core::to_string(q.regime)});
                friction.add({csv_number(c.rq_um), csv_number(p.phase),
                              csv_number(p.back_tension * 1e-6), csv_number(q.x * 1e3),
                              csv_number(q.friction * 1e-6), csv_number(q.strip_speed),
                              csv_number(q.film_ratio), csv_number(q.contact_ratio),
                              core::to_string(q.regime)});
            }
            const PhaseSummary& m = c.phases[k];
            summary.add({csv_number(c.rq_um), csv_number(m.phase), core::to_string(c.result.status),
                         csv_number(m.back_tension * 1e-6), csv_number(m.gap * 1e6),
                         csv_number(m.inlet_film * 1e6), csv_number(m.force * 1e-6),
                         csv_number(m.peak_pressure * 1e-6), csv_number(m.mean_pressure * 1e-6),
                         csv_number(m.peak_friction * 1e-6),
                         csv_number(m.mean_friction_stress * 1e-6), csv_number(m.film_ratio_min),
                         csv_number(m.film_ratio_max), csv_number(m.contact_ratio_max),
                         csv_number(m.neutral_point * 1e3), csv_number(m.contact_length * 1e3)});
        }
        if (c.result.phases.empty()) {
            summary.add({csv_number(c.rq_um), "", core::to_string(c.result.status), "", "", "", "",
                         "", "", "", "", "", "", "", "", ""});
        }
    }
    out.csv("fig14_" + film + ".csv", pressure);
    out.csv("fig15_" + film + ".csv", friction);
    out.csv("fig14-15_summary_" + film + ".csv", summary);

    for (int figure : {14, 15}) {
        Plot plot;
        plot.title = "Fig. " + std::to_string(figure) + ": " +
                     (figure == 14 ? "compressive stress" : "friction stress") +
                     " over a back-tension cycle — " + film_name(run.film) + " inlet film" +
                     variant_title(run.asperity_factor);
        plot.x_label = "x (mm), from the exit (0) to the entry";
        plot.y_label =
            figure == 14 ? "compressive stress p (MPa)" : "friction stress τ on the strip (MPa)";
        plot.x_min = 0.0;
        for (const CycleCase& c : run.cases) {
            for (const auto& p : c.result.phases) {
                Series s;
                s.label = rq_label(c.rq_um) + ", T = " + fmt(p.phase, 2) +
                          " (s_b = " + fmt(p.back_tension * 1e-6, 1) + " MPa)";
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
                plot.notes.push_back(
                    rq_label(c.rq_um) +
                    ": no distributions — the coupled run ended before the first phase: " +
                    core::to_string(c.result.status) + " (\"" + c.result.message +
                    "\"). With the back tension " +
                    "as an input this case has an unstable mode at " +
                    fmt(c.input_tension.least_damped.frequency_Hz, 0) + " Hz growing at " +
                    fmt(c.input_tension.max_real_part, 0) + " 1/s.");
            }
        }
        plot.notes.push_back(
            "Back tension 18 ± 9 MPa at 10 Hz, sinusoid (T = 0.25: highest, 0.5: mean, 0.75: lowest); v = 19 m/s, "
            "R = 0.15; distributions at the phases of the second cycle of the coupled run.");
        out.svg("fig" + std::to_string(figure) + "_" + film + ".svg", plot);
    }
}

}  // namespace rollgap::tools::paper
