#pragma once
// Figs. 14-15: the bite's compressive and friction stress over a sinusoidal back-tension cycle,
// at two roughnesses, per inlet film model.
#include <string>
#include <vector>

#include "core/control.h"
#include "core/stability.h"
#include "core/tension_cycle.h"
#include "tools/reproduce_paper/output.h"

namespace rollgap::tools::paper {

struct PhaseSummary {
    double phase, back_tension, gap, inlet_film, force, peak_pressure, mean_pressure, peak_friction,
        mean_friction_stress;
    double film_ratio_min, film_ratio_max, contact_ratio_max, neutral_point, contact_length;
};

struct CycleCase {
    double rq_um = 0.0;
    core::TensionCycleResult result;
    core::SpeedStability
        input_tension;  // linear stability with the back tension as an input (no span state)
    std::vector<PhaseSummary> phases;
};

struct CycleRun {
    InletFilmModel film = InletFilmModel::paper;
    double asperity_factor = 1.0;  // m_a of the run (docs/model.md §4; 1 is the paper's)
    std::vector<CycleCase> cases;  // Rq = 1, 6 µm
    double seconds = 0.0;
};

Scenario cycle_scenario(InletFilmModel film, double rq_um, double asperity_factor = 1.0);
CycleRun run_cycles(InletFilmModel film, const core::Control& compute,
                    double asperity_factor = 1.0);
std::string rq_label(double rq);
void write_cycle_outputs(Output& out, const CycleRun& run);

}  // namespace rollgap::tools::paper
