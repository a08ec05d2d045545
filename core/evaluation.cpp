#include "core/evaluation.h"

namespace rollgap::core {

Evaluation evaluate_scenario(const Scenario& s, const CriticalSpeedOptions& critical_options,
                             const AmplitudeOptions& amplitude_options, const Control& control) {
    Evaluation out;
    out.bite = solve_roll_bite(s, steady_bite_state(s));
    // The critical speed is a search over speed, so it answers even when the scenario's own speed
    // has no steady bite (a skidding set speed still has a chatter limit below it).
    // progress: the critical speed is most of the work, then the amplitude
    Control critical_control = control;
    critical_control.progress = [&](double f) { control.report(0.6 * f); };
    out.critical = critical_speed(s, critical_options, critical_control);
    if (out.bite.status != BiteStatus::ok)
        return out;  // no steady state: nothing vibrates about it
    out.stability = stability_at(s);
    if (control.should_stop()) return out;
    Control amplitude_control = control;
    amplitude_control.progress = [&](double f) { control.report(0.6 + 0.4 * f); };
    out.amplitude = vibration_amplitude(s, amplitude_options, amplitude_control);
    return out;
}

}  // namespace rollgap::core
