#pragma once
// Everything the reproduction computed, as the report reads it.

#include <array>
#include <map>
#include <vector>

#include "tools/reproduce_paper/amplitude_figure.h"
#include "tools/reproduce_paper/boundary_friction.h"
#include "tools/reproduce_paper/cycle_figures.h"
#include "tools/reproduce_paper/mechanism.h"
#include "tools/reproduce_paper/sweep_figures.h"

namespace rollgap::tools::paper {

struct Results {
    std::vector<SweepFigure> figures;
    std::vector<std::array<SweepRun, 2>> sweeps;  // per figure: paper, eulerian
    std::map<int, SweepRun> coulomb;  // Figs. 9, 10, 12 with a fixed friction coefficient
    double coulomb_mu = 0.07;
    std::array<AmplitudeRun, 2> amplitude;
    std::array<CycleRun, 2> cycles;
    SpeedDiagnostics defaults_gap_mode;  // paper film, ~104 Hz mode over speed
    std::vector<VariantResult> variants;
    std::vector<double> coulomb_mus;
    std::vector<VariantResult> coulomb_variants;
    std::vector<ModeDiagnostics> coulomb_diag;  // at 15 m/s, ~104 Hz mode
    SpeedDiagnostics high_mode_eulerian,
        high_mode_paper;  // the eulerian's least-damped mode, both films
    StabilityMap map;
    // The boundary-friction variant: [0] the paper's m_a = 1 runs above, then m_a < 1.
    std::vector<FrictionVariant> friction;
    double seconds = 0.0;
    int threads = 1;
};

}  // namespace rollgap::tools::paper
