#pragma once
// Fig. 13: the vibration amplitude against the rolling speed, per inlet film model.
#include <vector>

#include "core/control.h"
#include "core/amplitude.h"
#include "core/stability.h"
#include "tools/reproduce_paper/output.h"
#include "tools/reproduce_paper/trend.h"

namespace rollgap::tools::paper {

struct AmplitudeRun {
    InletFilmModel film = InletFilmModel::paper;
    double asperity_factor = 1.0;  // m_a of the run (docs/model.md §4; 1 is the paper's)
    std::vector<double> speeds;
    std::vector<core::AmplitudeResult> results;
    core::CriticalSpeedResult critical;  // of the default scenario, for the reference line
    Trend trend;                         // of x3 over the runs that completed the window
    double seconds = 0.0;
};

// The run reached the end of its window (no physical limit ended it).
bool completed(const core::AmplitudeResult& a);
AmplitudeRun run_amplitude(InletFilmModel film, const core::Control& compute,
                           double asperity_factor = 1.0);
void write_amplitude_outputs(Output& out, const AmplitudeRun& run);

}  // namespace rollgap::tools::paper
