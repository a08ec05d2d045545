#pragma once
// The boundary-friction variant (docs/model.md §10.4): Figs. 8-15 rerun, paper film, with the
// asperity factor m_a below the paper's 1 (boundary-lubricated asperities shear at a fraction of
// the strip's shear yield stress), beside the paper's own runs, and the steady roll force over
// speed that the asperity factor sets. Labelled as a variant everywhere: the paper's default
// (m_a = 1) is what every other section of the report runs.
#include <array>
#include <string>
#include <vector>

#include "core/roll_bite.h"
#include "tools/reproduce_paper/amplitude_figure.h"
#include "tools/reproduce_paper/cycle_figures.h"
#include "tools/reproduce_paper/output.h"
#include "tools/reproduce_paper/sweep_figures.h"

namespace rollgap::tools::paper {

// The variants beside the paper's m_a = 1 (docs/model.md §10.4 gives the reasons for the values).
inline constexpr double boundary_asperity_factors[] = {0.7, 0.3};
// Speeds at which the report gives the steady roll force of the default stand.
inline constexpr double force_speeds[] = {1.0, 5.0, 10.0, 19.0};

struct SteadyBite {
    double speed = 0.0;
    core::BiteStatus status = core::BiteStatus::solver_failure;
    double force = no_value;          // N
    double mean_friction = no_value;  // int |tau| dx / int p dx
};

struct FrictionVariant {
    double asperity_factor = 1.0;
    std::vector<SweepRun> sweeps;   // Figs. 8-12, in the order of sweep_figures(), paper film
    AmplitudeRun amplitude;         // Fig. 13, paper film
    CycleRun cycles;                // Figs. 14-15, paper film
    std::vector<SteadyBite> bites;  // the default stand at force_speeds
    double seconds = 0.0;
};

// The default stand's steady bite at force_speeds with asperity factor m_a.
std::vector<SteadyBite> steady_bites(double asperity_factor, const core::Control& compute);
// Figs. 8-15 (paper film) and the steady bites with asperity factor m_a.
FrictionVariant run_friction_variant(const std::vector<SweepFigure>& figures,
                                     double asperity_factor, const core::Control& compute);
// The paper's runs (m_a = 1, already computed for the main report) as the reference variant.
FrictionVariant paper_friction_reference(const std::vector<std::array<SweepRun, 2>>& sweeps,
                                         const AmplitudeRun& amplitude, const CycleRun& cycles,
                                         const core::Control& compute);
// The variants' CSV files and plots; variants[0] is the m_a = 1 reference (its own files are
// the main report's and are not written again), the plots overlay every variant.
void write_friction_variant_outputs(Output& out, const std::vector<SweepFigure>& figures,
                                    const std::vector<FrictionVariant>& variants);
// File names of the overlay plots.
std::string friction_sweep_plot(const SweepFigure& fig);
inline constexpr const char* friction_amplitude_plot = "fig13_boundary_friction.svg";

}  // namespace rollgap::tools::paper
