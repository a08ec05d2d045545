// libFuzzer harness: the right-hand side of the coupled mill-bite-film model (docs/model.md §6)
// on any valid scenario, at states around its equilibrium such as a time integration visits.
// Whatever the state, rhs() returns a status; where it says ok every derivative is finite, and
// the cheap limit margins are finite too (the integrator's root finding reads them).

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <Eigen/Dense>

#include "core/coupled_model.h"
#include "fuzz/fuzz_input.h"
#include "fuzz/scenario_from_bytes.h"

using namespace rollgap;
using fuzz::require;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::FuzzInput input(data, size);
    const auto scenario = fuzz::scenario_from_bytes(input);
    if (!scenario) return -1;  // not a scenario a client could send: not worth keeping
    const core::Scenario s = core::dynamics_scenario(*scenario);

    const core::ReferenceState reference = core::reference_state(s);
    if (reference.status != core::BiteStatus::ok) return 0;  // no operating point: a status
    require(std::isfinite(reference.strip_stiffness), "reference: finite k4");
    core::Excitation excitation;
    if (input.flag()) {
        excitation.back_tension_amplitude = input.unit() * 0.5 * s.tensions.back.stress;
        excitation.frequency_Hz = input.between(0.1, 1e4);
    }
    const core::CoupledModel model(s, reference, excitation);
    const int n = model.size();
    Eigen::VectorXd z = model.equilibrium();
    require(z.size() == n && z.allFinite(), "a finite equilibrium of the model's size");

    // A few states in a row on the same model, as an integrator's steps and Jacobian columns
    // reach them (the model memoises recent bites): displacements up to 1/10 of the exit
    // thickness, velocities up to 1 m/s, the film from 0.1 to 10 times steady, the span
    // tensions from slack to the flow stress.
    const double y2 = reference.exit_thickness;
    const int states = 1 + input.byte() % 4;
    for (int k = 0; k < states; ++k) {
        const double t = input.between(0.0, 1.0);
        Eigen::VectorXd state = z;
        for (int i = 0; i < 6; ++i) state[i] += input.between(-0.1, 0.1) * y2;
        for (int i = 6; i < 12; ++i) state[i] += input.between(-1.0, 1.0);
        state[core::CoupledModel::film_index] *= input.between(0.1, 10.0);
        if (model.back_tension_index() >= 0) {
            state[model.back_tension_index()] = input.unit() * 0.999 * s.strip.flow_stress;
        }
        if (model.front_tension_index() >= 0) {
            state[model.front_tension_index()] = input.unit() * 0.999 * s.strip.flow_stress;
        }

        double margins[core::CoupledModel::limit_count];
        model.limit_margins(t, state.data(), margins);
        for (double margin : margins) require(std::isfinite(margin), "finite limit margins");

        Eigen::VectorXd zdot = Eigen::VectorXd::Constant(n, 0.0);
        core::BiteResult bite;
        const core::DynamicsStatus status = model.rhs(t, state.data(), zdot.data(), &bite);
        if (status != core::DynamicsStatus::ok) continue;  // a status is a legitimate answer
        require(zdot.allFinite(), "ok: finite derivatives");
        require(bite.status == core::BiteStatus::ok, "ok: the bite behind it is ok");
        require(std::isfinite(bite.force) && std::isfinite(bite.entry_speed) &&
                    std::isfinite(bite.exit_speed),
                "ok: a finite bite");
    }
    return 0;
}
