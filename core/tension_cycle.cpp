#include "core/tension_cycle.h"

#include <algorithm>
#include <cmath>

#include "core/time_integration.h"

namespace rollgap::core {

TensionCycleResult tension_cycle(Scenario s, const TensionCycleOptions& options,
                                 const Control& control) {
    TensionCycleResult out;
    s.tensions.back.mode = TensionMode::sinusoid;
    out.frequency_Hz = s.tensions.back.frequency;
    // The api validates these; core answers a direct caller's nonsense with a status, not a hang.
    const bool phases_valid = std::all_of(options.phases.begin(), options.phases.end(),
                                          [](double phase) { return phase >= 0.0 && phase < 1.0; });
    if (!(out.frequency_Hz > 0.0 && std::isfinite(out.frequency_Hz)) || !phases_valid) {
        out.message = "the tension cycle needs a finite frequency > 0 and phases in [0, 1)";
        return out;
    }

    const Scenario dynamics = dynamics_scenario(s);
    const ReferenceState ref = reference_state(dynamics, false);
    out.steady_status = ref.status;
    if (ref.status != BiteStatus::ok) {
        out.message = "no steady state at the mean tension: the bite skids or loses contact";
        return out;
    }
    const CoupledModel model(dynamics, ref);

    std::vector<double> phases = options.phases;
    std::sort(phases.begin(), phases.end());
    const double period = 1.0 / out.frequency_Hz;
    const int cycles = std::max(1, options.cycles);
    // The run stops at the phase outputs and, in between, often enough (at most every 50 ms of
    // simulated time) for a cancellation or a deadline to be heard without waiting for a cycle.
    std::vector<double> phase_times;
    for (double phase : phases) phase_times.push_back((cycles - 1 + phase) * period);
    const double end = phase_times.empty() ? 0.0 : phase_times.back();
    constexpr double max_polls = 1e5;  // bounds the output list whatever the cycle's length
    const double poll = std::max(std::min(period / 8.0, 0.05), end / max_polls);
    std::vector<double> times;
    std::vector<bool> is_phase;
    std::size_t next_phase = 0;
    for (int k = 1; k * poll < end || next_phase < phase_times.size(); ++k) {
        const double t = k * poll;
        while (next_phase < phase_times.size() && phase_times[next_phase] <= t) {
            times.push_back(std::max(phase_times[next_phase], 1e-12));  // CVODE needs t > t0
            is_phase.push_back(true);
            ++next_phase;
        }
        if (t < end && (times.empty() || t > times.back())) {
            times.push_back(t);
            is_phase.push_back(false);
        }
    }

    std::vector<Eigen::VectorXd> states;
    std::vector<double> reached;
    Eigen::VectorXd z = model.equilibrium();
    IntegrationOptions integration;
    integration.relative_tolerance = options.relative_tolerance;
    integration.max_step = period / 50.0;
    std::size_t output = 0;
    const IntegrationResult run = integrate(
        model, z, 0.0, times,
        [&](const Sample& sample) {
            if (is_phase[output++]) {
                states.push_back(sample.z);
                reached.push_back(sample.t);
            }
        },
        integration, control);
    out.status = run.status;
    out.message = run.status == DynamicsStatus::ok ? "ok" : run.message;

    for (std::size_t i = 0; i < states.size(); ++i) {
        PhaseDistribution p;
        p.phase = phases[i];
        p.time = reached[i];
        const BiteState state = model.bite_state(p.time, states[i].data());
        p.back_tension = state.back_tension;
        p.gap = states[i](2) - states[i](3);
        p.inlet_film = states[i](CoupledModel::film_index);
        p.bite = solve_roll_bite(s, state);  // the distributions at the scenario's own resolution
        out.phases.push_back(std::move(p));
    }
    return out;
}

}  // namespace rollgap::core
