// The report on the boundary-friction variant (docs/model.md §10.4): the steady force over
// speed, and per figure the paper's direction and the verdict of every asperity factor, computed
// from the runs (the same trend and check functions as the main report).

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tools/reproduce_paper/markdown_cells.h"
#include "tools/reproduce_paper/markdown_sections.h"

namespace rollgap::tools::paper {

namespace {

std::string ma_text(double m_a) { return "m_a = " + fmtg(m_a, 2); }

std::string sweep_cell(const SweepRun& run, const SweepFigure& fig) {
    if (run.found == 0) return run.trend.direction + "; " + run.trend.verdict;
    std::string s = short_direction(run.trend);
    const std::string ext = extremum_text(run.trend, fig);
    if (!ext.empty()) s += "; " + ext;
    return s + ": " + verdict_cell(run.trend);
}

// The mean friction coefficient at the critical speed at the first and last point that has one.
std::pair<double, double> friction_ends(const SweepRun& run) {
    double first = no_value, last = no_value;
    for (const SweepPoint& p : run.points) {
        if (p.result.status != CriticalSpeedStatus::found) continue;
        if (!std::isfinite(first)) first = p.diag.mean_friction;
        last = p.diag.mean_friction;
    }
    return {first, last};
}

// Where the verdicts differ: what the data say about the friction path. The main report
// (Figs. 9, 10, 12) traces two competing effects: the geometry the paper describes, alone when
// the friction coefficient is held fixed, and friction that changes with asperity contact. The
// asperity term of the friction law is A·m_a·σ/2, so m_a scales the second effect; the cell gives
// the friction coefficient at the critical speed over the range for every variant and the
// fixed-friction diagnostic's direction, the evidence for that reading.
std::string sweep_mechanism(const Results& R, std::size_t index) {
    const SweepFigure& fig = R.figures[index];
    bool differs = false;
    for (const FrictionVariant& v : R.friction)
        differs =
            differs || v.sweeps[index].trend.verdict != R.friction[0].sweeps[index].trend.verdict;
    if (!differs) return "same verdict for every m_a";
    std::string s = "μ at v_c over the range (first → last point): ";
    // Does the friction change over the range shrink as m_a falls (R.friction is in falling m_a)?
    bool shrinks = true;
    double previous = INFINITY;
    for (std::size_t k = 0; k < R.friction.size(); ++k) {
        const auto [first, last] = friction_ends(R.friction[k].sweeps[index]);
        s += (k ? "; " : "") + ma_text(R.friction[k].asperity_factor) + ": " + fmt(first, 3) +
             " → " + fmt(last, 3) + " (Δ " + (last >= first ? "+" : "−") +
             fmt(std::abs(last - first), 3) + ")";
        shrinks = shrinks && std::abs(last - first) < previous;
        previous = std::abs(last - first);
    }
    s +=
        shrinks
            ? ". The asperity shear A·m_a·σ/2 carries the friction change that competes with the geometry "
              "(main report, this figure's mechanism); it shrinks with m_a"
            : ". The friction change over the range does not shrink steadily with m_a";
    const auto fixed = R.coulomb.find(fig.number);
    if (fixed != R.coulomb.end()) {
        s += ", and with μ held at " + fmt(R.coulomb_mu, 2) +
             " (Coulomb diagnostic) the curve is " + short_direction(fixed->second.trend) + " (" +
             fixed->second.trend.verdict + ")";
    }
    return s;
}

std::string amplitude_cell(const AmplitudeRun& run) {
    double first_limit = no_value;
    for (const auto& a : run.results) {
        if (a.status == core::AmplitudeStatus::limit_reached) {
            first_limit = a.speed;
            break;
        }
    }
    std::string s =
        short_direction(run.trend) + " below v_c = " + fmt(run.critical.critical_speed, 2) + " m/s";
    if (std::isfinite(first_limit)) s += " (limit reached from " + fmt(first_limit, 0) + " m/s)";
    return s + ": " + verdict_cell(run.trend);
}

std::string cycle_cell(const CycleChecks& c, int figure) {
    if (!c.available) return "no result: **not testable**";
    if (figure == 14) {
        return "Rq = 6 µm " + std::string(c.rough_higher_everywhere ? "higher" : "not higher") +
               " at every T; roughness effect on the force " + fmt(c.dP_high * 1e-6, 2) + " → " +
               fmt(c.dP_low * 1e-6, 2) + " MN (T = 0.25 → 0.75); mean p at T = 0.75 " +
               percent(c.mean_p_ratio_low - 1.0, 0) + ": " + bold(fig14_verdict(c));
    }
    return "mean friction stress ×" + fmt(c.friction_ratio_min, 1) + "–" +
           fmt(c.friction_ratio_max, 1) + " (Rq 6 vs 1 µm); back tension ≤ " +
           fmt(c.tension_effect_on_friction * 100, 1) + " %: " + bold(fig15_verdict(c));
}

}  // namespace

void md_boundary_friction(std::ostringstream& md, const Results& R, const Output& out) {
    if (R.friction.empty()) return;
    md << "## Boundary friction variant (m_a < 1)\n\n";
    md << "*A labelled variant, not the paper's model: every other section runs the paper's m_a = 1.* The paper's "
          "asperities stick: the asperity shear stress is τ_a = m_a·σ/2 with m_a = 1 (eq. 16, docs/model.md §4). "
          "Boundary-lubricated asperities shear at a fraction of the strip's shear yield stress, m_a < 1 "
          "(docs/model.md §10.4 gives the values' basis). This section reruns Figs. 8–15 with the paper film for "
          ""
       <<
        [&] {
            std::string s;
            for (std::size_t k = 1; k < R.friction.size(); ++k)
                s += (k > 1 ? " and " : "") + ma_text(R.friction[k].asperity_factor);
            return s;
        }()
       << " beside the paper's m_a = 1; nothing else changes. Verdicts come from the same trend and check functions "
          "as the Summary.\n\n";

    md << "### Roll force over speed (default stand, steady bite)\n\n";
    md << "| m_a | ";
    for (double v : force_speeds) md << "force at " << fmt(v, 0) << " m/s (MN) | ";
    md << "change " << fmt(force_speeds[0], 0) << " → "
       << fmt(force_speeds[std::size(force_speeds) - 1], 0) << " m/s | mean μ at "
       << fmt(force_speeds[0], 0) << " / " << fmt(force_speeds[std::size(force_speeds) - 1], 0)
       << " m/s | critical speed at the defaults |\n|---|";
    for (std::size_t k = 0; k < std::size(force_speeds) + 3; ++k) md << "---|";
    md << "\n";
    for (const FrictionVariant& v : R.friction) {
        md << "| " << fmtg(v.asperity_factor, 2) << (v.asperity_factor == 1.0 ? " (paper)" : "")
           << " | ";
        for (const SteadyBite& b : v.bites)
            md << (b.status == core::BiteStatus::ok ? fmt(b.force * 1e-6, 2)
                                                    : std::string(core::to_string(b.status)))
               << " | ";
        const SteadyBite& lo = v.bites.front();
        const SteadyBite& hi = v.bites.back();
        md << percent(hi.force / lo.force - 1.0, 0) << " | " << fmt(lo.mean_friction, 3) << " / "
           << fmt(hi.mean_friction, 3) << " | " << critical_text(v.amplitude.critical) << " |\n";
    }
    md << "\n(CSV: `boundary_friction_forces.csv`.)\n\n";

    md << "### Which of the paper's directions each variant reproduces\n\n";
    md << "| Fig. | the paper says |";
    for (const FrictionVariant& v : R.friction)
        md << " " << ma_text(v.asperity_factor) << (v.asperity_factor == 1.0 ? " (paper)" : "")
           << " |";
    md << " mechanism where the verdicts differ |\n|---|---|";
    for (std::size_t k = 0; k < R.friction.size(); ++k) md << "---|";
    md << "---|\n";
    for (std::size_t i = 0; i < R.figures.size(); ++i) {
        const SweepFigure& fig = R.figures[i];
        md << "| " << fig.number << " | " << fig.claim << " |";
        for (const FrictionVariant& v : R.friction)
            md << " " << sweep_cell(v.sweeps[i], fig) << " |";
        md << " " << sweep_mechanism(R, i) << " |\n";
    }
    {
        md << "| 13 | the amplitude rises with speed |";
        bool differs = false;
        for (const FrictionVariant& v : R.friction) {
            md << " " << amplitude_cell(v.amplitude) << " |";
            differs = differs || v.amplitude.trend.verdict != R.friction[0].amplitude.trend.verdict;
        }
        md << " " << (differs ? "see the plot" : "same verdict for every m_a") << " |\n";
    }
    for (int figure : {14, 15}) {
        md << "| " << figure << " | "
           << (figure == 14
                   ? "compressive stress rises with roughness, strongly at high back tension; the curves "
                     "coincide at T = 0.75"
                   : "friction stress rises with roughness and is more sensitive to it than to back "
                     "tension")
           << " |";
        std::vector<std::string> verdicts;
        for (const FrictionVariant& v : R.friction) {
            const CycleChecks c = check_cycles(v.cycles);
            md << " " << cycle_cell(c, figure) << " |";
            verdicts.push_back(figure == 14 ? fig14_verdict(c) : fig15_verdict(c));
        }
        const bool differs =
            std::any_of(verdicts.begin(), verdicts.end(),
                        [&](const std::string& s) { return s != verdicts.front(); });
        md << " "
           << (differs ? "the verdict's checks are in the cell" : "same verdict for every m_a")
           << " |\n";
    }
    md << "\n";
    md << "**Plots** (every m_a on one plot):\n\n";
    for (const SweepFigure& fig : R.figures)
        md << out.image(friction_sweep_plot(fig),
                        "Fig. " + std::to_string(fig.number) + ", boundary-friction variants")
           << "\n";
    md << out.image(friction_amplitude_plot, "Fig. 13, boundary-friction variants") << "\n\n";
    md << "Figs. 14–15 of each variant: ";
    bool first = true;
    for (const FrictionVariant& v : R.friction) {
        if (v.asperity_factor == 1.0) continue;
        for (int figure : {14, 15}) {
            const std::string name = "fig" + std::to_string(figure) + "_paper" +
                                     variant_suffix(v.asperity_factor) + ".svg";
            md << (first ? "" : ", ") << "[Fig. " << figure << ", " << ma_text(v.asperity_factor)
               << "](" << out.link << "/" << name << ")";
            first = false;
        }
    }
    md << ". The CSV files of the variants carry the suffix `_ma0.7`, `_ma0.3` (same columns as the paper's).\n\n";
}

}  // namespace rollgap::tools::paper
