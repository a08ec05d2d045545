#include "tools/reproduce_paper/mechanism.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/parallel_for.h"
#include "core/sweep.h"
#include "tools/reproduce_paper/sweep_figures.h"

namespace rollgap::tools::paper {

std::vector<VariantResult> run_variants(const std::vector<Variant>& variants,
                                        const core::Control& compute) {
    std::vector<Scenario> scenarios;
    for (const Variant& v : variants) {
        Scenario s;
        v.apply(s);
        scenarios.push_back(s);
    }
    auto results = core::sweep_critical_speed(scenarios, search_options, compute);
    std::vector<VariantResult> out;
    for (std::size_t i = 0; i < variants.size(); ++i)
        out.push_back({variants[i].label, std::move(results[i])});
    return out;
}

std::string critical_text(const core::CriticalSpeedResult& r) {
    switch (r.status) {
        case CriticalSpeedStatus::found:
            return fmt(r.critical_speed, 2) + " m/s (" + fmt(r.unstable_mode.frequency_Hz, 0) +
                   " Hz)";
        case CriticalSpeedStatus::stable_in_range: return "stable to 60 m/s";
        case CriticalSpeedStatus::unstable_at_lower_bound:
            return "unstable at 1 m/s (" + fmt(r.unstable_mode.frequency_Hz, 0) + " Hz, " +
                   fmt(r.unstable_mode.eigenvalue.real(), 0) + " 1/s)";
        default: return core::to_string(r.status);
    }
}

// The coupled model at the defaults over speed, following the mode nearest `frequency_Hz`
// (<= 0: the least-damped one).
SpeedDiagnostics diagnose_over_speed(InletFilmModel film, const std::vector<double>& speeds,
                                     double frequency_Hz,
                                     const std::function<void(Scenario&)>& apply,
                                     const core::Control& compute) {
    SpeedDiagnostics out{film, std::vector<ModeDiagnostics>(speeds.size())};
    core::parallel_for(static_cast<int>(speeds.size()), compute, [&](int i) {
        Scenario s;
        s.inlet_film = film;
        if (apply) apply(s);
        s.rolls.speed = speeds[static_cast<std::size_t>(i)];
        out.rows[static_cast<std::size_t>(i)] = tools::diagnose(s, frequency_Hz);
    });
    return out;
}

StabilityMap stability_map(const core::Control& compute) {
    StabilityMap map;
    std::vector<Scenario> scenarios;
    for (InletFilmModel film : film_models) {
        for (bool span : {true, false}) {
            Scenario s;
            s.inlet_film = film;
            if (!span) s.tensions.back.mode = core::TensionMode::constant;
            scenarios.push_back(s);
            map.labels.push_back(std::string(film_name(film)) + " film, " +
                                 (span ? "entry-span tension (default)" : "constant back tension"));
        }
    }
    map.results = core::sweep_critical_speed(scenarios, search_options, compute);
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
            s.y.push_back(p.status == core::DynamicsStatus::ok ? p.max_real_part : no_value);
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
                         fmt(std::max(map.results[2].scan.front().max_real_part,
                                      map.results[3].scan.front().max_real_part),
                             0) +
                         " 1/s at 1 m/s); the CSV has every value. Scan step 0.5 m/s.");
    out.svg("stability_defaults.svg", plot);
}

}  // namespace rollgap::tools::paper
