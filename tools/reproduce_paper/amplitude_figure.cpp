#include "tools/reproduce_paper/amplitude_figure.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/sweep.h"
#include "tools/reproduce_paper/sweep_figures.h"

namespace rollgap::tools::paper {

bool completed(const core::AmplitudeResult& a) { return a.end_status == core::DynamicsStatus::ok; }

AmplitudeRun run_amplitude(InletFilmModel film, const core::Control& compute,
                           double asperity_factor) {
    const auto t0 = Clock::now();
    AmplitudeRun run;
    run.film = film;
    run.asperity_factor = asperity_factor;
    run.speeds = range(2.0, 24.0, 1.0);
    std::vector<Scenario> scenarios;
    for (double v : run.speeds) {
        Scenario s;
        s.inlet_film = film;
        s.friction.asperity_factor = asperity_factor;
        s.rolls.speed = v;
        scenarios.push_back(s);
    }
    core::AmplitudeOptions options;  // window 2 s, 1 MPa at the least-damped eigenfrequency
    run.results = core::sweep_amplitude(scenarios, options, compute);
    Scenario s;
    s.inlet_film = film;
    s.friction.asperity_factor = asperity_factor;
    core::CriticalSpeedOptions search = search_options;
    run.critical = core::critical_speed(s, search, compute);
    std::vector<double> x3;
    for (const auto& a : run.results) x3.push_back(completed(a) ? a.upper_roll * 1e6 : no_value);
    run.trend =
        trend_of(run.speeds, x3, +1, speed_text, [](double v) { return fmtg(v, 3) + " µm"; });
    run.seconds = seconds_since(t0);
    return run;
}

void write_amplitude_outputs(Output& out, const AmplitudeRun& run) {
    Csv csv({"speed_m_s", "status", "upper_roll_um", "gap_um", "force_kN",
             "excitation_frequency_Hz", "least_damped_growth_rate_per_s",
             "window_growth_rate_per_s", "end_time_s", "settled", "end_status", "message"});
    for (const auto& a : run.results) {
        csv.add({csv_number(a.speed), core::to_string(a.status), csv_number(a.upper_roll * 1e6),
                 csv_number(a.gap * 1e6), csv_number(a.force * 1e-3),
                 csv_number(a.excitation_frequency_Hz), csv_number(a.least_damped_growth_rate),
                 csv_number(a.growth_rate), csv_number(a.end_time), a.settled ? "true" : "false",
                 core::to_string(a.end_status), a.message});
    }
    const std::string name =
        std::string("fig13_") + film_name(run.film) + variant_suffix(run.asperity_factor);
    out.csv(name + ".csv", csv);

    Plot plot;
    plot.title = std::string("Fig. 13: vibration amplitude vs rolling speed — ") +
                 film_name(run.film) + " inlet film" + variant_title(run.asperity_factor);
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
        x3.y.push_back(done ? a.upper_roll * 1e6 : no_value);
        gap.x.push_back(a.speed);
        gap.y.push_back(done ? a.gap * 1e6 : no_value);
        unsettled.x.push_back(a.speed);
        unsettled.y.push_back(done && !a.settled ? a.upper_roll * 1e6 : no_value);
        limit.x.push_back(a.speed);
        limit.y.push_back(a.status == core::AmplitudeStatus::limit_reached ? a.upper_roll * 1e6
                                                                           : no_value);
        failure.x.push_back(a.speed);
        failure.y.push_back(a.status == core::AmplitudeStatus::solver_failure ? a.upper_roll * 1e6
                                                                              : no_value);
    }
    for (const Series* s : {&x3, &gap, &unsettled, &limit, &failure}) {
        if (std::any_of(s->y.begin(), s->y.end(), [](double v) { return std::isfinite(v); }))
            plot.series.push_back(*s);
    }
    if (run.critical.status == CriticalSpeedStatus::found) {
        plot.vertical_lines.push_back(
            {run.critical.critical_speed,
             "critical speed " + fmt(run.critical.critical_speed, 1) + " m/s"});
    } else {
        plot.notes.push_back(
            std::string("No critical speed at the defaults with this film model: ") +
            core::to_string(run.critical.status) + ".");
    }
    plot.notes.push_back(
        "Excitation: 1 MPa back-tension ripple at the least-damped eigenfrequency of each speed; window 2 s; "
        "amplitude over the last 10 % of the window (or of the run, when a limit ended it).");
    out.svg(name + ".svg", plot);
}

}  // namespace rollgap::tools::paper
