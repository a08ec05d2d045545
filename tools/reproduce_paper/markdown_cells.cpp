#include "tools/reproduce_paper/markdown_cells.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace rollgap::tools::paper {

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
    if (t.verdict == "partly agrees")
        return "**partly** (" + fmt(t.agreeing_fraction * 100, 0) + " % of the range)";
    return t.verdict;
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
    if (run.found > 0)
        text += std::to_string(run.found) + " of " + std::to_string(run.points.size()) +
                " points have a critical speed; ";
    if (lower > 0) {
        text += std::to_string(lower) + " of " + std::to_string(run.points.size()) +
                " points are unstable already at the lower bound 1 m/s (mode " + fmt(f_lo, 0) +
                "–" + fmt(f_hi, 0) + " Hz, growth rate " + fmt(g_lo, 0) + "–" + fmt(g_hi, 0) +
                " 1/s at 1 m/s)";
    }
    return text;
}

void md_sweep_table(std::ostringstream& md, const SweepFigure& fig, const Results& R,
                    std::size_t index) {
    const SweepRun& paper = R.sweeps[index][0];
    const SweepRun& euler = R.sweeps[index][1];
    const auto coulomb = R.coulomb.find(fig.number);
    const bool with_coulomb = coulomb != R.coulomb.end();
    md << "| " << fig.x_label()
       << " | paper film: status | v_c (m/s) | mode (Hz) | μ at v_c | H_t at v_c | A max | "
       << "k4 (GN/m) | gap mass (t) | Re λ, tension held (1/s) |";
    if (with_coulomb) md << " v_c, Coulomb μ = " << fmt(R.coulomb_mu, 2) << " (m/s) |";
    md << " eulerian film: status | mode at 1 m/s: Hz, 1/s | ~100 Hz mode crosses (m/s) |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|" << (with_coulomb ? "---|" : "")
       << "---|---|---|\n";
    for (std::size_t i = 0; i < fig.xs.size(); ++i) {
        const SweepPoint& p = paper.points[i];
        const SweepPoint& e = euler.points[i];
        const ModeDiagnostics& d = p.diag;
        const bool found = p.result.status == CriticalSpeedStatus::found;
        md << "| " << fmt(fig.xs[i], fig.x_decimals) << " | " << status_cell(p.result) << " | "
           << (found ? fmt(p.result.critical_speed, 2) : "–") << " | "
           << (found || p.result.status == CriticalSpeedStatus::unstable_at_lower_bound
                   ? fmt(p.result.unstable_mode.frequency_Hz, 0)
                   : "–")
           << " | " << fmt(d.mean_friction, 3) << " | "
           << regime_text(d.film_ratio_min, d.film_ratio_max) << " | "
           << fmt(d.contact_ratio_max, 3) << " | " << fmt(d.strip_stiffness * 1e-9, 1) << " | "
           << fmt(d.gap_mass * 1e-3, 0) << " | " << fmt(d.growth_constant_tension, 1) << " |";
        if (with_coulomb) {
            const auto& c = coulomb->second.points[i].result;
            md << " "
               << (c.status == CriticalSpeedStatus::found ? fmt(c.critical_speed, 2)
                                                          : status_cell(c))
               << " |";
        }
        md << " " << status_cell(e.result) << " | ";
        if (e.result.status == CriticalSpeedStatus::unstable_at_lower_bound) {
            md << fmt(e.result.unstable_mode.frequency_Hz, 0) << ", "
               << fmt(e.result.unstable_mode.eigenvalue.real(), 0);
        } else if (e.result.status == CriticalSpeedStatus::found) {
            md << "v_c = " << fmt(e.result.critical_speed, 2) << " m/s";
        } else {
            md << "–";
        }
        md << " | "
           << (e.gap_mode.status == "found"
                   ? fmt(e.gap_mode.speed, 1) +
                         (std::isfinite(e.gap_mode.unstable_below)
                              ? " (also unstable below " + fmt(e.gap_mode.unstable_below, 1) + ")"
                              : "")
               : e.gap_mode.status == "stable_in_range"         ? "> 60"
               : e.gap_mode.status == "unstable_at_lower_bound" ? "< 1"
                                                                : "–")
           << " |\n";
    }
    md << "\n";
}

