// The report on the two inlet film models.

#include "tools/reproduce_paper/markdown_sections.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tools/reproduce_paper/markdown_cells.h"

namespace rollgap::tools::paper {

// The paper's inlet film against the frame-corrected (eulerian) one.
void md_film_comparison(std::ostringstream& md, const Results& R, const Output& out) {
    // ----- Paper vs eulerian
    {
        md << "## Paper vs eulerian inlet film\n\n";
        md << out.image("stability_defaults.svg", "growth rate over speed at the defaults")
           << "\n\n";
        const auto& m = R.map;
        md << "| configuration (defaults) | critical speed | largest Re λ over 1–60 m/s | smallest Re λ over 1–60 m/s |\n|---|---|---|---|\n";
        for (std::size_t k = 0; k < m.results.size(); ++k) {
            double lo = INFINITY, hi = -INFINITY, v_lo = no_value, v_hi = no_value;
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
            md << "| " << m.labels[k] << " | " << critical_text(m.results[k]) << " | " << fmt(hi, 1)
               << " 1/s at " << fmt(v_hi, 1) << " m/s | " << fmt(lo, 1) << " 1/s at "
               << fmt(v_lo, 1) << " m/s |\n";
        }
        // where the eulerian with constant tension becomes stable
        double restabilise = no_value;
        {
            const auto& scan = m.results[3].scan;
            for (std::size_t k = 1; k < scan.size(); ++k) {
                if (!scan[k - 1].stable && scan[k].stable) {
                    restabilise = scan[k].speed;
                    break;
                }
            }
        }
        md << "\ndocs/model.md §2 predicts that the eulerian film makes a ~450 Hz mode unstable at every speed at the defaults. "
              "**Confirmed, with a qualification:** with the default entry-span tension no speed in 1–60 m/s is stable "
              "(in the table above, even the smallest of the largest growth rates is positive). The unstable mode is the two work rolls moving "
              "against each other between the backup rolls ";
        const auto& he = R.high_mode_eulerian.rows;
        const auto& hp = R.high_mode_paper.rows;
        if (!he.empty())
            md << "(" << fmt(he.back().frequency_Hz, 0) << "–" << fmt(he.front().frequency_Hz, 0)
               << " Hz over the speeds below)";
        md << ". With a constant back tension the film squeeze alone is unstable from 1 m/s up to ";
        md << (std::isfinite(restabilise)
                   ? fmt(restabilise, 1) +
                         " m/s, where the bite approaches full film and it becomes stable"
                   : "the end of the range")
           << "; with the entry span, the ~104 Hz gap mode becomes unstable from "
           << fmt(gap_mode_crossing(m.results[2]).speed, 1)
           << " m/s (and later the ~400 Hz mode), before the squeeze instability has ended: the two overlap and leave no "
              "stable window (smallest largest growth rate "
           <<
            [&] {
                double lo = INFINITY;
                for (const auto& q : m.results[2].scan) {
                    if (q.status == core::DynamicsStatus::ok) lo = std::min(lo, q.max_real_part);
                }
                return fmt(lo, 1);
            }()
           << " 1/s).\n\n";
        md << "| v (m/s) | mode (Hz) | A max | Re λ eulerian (1/s) | Re λ paper, same mode (1/s) | film-path damper eulerian "
              "(MN·s/m) | film-path damper paper (MN·s/m) | squeeze estimate abs(∂P/∂h0)·h0/(2θū1) (MN·s/m) | gap mass (t) |\n"
              "|---|---|---|---|---|---|---|---|---|\n";
        for (std::size_t k = 0; k < he.size() && k < hp.size(); ++k) {
            md << "| " << fmt(he[k].speed, 0) << " | " << fmt(he[k].frequency_Hz, 0) << " | "
               << fmt(he[k].contact_ratio_max, 3) << " | " << fmt(he[k].growth_rate, 1) << " | "
               << fmt(hp[k].growth_rate, 1) << " | " << fmt(he[k].film_damping * 1e-6, 2) << " | "
               << fmt(hp[k].film_damping * 1e-6, 2) << " | "
               << fmt(he[k].squeeze_estimate * 1e-6, 2) << " | " << fmt(he[k].gap_mass * 1e-3, 1)
               << " |\n";
        }
        md << "\n**Mechanism.** The eulerian film equation has the squeeze term −ẏc/2: an opening gap thins the inlet film, a "
              "thinner film raises asperity contact and friction, and the force rises while the gap opens — a negative "
              "damper across the gap of about abs(∂P/∂h0)·h0/(2θū1) (docs/model.md §2; the *squeeze estimate* column, which the "
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
               << " MN·s/m — a sixth of the tension loop's — but it acts on the "
               << fmt(e19->frequency_Hz, 0)
               << " Hz mode of the two work rolls moving against each other, whose gap mass is "
               << fmt(e19->gap_mass * 1e-3, 1)
               << " t (against ≈ 170 t for the ~104 Hz mode): the change of film-path damper from the paper film to the "
                  "eulerian film, "
               << fmt((p19->film_damping - e19->film_damping) * 1e-6, 2)
               << " MN·s/m, shifts that mode's "
                  "growth rate by about Δc/(2·m_gap) = "
               << fmt(shift, 0) << " 1/s (the eigenvalues: " << fmt(p19->growth_rate, 1) << " → "
               << fmt(e19->growth_rate, 1) << " 1/s), far beyond its structural damping. ";
        }
        md << "The lever ∂P/∂h0 is large in the mixed regime at low speed (large A) and vanishes in full film (A → 0), hence "
              "the growth rate falls with speed, and rough surfaces keep the instability to higher speeds than smooth ones.\n\n";
        md << "**Where the two film models differ in the figures:**\n\n";
        md << "- Figs. 8–12: the paper film has a critical speed at almost every point; the eulerian film has none (unstable at "
              "1 m/s everywhere). The ~100 Hz gap mode alone crosses zero somewhat earlier with the eulerian film (e.g. ";
        {
            const GapModeCrossing q = gap_mode_crossing(m.results[2]);
            md << fmt(q.speed, 1) << " against " << fmt(m.results[0].critical_speed, 1)
               << " m/s at the defaults";
        }
        md << "): its squeeze damper removes damping from that mode as well.\n";
        md << "- Fig. 13: no eulerian run lasts longer than a few tens of milliseconds.\n";
        md << "- Figs. 14–15: identical where the bite is in full film (Rq = 1 µm); no result where it is mixed (Rq = 6 µm).\n\n";
        md << "Real mills roll at these conditions without a 450–550 Hz instability, so the eulerian variant — as docs/model.md §2 "
              "says — needs calibration (e.g. of how quickly the inlet film can follow the gap) before it can be used for "
              "critical speeds.\n\n";
    }
}

}  // namespace rollgap::tools::paper
