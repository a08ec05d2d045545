#pragma once
// The all-in-one answer: the roll-gap distributions at the scenario's speed, the critical speed
// over the search range and the vibration amplitude at the scenario's speed.

#include "core/amplitude.h"
#include "core/control.h"
#include "core/roll_bite.h"
#include "core/stability.h"

namespace rollgap::core {

struct Evaluation {
    BiteResult bite;
    SpeedStability stability;  // eigenvalues at the scenario's speed
    CriticalSpeedResult critical;
    AmplitudeResult amplitude;
};

Evaluation evaluate_scenario(const Scenario& s, const CriticalSpeedOptions& critical_options = {},
                             const AmplitudeOptions& amplitude_options = {},
                             const Control& control = {});

}  // namespace rollgap::core
