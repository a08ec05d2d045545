#include "core/bite_jacobian.h"

namespace rollgap::core {

namespace {

double& bite_input(BiteState& state, BiteInput input) {
    switch (input) {
        case BiteInput::entry_thickness: return state.entry_thickness;
        case BiteInput::exit_thickness: return state.exit_thickness;
        case BiteInput::gap_rate: return state.gap_rate;
        case BiteInput::inlet_film: return state.inlet_film;
        case BiteInput::back_tension: return state.back_tension;
        case BiteInput::front_tension: break;
    }
    return state.front_tension;
}

const char* failed_column_message(BiteInput input) {
    switch (input) {
        case BiteInput::entry_thickness: return "the bite does not solve at y1 +- its step";
        case BiteInput::exit_thickness: return "the bite does not solve at y2 +- its step";
        case BiteInput::gap_rate: return "the bite does not solve at the gap rate +- its step";
        case BiteInput::inlet_film: return "the bite does not solve at h0 +- its step";
        case BiteInput::back_tension: return "the bite does not solve at s_b +- its step";
        case BiteInput::front_tension: break;
    }
    return "the bite does not solve at s_f +- its step";
}

Eigen::Matrix<double, bite_output_count, 1> bite_outputs(const BiteResult& bite) {
    Eigen::Matrix<double, bite_output_count, 1> out;
    out(static_cast<int>(BiteOutput::force)) = bite.force;
    out(static_cast<int>(BiteOutput::entry_speed)) = bite.entry_speed;
    out(static_cast<int>(BiteOutput::exit_speed)) = bite.exit_speed;
    out(static_cast<int>(BiteOutput::inlet_angle)) = bite.inlet_angle;
    out(static_cast<int>(BiteOutput::torque)) = bite.torque;
    return out;
}

}  // namespace

double BiteSteps::step(BiteInput input, const BiteState& at) const {
    switch (input) {
        case BiteInput::entry_thickness: return entry_thickness;
        case BiteInput::exit_thickness: return exit_thickness;
        case BiteInput::gap_rate: return gap_rate;
        case BiteInput::inlet_film: return inlet_film_relative * at.inlet_film;
        case BiteInput::back_tension:
        case BiteInput::front_tension: break;
    }
    return tension;
}

BiteJacobian bite_jacobian(const Scenario& s, const BiteState& at, const BiteResult& bite,
                           unsigned columns, const BiteSteps& steps) {
    BiteJacobian out;
    if (bite.status != BiteStatus::ok) {
        out.status = bite.status;
        out.message = "the bite to linearise about is not solved";
        return out;
    }
    if ((columns & bite_column(BiteInput::inlet_film)) != 0 && !(at.inlet_film > 0.0)) {
        out.message = "the film column needs a given inlet film (h0 > 0), not the steady one";
        return out;
    }
    // y1 is an input only if the state carries it; otherwise the scenario's, made explicit here
    // so that its column perturbs a number.
    BiteState base = at;
    base.entry_thickness = at.entry_thickness_or(s.strip.entry_thickness);

    // The reference bite's neutral point as the warm start of every perturbed solve: the root
    // is the same to ~1e-14 of x_w (core/roll_bite.h), the search a few Brent steps.
    const BiteOptions options{false, bite.neutral_point};
    for (int j = 0; j < bite_input_count; ++j) {
        const auto input = static_cast<BiteInput>(j);
        if ((columns & bite_column(input)) == 0) continue;
        const double delta = steps.step(input, base);
        BiteState lo = base, hi = base;
        bite_input(lo, input) -= delta;
        bite_input(hi, input) += delta;
        const BiteResult a = solve_roll_bite(s, lo, options);
        const BiteResult b = solve_roll_bite(s, hi, options);
        out.bite_solves += 2;
        if (a.status != BiteStatus::ok || b.status != BiteStatus::ok) {
            // the upper side's status first, as finite_difference_jacobian reports it
            out.status = b.status != BiteStatus::ok ? b.status : a.status;
            out.message = failed_column_message(input);
            return out;
        }
        // divided by the inputs' actual difference, as the state Jacobian divides by its
        // components' (core/dynamic_model.cpp)
        out.derivative.col(j) =
            (bite_outputs(b) - bite_outputs(a)) / (bite_input(hi, input) - bite_input(lo, input));
        out.columns |= bite_column(input);
    }
    out.status = BiteStatus::ok;
    out.message = "ok";
    return out;
}

}  // namespace rollgap::core
