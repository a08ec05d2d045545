#pragma once
// Mechanism studies: variants of the assumptions the specification adds to the paper, the gap
// mode followed over speed, and the growth rate over speed at the defaults (stability map).
#include <functional>
#include <string>
#include <vector>

#include "core/control.h"
#include "core/stability.h"
#include "tools/reproduce_paper/output.h"

namespace rollgap::tools::paper {

struct Variant {
    std::string label;
    std::function<void(Scenario&)> apply;
};

struct VariantResult {
    std::string label;
    core::CriticalSpeedResult result;
};

std::vector<VariantResult> run_variants(const std::vector<Variant>& variants,
                                        const core::Control& compute);
// "20.10 m/s (104 Hz)", "stable to 60 m/s", ...
std::string critical_text(const core::CriticalSpeedResult& r);

struct SpeedDiagnostics {
    InletFilmModel film;
    std::vector<ModeDiagnostics> rows;
};

SpeedDiagnostics diagnose_over_speed(InletFilmModel film, const std::vector<double>& speeds,
                                     double frequency_Hz,
                                     const std::function<void(Scenario&)>& apply,
                                     const core::Control& compute);

struct StabilityMap {
    std::vector<std::string> labels;
    std::vector<core::CriticalSpeedResult> results;
};

StabilityMap stability_map(const core::Control& compute);
void write_stability_map(Output& out, const StabilityMap& map);

}  // namespace rollgap::tools::paper
