#pragma once
// Sweeps (MODEL.md §7.5): one analysis over many scenarios, in parallel. Each scenario is
// independent and its result lands in its own slot, so the results do not depend on the thread
// count.

#include <vector>

#include "core/amplitude.h"
#include "core/control.h"
#include "core/stability.h"

namespace rollgap::core {

std::vector<CriticalSpeedResult> sweep_critical_speed(const std::vector<Scenario>& scenarios,
                                                      const CriticalSpeedOptions& options, int threads,
                                                      const Control& control = {});

std::vector<AmplitudeResult> sweep_amplitude(const std::vector<Scenario>& scenarios, const AmplitudeOptions& options,
                                             int threads, const Control& control = {});

}  // namespace rollgap::core
