// The report on the critical speed: what sets it at the defaults and Figs. 8-12.

#include "tools/reproduce_paper/markdown_sections.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tools/reproduce_paper/markdown_cells.h"

namespace rollgap::tools::paper {

std::string md_figure_mechanism(const SweepFigure& fig, const Results& R, std::size_t index) {
    const SweepRun& paper = R.sweeps[index][0];
    std::ostringstream md;
    const Scenario defaults;
    const SweepPoint* def = nullptr;  // the point at the default scenario, if the sweep has it
    for (const auto& p : paper.points) {
        Scenario s;
        fig.apply(s, p.x);
        const Scenario& d = defaults;
        if (std::abs(s.strip.entry_thickness - d.strip.entry_thickness) < 1e-9 &&
            std::abs(s.strip.reduction - d.strip.reduction) < 1e-9 &&
            std::abs(s.rolls.radius - d.rolls.radius) < 1e-9 &&
            std::abs(s.lubricant.viscosity - d.lubricant.viscosity) < 1e-12 &&
            std::abs(std::hypot(s.roughness.roll_rq, s.roughness.strip_rq) -
                     std::hypot(d.roughness.roll_rq, d.roughness.strip_rq)) < 1e-9) {
            def = &p;
        }
    }
    auto point_text = [&](const SweepPoint& p) {
        const ModeDiagnostics& d = p.diag;
        std::string text = fig.x_symbol + " = " + fig.x_text(p.x) +
                           ": v_c = " + fmt(p.result.critical_speed, 2) + " m/s";
        if (p.result.unstable_mode.frequency_Hz > 200.0)
            text += " (" + fmt(p.result.unstable_mode.frequency_Hz, 0) + " Hz mode)";
        return text + ", θ = " + fmt(d.inlet_angle * 1e3, 1) +
               " mrad, h00 = " + fmt(d.inlet_film * 1e6, 2) +
               " µm, H_t = " + fmt(d.film_ratio_min, 2) + "–" + fmt(d.film_ratio_max, 2) +
               ", A ≤ " + fmt(d.contact_ratio_max, 3) + ", μ = " + fmt(d.mean_friction, 3) +
               ", k4 = " + fmt(d.strip_stiffness * 1e-9, 1) + " GN/m, gap mass " +
               fmt(d.gap_mass * 1e-3, 0) + " t, |∂P/∂s_b| = " + fmt(std::abs(d.dP_dback) * 1e3, 1) +
               "·10⁻³ m²";
    };
    const Trend& t = paper.trend;
    const auto coulomb = R.coulomb.find(fig.number);
    std::string coulomb_text;
    if (coulomb != R.coulomb.end()) {
        coulomb_text =
            "With the friction coefficient held fixed (verification friction law `coulomb`, μ = " +
            fmt(R.coulomb_mu, 2) + "; a diagnostic variant, not the model) the critical speed is " +
            coulomb->second.trend.direction + ", i.e. it **" +
            (coulomb->second.trend.verdict == "agrees" ? "follows" : "does not follow") +
            "** the paper's direction.";
    }
    // found points in x order; the first and last, the lowest, and the first/last crossing through
    // the ~100 Hz mode
    std::vector<const SweepPoint*> found;
    for (const auto& p : paper.points) {
        if (p.result.status == CriticalSpeedStatus::found) found.push_back(&p);
    }
    if (found.empty()) return "";
    const SweepPoint* first = found.front();
    const SweepPoint* last = found.back();
    const SweepPoint* lowest =
        *std::min_element(found.begin(), found.end(), [](const SweepPoint* a, const SweepPoint* b) {
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
            return paper.points[i].result.status == CriticalSpeedStatus::found &&
                   std::abs(paper.points[i].result.critical_speed / v0 - 1.0) <= 0.02;
        };
        while (lo > 0 && within(lo - 1)) --lo;
        while (hi + 1 < paper.points.size() && within(hi + 1)) ++hi;
        band = fig.x_symbol + " = " + fmt(paper.points[lo].x, fig.x_decimals) + "–" +
               fig.x_text(paper.points[hi].x);
    }

    switch (fig.number) {
        case 8: {
            md << "**Why (paper film).** The viscosity acts only through the inlet film (docs/model.md §4: with the printed γ the "
                  "fluid shear in the bite is capped at λ_L·p everywhere). A thicker film means fewer asperity contacts and a "
                  "lower friction coefficient, and a lower friction coefficient lowers the critical speed (see *What sets the "
                  "critical speed*): ";
            if (first_gap) md << point_text(*first_gap) << "; ";
            md << point_text(*last)
               << ". That is the paper's chain (film ↑ → contact ratio ↓ → stability ↓), but the "
                  "destabilising element is the entry-span tension loop; friction decides how much of the gap mode it can "
                  "reach. Once the bite is in full film at the critical speed (A → 0, μ → λ_L = 0.05) the curve runs into a "
                  "floor of ≈ "
               << fmt(last->result.critical_speed, 1)
               << " m/s, the full-film critical speed: beyond that, η0 changes nothing the dynamics depend on.";
            if (first->result.unstable_mode.frequency_Hz > 200.0) {
                md << " At " << fig.x_text(first->x)
                   << " the friction is so high (μ = " << fmt(first->diag.mean_friction, 3)
                   << ") that the ~104 Hz mode stays stable beyond "
                   << fmt(first->result.critical_speed, 0) << " m/s and the "
                   << fmt(first->result.unstable_mode.frequency_Hz, 0)
                   << " Hz mode (the two work rolls moving against each other, gap mass "
                   << fmt(first->diag.gap_mass * 1e-3, 0) << " t) crosses first.";
            }
            md << "\n\n";
            break;
        }
        case 9:
        case 10: {
            // Fig. 9: small y2 = large reduction (the first point); Fig. 10: large y1 = large
            // reduction (the last)
            const SweepPoint* large = fig.number == 9 ? first : last;
            const SweepPoint* small = fig.number == 9 ? last : first;
            if (t.verdict == "agrees") {
                md << "**Why (paper film).** " << coulomb_text << "\n\n";
                break;
            }
            md << "**Mechanism of the disagreement (paper film).** The curve has a minimum of "
               << speed_text(t.y_min) << " at " << fig.x_text(t.x_at_min) << ". On its "
               << (fig.number == 9 ? "thin-exit" : "thick-entry")
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
            md << "Numbers at the critical speed — largest reduction: " << point_text(*large)
               << "; at the minimum: " << point_text(*lowest);
            if (def) md << "; at the defaults: " << point_text(*def);
            md << "; smallest reduction: " << point_text(*small) << ".\n\n";
            md << "At large reductions the friction effect outweighs the geometric one. At small reductions the bite is in "
                  "full film already (A = 0, μ = λ_L): friction cannot fall any further, the geometric effect is all that is "
                  "left, and the model agrees with the paper, steeply — until, at the smallest reductions, the "
               << fmt(small->result.unstable_mode.frequency_Hz, 0)
               << " Hz work-roll mode crosses first or no mode crosses "
                  "below 60 m/s. In between, around the defaults, the two effects almost cancel";
            if (!band.empty())
                md << ": the critical speed stays within ±2 % of the default's for " << band;
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
            md << "**Mechanism (paper film).** The model's curve is " << t.direction
               << ". The radius has the same two "
                  "competing effects as the reduction (Figs. 9–10). A larger radius lengthens the contact (x_w = √(a·Δy)), "
                  "which strengthens the back-tension lever. "
               << coulomb_text
               << " But a larger radius also flattens the inlet "
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

// What sets the critical speed at the defaults: the crossing mode followed over speed.
void md_critical_speed(std::ostringstream& md, const Results& R) {
    const Scenario defaults;
    const core::CriticalSpeedResult& vc_default = R.variants.front().result;
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
        md << "1. **The destabilising element is the entry-span tension loop** (docs/model.md §6 [extension], the \"negative damping "
              "generated by the inlet tension\" of the paper's Section 6.1). With the back tension held constant the mode's "
              "growth rate is "
           << fmt(held_lo, 1) << " to " << fmt(held_hi, 1)
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
                  "∂u1/∂g = "
               << fmt(at_vc->du1_dgap * defaults.strip.entry_thickness / at_vc->speed, 2)
               << "·v/y1 (mass flow). The entry span integrates the speed difference, ṡ_b = (E/L_b)(u1 − u1_ref) with "
                  "E/L_b = "
               << fmt(EL * 1e-9, 0)
               << " GPa/m, so the back tension lags the gap by about a quarter period "
                  "(the span's own relaxation, "
               << fmt(at_vc->tension_pole, 0) << " 1/s, is slow against ω = " << fmt(w, 0)
               << " 1/s). A higher back tension lowers the force (∂P/∂s_b = "
               << fmtg(at_vc->dP_dback, 3) << " m², about "
               << fmt(std::abs(at_vc->dP_dback) / (defaults.strip.width * at_vc->contact_length), 2)
               << "·w·x_w). A force that lags the gap by 90° and pushes it further open is a negative damper: "
                  "|∂P/∂s_b|·(E/L_b)·(∂u1/∂g)/ω² ≈ "
               << fmt(estimate * 1e-6, 1)
               << " MN·s/m at v_c (the full calculation, "
                  "with the span relaxation and the film coupling: "
               << fmt(at_vc->loop_damping * 1e-6, 1)
               << " MN·s/m). Because ∂u1/∂g ∝ v, **the loop's negative damping grows in proportion to the speed**; the "
                  "critical speed is where it has eaten the structure's damping. The mode's growth rate moves by about "
                  "−c/(2·m_gap) = "
               << fmt(-at_vc->loop_damping / (2.0 * at_vc->gap_mass), 0) << " 1/s for the loop's c "
               << "(the eigenvalue calculation: "
               << fmt(at_vc->growth_rate - at_vc->growth_constant_tension, 1) << " 1/s).\n";
        }
        md << "3. **The number 20 m/s comes from the model document's assumptions, not from the paper.** The balance is between the "
              "structural damping (Rayleigh, an [extension]) and the loop gain E/L_b (the entry-span length L_b = 5 m is an "
              "[extension] as well):\n\n";
        md << "| variant (diagnostic, not the model) | critical speed |\n|---|---|\n";
        for (const auto& v : R.variants)
            md << "| " << v.label << " | " << critical_text(v.result) << " |\n";
        md << "\n4. **Friction sets the loop's leverage.** With a fixed friction coefficient (verification law `coulomb`) "
              "the critical speed rises steeply with μ; the table gives the ~104 Hz mode at 15 m/s for each μ:\n\n";
        md << "| Coulomb μ | critical speed | k4 at 15 m/s (GN/m) | gap mass (t) | tension-loop damper (MN·s/m) | "
              "Re λ (1/s) | Re λ, tension held (1/s) |\n|---|---|---|---|---|---|---|\n";
        for (std::size_t k = 0; k < R.coulomb_mus.size(); ++k) {
            const ModeDiagnostics& d = R.coulomb_diag[k];
            md << "| " << fmt(R.coulomb_mus[k], 2) << " | "
               << critical_text(R.coulomb_variants[k].result) << " | "
               << fmt(d.strip_stiffness * 1e-9, 1) << " | " << fmt(d.gap_mass * 1e-3, 0) << " | "
               << fmt(d.loop_damping * 1e-6, 2) << " | " << fmt(d.growth_rate, 1) << " | "
               << fmt(d.growth_constant_tension, 1) << " |\n";
        }
        if (!R.coulomb_diag.empty()) {
            const auto& lo = R.coulomb_diag.front();
            const auto& hi = R.coulomb_diag.back();
            md << "\nThe loop's damper barely changes with friction ("
               << fmt(lo.loop_damping * 1e-6, 1) << " → " << fmt(hi.loop_damping * 1e-6, 1)
               << " MN·s/m), but the strip stiffness does (" << fmt(lo.strip_stiffness * 1e-9, 1)
               << " → " << fmt(hi.strip_stiffness * 1e-9, 1)
               << " GN/m): with more friction the force depends more on the exit "
                  "thickness (a steeper friction hill). A stiffer strip couples the work rolls more rigidly, the ~104 Hz mode "
                  "becomes a motion of the heavy backup rolls and crossheads with less relative work-roll motion — the gap mass "
               << "rises from " << fmt(lo.gap_mass * 1e-3, 0) << " to "
               << fmt(hi.gap_mass * 1e-3, 0)
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
}

// Figs. 8-12, one section each.
void md_sweep_figures(std::ostringstream& md, const Results& R, const Output& out) {
    // ----- Figs. 8-12
    for (std::size_t i = 0; i < R.figures.size(); ++i) {
        const SweepFigure& fig = R.figures[i];
        const SweepRun& p = R.sweeps[i][0];
        const SweepRun& e = R.sweeps[i][1];
        md << "## Fig. " << fig.number << ": critical speed vs " << fig.quantity << "\n\n";
        md << "**The paper:** \"" << fig.claim_quote << "\" — i.e. " << fig.claim << ".\n\n";
        md << "**Setup:** " << fig.setup << ".\n\n";
        md << out.image(fig.id + "_paper.svg",
                        "Fig. " + std::to_string(fig.number) + ", paper film")
           << "\n"
           << out.image(fig.id + "_eulerian.svg",
                        "Fig. " + std::to_string(fig.number) + ", eulerian film")
           << "\n\n";
        md << "**Paper film — the model:** " << p.trend.direction
           << ". **Verdict: " << p.trend.verdict << "**";
        if (p.trend.verdict == "partly agrees")
            md << " (the paper's direction over " << fmt(p.trend.agreeing_fraction * 100, 0)
               << " % of the range)";
        md << ".";
        int not_found = 0;
        for (const auto& q : p.points)
            not_found += q.result.status == CriticalSpeedStatus::found ? 0 : 1;
        if (not_found > 0)
            md << " Points without a critical speed (counted at the end of the search range for the direction): "
               << not_found << ".";
        md << "\n\n";
        md << "**Eulerian film — the model:** " << eulerian_summary(e)
           << ". No critical speed to compare: **not testable**. "
           << "The ~100 Hz gap mode on its own crosses zero at a speed that is "
           << e.gap_trend.direction << " (" << e.gap_trend.verdict
           << " with the paper's direction).\n\n";
        md << md_figure_mechanism(fig, R, i);
        md << "<details><summary>Table: the curve and the state at the critical speed (CSV: `"
           << fig.id << "_paper.csv`, `" << fig.id << "_eulerian.csv`)</summary>\n\n";
        md_sweep_table(md, fig, R, i);
        md << "</details>\n\n";
    }
}

}  // namespace rollgap::tools::paper