void md_diag_row(std::ostringstream& md, const ModeDiagnostics& d, bool with_loop) {
    md << "| " << fmt(d.speed, 2) << " | " << fmt(d.frequency_Hz, 1) << " | "
       << fmt(d.mean_friction, 3) << " | " << regime_text(d.film_ratio_min, d.film_ratio_max)
       << " | " << fmt(d.contact_ratio_max, 3) << " | " << fmt(d.inlet_film * 1e6, 2) << " | "
       << fmt(d.strip_stiffness * 1e-9, 1) << " | " << fmt(d.gap_mass * 1e-3, 0) << " | "
       << fmt(d.growth_rate, 2) << " | " << fmt(d.growth_constant_tension, 2) << " | "
       << fmt(d.growth_frozen_film, 2) << " | ";
    if (with_loop) md << fmt(d.loop_damping * 1e-6, 2) << " | ";
    md << fmt(d.film_damping * 1e-6, 2) << " |\n";
}

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

CycleChecks check_cycles(const CycleRun& run) {
    CycleChecks c;
    if (run.cases.size() != 2 || run.cases[0].phases.size() != 3 || run.cases[1].phases.size() != 3)
        return c;
    c.available = true;
    const auto& a = run.cases[0].phases;  // Rq 1
    const auto& b = run.cases[1].phases;  // Rq 6
    c.dP_high = b[0].force - a[0].force;
    c.dP_mid = b[1].force - a[1].force;
    c.dP_low = b[2].force - a[2].force;
    c.mean_p_ratio_low = b[2].mean_pressure / a[2].mean_pressure;
    c.peak_p_ratio_low = b[2].peak_pressure / a[2].peak_pressure;
    for (int k = 0; k < 3; ++k) {
        if (!(b[k].force > a[k].force && b[k].mean_pressure > a[k].mean_pressure))
            c.rough_higher_everywhere = false;
        const double ratio = b[k].mean_friction_stress / a[k].mean_friction_stress;
        c.friction_ratio_min = std::min(c.friction_ratio_min, ratio);
        c.friction_ratio_max = std::max(c.friction_ratio_max, ratio);
        c.roughness_effect_on_friction = std::min(c.roughness_effect_on_friction, ratio - 1.0);
    }
    for (const auto* p : {&a, &b}) {
        if (!((*p)[0].force < (*p)[2].force)) c.tension_lowers_pressure = false;
        c.tension_effect_on_friction =
            std::max(c.tension_effect_on_friction,
                     std::abs((*p)[0].mean_friction_stress - (*p)[2].mean_friction_stress) /
                         (*p)[1].mean_friction_stress);
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
            md << "| " << fmt(c.rq_um, 0) << " | " << fmt(m.phase, 2) << " | "
               << fmt(m.back_tension * 1e-6, 1) << " | " << fmt(m.gap * 1e6, 2) << " | "
               << fmt(m.inlet_film * 1e6, 3) << " | " << fmt(m.film_ratio_min, 2) << "–"
               << fmt(m.film_ratio_max, 2) << " | " << fmt(m.contact_ratio_max, 3) << " | "
               << fmt(m.force * 1e-6, 3) << " | " << fmt(m.mean_pressure * 1e-6, 1) << " | "
               << fmt(m.peak_pressure * 1e-6, 1) << " | " << fmt(m.mean_friction_stress * 1e-6, 1)
               << " | " << fmt(m.peak_friction * 1e-6, 1) << " | " << fmt(m.neutral_point * 1e3, 2)
               << " |\n";
        }
    }
    md << "\n";
}

}  // namespace rollgap::tools::paper
