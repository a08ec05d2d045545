#pragma once
// Distributions over a sinusoidal back-tension cycle (docs/model.md §7.2, the paper's Figs. 14-15):
// the coupled model is run over whole cycles and the bite is resolved at the requested phases
// of the last one.

#include <vector>

#include "core/control.h"
#include "core/coupled_model.h"
#include "core/roll_bite.h"
#include "core/scenario.h"

namespace rollgap::core {

struct TensionCycleOptions {
    int cycles = 2;                               // the first ones let the start-up transient pass
    std::vector<double> phases{0.25, 0.5, 0.75};  // T in [0, 1): s_b = mean + amplitude sin(2 pi T)
    double relative_tolerance = 1e-6;
};

struct PhaseDistribution {
    double phase = 0.0;
    double time = 0.0;          // s
    double back_tension = 0.0;  // Pa, as the bite sees it
    double gap = 0.0;           // m, x3 - x4
    double inlet_film = 0.0;    // m, h0 of the state
    BiteResult bite;            // with distributions
};

struct TensionCycleResult {
    DynamicsStatus status = DynamicsStatus::solver_failure;
    const char* message = "";
    BiteStatus steady_status = BiteStatus::solver_failure;
    double frequency_Hz = 0.0;
    std::vector<PhaseDistribution> phases;
};

// The scenario's back tension is run in sinusoid mode (its mean, amplitude and frequency),
// whatever mode the scenario names.
TensionCycleResult tension_cycle(Scenario s, const TensionCycleOptions& options = {},
                                 const Control& control = {});

}  // namespace rollgap::core
