// libFuzzer harness: the roll-bite solver (docs/model.md §1-4) on any valid scenario and on
// bite states around its steady state, as the coupled dynamics hand them over. Whatever the
// inputs, the solver returns a status; what it calls ok is finite and physically ordered.

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/roll_bite.h"
#include "fuzz/fuzz_input.h"
#include "fuzz/scenario_from_bytes.h"

using namespace rollgap;
using fuzz::require;

namespace {

void check(const core::BiteState& state, const core::BiteResult& bite) {
    require(bite.message != nullptr, "a message, possibly empty");
    if (bite.status != core::BiteStatus::ok) return;  // a status is a legitimate answer
    require(std::isfinite(bite.contact_length) && bite.contact_length > 0.0,
            "ok: contact length > 0");
    require(std::isfinite(bite.inlet_angle) && bite.inlet_angle > 0.0, "ok: inlet angle > 0");
    require(std::isfinite(bite.inlet_film) && bite.inlet_film >= 0.0, "ok: inlet film >= 0");
    require(std::isfinite(bite.neutral_point) && bite.neutral_point >= 0.0 &&
                bite.neutral_point <= bite.contact_length * (1.0 + 1e-9),
            "ok: the neutral point inside the bite");
    require(std::isfinite(bite.entry_speed) && bite.entry_speed > 0.0, "ok: entry speed > 0");
    require(std::isfinite(bite.exit_speed) && bite.exit_speed > 0.0, "ok: exit speed > 0");
    require(std::isfinite(bite.forward_slip), "ok: finite forward slip");
    require(std::isfinite(bite.force), "ok: finite force");
    require(std::isfinite(bite.torque), "ok: finite torque");
    require(std::isfinite(bite.mean_friction_coefficient) && bite.mean_friction_coefficient >= 0.0,
            "ok: mean friction coefficient >= 0");
    // The strip thins through the bite: the exit is faster than the entry (mass flow).
    if (state.gap_rate == 0.0) require(bite.exit_speed > bite.entry_speed, "ok, steady: u2 > u1");

    double previous_x = -1.0;
    for (const core::BitePoint& point : bite.distribution) {
        require(std::isfinite(point.x) && std::isfinite(point.pressure) &&
                    std::isfinite(point.friction) && std::isfinite(point.film) &&
                    std::isfinite(point.film_ratio) && std::isfinite(point.contact_ratio) &&
                    std::isfinite(point.strip_speed) && std::isfinite(point.thickness),
                "ok: finite distributions");
        require(point.x >= previous_x, "ok: distribution in ascending x");
        previous_x = point.x;
        require(point.contact_ratio >= 0.0 && point.contact_ratio <= 1.0,
                "ok: contact ratio in [0, 1]");
        require(point.film >= 0.0 && point.film_ratio >= 0.0, "ok: film >= 0");
        require(point.strip_speed > 0.0, "ok: strip moves forward");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::FuzzInput input(data, size);
    const auto scenario = fuzz::scenario_from_bytes(input);
    if (!scenario) return -1;  // not a scenario a client could send: not worth keeping
    const core::Scenario& s = *scenario;

    core::BiteOptions options;
    options.distributions = input.flag();
    core::BiteState state = core::steady_bite_state(s);
    check(state, core::solve_roll_bite(s, state, options));

    // A state the dynamics may visit: the gap opened or closed by up to a fifth of the exit
    // thickness, the rolls moving apart or together, the inlet film from dry to ten times
    // steady, the tensions anywhere between slack and the flow stress.
    if (input.flag()) {
        const double y2 = state.exit_thickness;
        state.exit_thickness = y2 * (1.0 + input.between(-0.2, 0.2));
        state.gap_rate = input.between(-1.0, 1.0) * s.rolls.speed * 1e-3;
        state.inlet_film = input.flag() ? 0.0 : input.between(1e-9, 1e-4);
        state.back_tension = input.unit() * 0.999 * s.strip.flow_stress;
        state.front_tension = input.unit() * 0.999 * s.strip.flow_stress;
        check(state, core::solve_roll_bite(s, state, options));
    }
    return 0;
}
