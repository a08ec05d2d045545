// The report on Fig. 13.

#include "tools/reproduce_paper/markdown_sections.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tools/reproduce_paper/markdown_cells.h"

namespace rollgap::tools::paper {

// Fig. 13.
void md_amplitude_figure(std::ostringstream& md, const Results& R, const Output& out) {
    // ----- Fig. 13
    {
        const AmplitudeRun& p = R.amplitude[0];
        const AmplitudeRun& e = R.amplitude[1];
        md << "## Fig. 13: vibration amplitude vs rolling speed\n\n";
        md << "**The paper:** \"It can be seen that the vibration amplitude increases with increasing rolling speed.\"\n\n";
        md << "**Setup:** defaults, v = 2–24 m/s; `core::vibration_amplitude` excites the bite with a 1 MPa back-tension "
              "ripple at the least-damped eigenfrequency of each speed and integrates the nonlinear coupled model for 2 s "
              "(docs/model.md §7.4). Amplitude: half peak-to-peak over the last 10 % of the window, or of the run when a "
              "physical limit ended it.\n\n";
        md << out.image("fig13_paper.svg", "Fig. 13, paper film") << "\n"
           << out.image("fig13_eulerian.svg", "Fig. 13, eulerian film") << "\n\n";
        md << "**Paper film — the model:** over the runs that complete the window the upper work roll amplitude is "
           << p.trend.direction << ". **Verdict: " << p.trend.verdict << "**. ";
        int limit = 0;
        double first_limit = no_value;
        for (const auto& a : p.results) {
            if (a.status == core::AmplitudeStatus::limit_reached) {
                ++limit;
                if (!std::isfinite(first_limit)) first_limit = a.speed;
            }
        }
        if (limit > 0) {
            md << "From " << fmt(first_limit, 0) << " m/s on (" << limit
               << " speeds) the run ends at a physical limit — ";
            for (const auto& a : p.results) {
                if (a.status == core::AmplitudeStatus::limit_reached) {
                    md << "\"" << a.message << "\"";
                    break;
                }
            }
            md << " — after " <<
                [&] {
                    double lo = INFINITY, hi = 0;
                    for (const auto& a : p.results) {
                        if (a.status == core::AmplitudeStatus::limit_reached) {
                            lo = std::min(lo, a.end_time);
                            hi = std::max(hi, a.end_time);
                        }
                    }
                    return fmt(lo, 2) + "–" + fmt(hi, 2) + " s";
                }()
               << ", with the gap swinging by ±" <<
                [&] {
                    double lo = INFINITY, hi = 0;
                    for (const auto& a : p.results) {
                        if (a.status == core::AmplitudeStatus::limit_reached) {
                            lo = std::min(lo, a.gap * 1e6);
                            hi = std::max(hi, a.gap * 1e6);
                        }
                    }
                    return fmt(lo, 0) + "–" + fmt(hi, 0) + " µm";
                }()
               << ". The model has no limit cycle below the physical limits: above the critical speed the vibration grows "
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
                md << " (10 m/s: Re λ = " << fmt(a10->least_damped_growth_rate, 1)
                   << " 1/s, x3 = " << fmtg(a10->upper_roll * 1e6, 3)
                   << " µm; 18 m/s: Re λ = " << fmt(a18->least_damped_growth_rate, 1)
                   << " 1/s, x3 = " << fmtg(a18->upper_roll * 1e6, 3) << " µm)";
            }
        }
        md << ". Even a linearly stable point just below v_c can reach the slack-strip limit: the 1 MPa ripple on a mode "
              "with ζ ≈ 0.0003 is amplified enormously.\n\n";
        // the low-speed step
        {
            const core::AmplitudeResult* before = nullptr;
            const core::AmplitudeResult* after = nullptr;
            for (std::size_t k = 0; k + 1 < p.results.size(); ++k) {
                if (p.results[k].excitation_frequency_Hz < 80.0 &&
                    p.results[k + 1].excitation_frequency_Hz > 80.0) {
                    before = &p.results[k];
                    after = &p.results[k + 1];
                }
            }
            if (before && after) {
                md << "*Note on the step between " << fmt(before->speed, 0) << " and "
                   << fmt(after->speed, 0) << " m/s:* below " << fmt(after->speed, 0)
                   << " m/s the least-damped eigenvalue is the "
                   << fmt(before->excitation_frequency_Hz, 1)
                   << " Hz mode, which has no gap motion (upper and lower halves in phase) and cannot be excited through the "
                      "bite; the excitation then drives the gap mode off resonance and the amplitude is small ("
                   << fmtg(before->upper_roll * 1e6, 3) << " µm). At " << fmt(after->speed, 0)
                   << " m/s the ~" << fmt(after->excitation_frequency_Hz, 0)
                   << " Hz gap mode becomes the least damped, the excitation moves "
                      "onto it and the amplitude jumps to "
                   << fmtg(after->upper_roll * 1e6, 3)
                   << " µm. The step is a property of docs/model.md §7.4's choice of excitation frequency, not of the mill; it "
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
            md << "no run completes the window; every run ends after " << fmt(end_lo * 1e3, 0)
               << "–" << fmt(end_hi * 1e3, 0) << " ms: ";
            bool comma = false;
            for (const auto& [s, n] : statuses) {
                md << (comma ? ", " : "") << n << "× " << s;
                comma = true;
            }
            md << ". The film-squeeze mode (" << fmt(e.results.front().excitation_frequency_Hz, 0)
               << "–" << fmt(e.results.back().excitation_frequency_Hz, 0) << " Hz, growth rate "
               << fmt(e.results.back().least_damped_growth_rate, 0) << "–"
               << fmt(e.results.front().least_damped_growth_rate, 0)
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
            md << "| " << fmt(a.speed, 0) << " | " << core::to_string(a.status) << " | "
               << fmtg(a.upper_roll * 1e6, 3) << " | " << fmtg(a.gap * 1e6, 3) << " | "
               << fmt(a.excitation_frequency_Hz, 1) << " | " << fmt(a.least_damped_growth_rate, 2)
               << " | " << fmt(a.end_time, 3) << " | " << core::to_string(b.status) << " | "
               << fmtg(b.upper_roll * 1e6, 3) << " | " << fmt(b.excitation_frequency_Hz, 1) << " | "
               << fmt(b.least_damped_growth_rate, 1) << " | " << fmt(b.end_time, 4) << " |\n";
        }
        md << "\n</details>\n\n";
    }
}

}  // namespace rollgap::tools::paper
