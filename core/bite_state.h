#pragma once
// The inputs of one roll-bite solve and the statuses it can end with (docs/model.md §1-4): plain
// data shared by the bite solver (core/roll_bite.h) and the flattening fixed point
// (core/roll_flattening.h), so that neither needs the other's header to name them.

namespace rollgap::core {

// The instantaneous state the bite is solved for. In steady state exit_thickness = y1 (1 - R),
// gap_rate = 0 and inlet_film = the Wilson-Walowit film h00 (see steady_bite_state()).
struct BiteState {
    // y1, m; <= 0: the scenario's strip.entry_thickness. steady_bite_state() and the stand block
    // fill it from the scenario, so a single stand sees the same y1 as before it was an input; a
    // mill will set it from the strip the stand upstream delivers, and the bite linearisation
    // has its column (docs/model.md §6.1).
    double entry_thickness = 0.0;
    double exit_thickness = 0.0;  // y2, m
    double gap_rate = 0.0;        // dyc/dt, m/s, opening positive
    double inlet_film = 0.0;      // h0, m; <= 0 means "steady": h0 = h00(u1) inside the solve
    double back_tension = 0.0;    // s_b, Pa
    double front_tension = 0.0;   // s_f, Pa
    // The radius of the bite's arc, m; <= 0: the scenario's rigid radius. steady_bite_state()
    // sets the flattened one when the scenario asks for it (core/roll_flattening.h).
    double roll_radius = 0.0;

    // The entry thickness the bite is solved for: this state's, or the scenario's `fallback`.
    double entry_thickness_or(double fallback) const {
        return entry_thickness > 0.0 ? entry_thickness : fallback;
    }
};

enum class BiteStatus {
    ok,
    skidding,       // no neutral point inside the bite: the rolls cannot drive the strip
    contact_lost,   // y1 <= y2: no reduction, no force
    solver_failure  // non-finite values or an inconsistent state (e.g. v + u <= 0)
};

}  // namespace rollgap::core
