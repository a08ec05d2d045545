#include "core/bite_jacobian.h"

#include "core/bite_kernel.h"
#include "core/dual.h"

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

namespace {

// The checks both methods make before differentiating; false with `out` filled when one fails.
bool linearisable(const BiteState& at, const BiteResult& bite, unsigned columns,
                  BiteJacobian& out) {
    if (bite.status != BiteStatus::ok) {
        out.status = bite.status;
        out.message = "the bite to linearise about is not solved";
        return false;
    }
    if ((columns & bite_column(BiteInput::inlet_film)) != 0 && !(at.inlet_film > 0.0)) {
        out.message = "the film column needs a given inlet film (h0 > 0), not the steady one";
        return false;
    }
    return true;
}

}  // namespace

BiteJacobian bite_jacobian(const Scenario& s, const BiteState& at, const BiteResult& bite,
                           unsigned columns) {
    BiteJacobian out;
    if (!linearisable(at, bite, columns, out)) return out;

    // One more pass of the kernel at the solved neutral point x_n, in dual numbers: directions
    // 0-5 the bite inputs, direction 6 the neutral point (docs/model.md §6.1).
    constexpr int xn_direction = bite_input_count;
    using D = Dual<bite_input_count + 1>;
    const bite_kernel::Bite<double> b0 = bite_kernel::bite_of(s, at);
    bite_kernel::Bite<D> b;
    b.s = b0.s;
    b.a = b0.a;
    b.v = b0.v;
    b.sigma = b0.sigma;
    b.width = b0.width;
    b.asperity_stress = b0.asperity_stress;
    b.rq = b0.rq;
    b.intervals = b0.intervals;
    const auto seed = [&](double value, BiteInput input) {
        return (columns & bite_column(input)) != 0 ? D::variable(value, static_cast<int>(input))
                                                   : D(value);
    };
    b.y1 = seed(b0.y1, BiteInput::entry_thickness);
    b.y2 = seed(b0.y2, BiteInput::exit_thickness);
    b.gap_rate = seed(b0.gap_rate, BiteInput::gap_rate);
    // a steady film (h0 <= 0) is no input: it moves with u1, theta and s_b inside the kernel
    b.fixed_film = seed(b0.fixed_film, BiteInput::inlet_film);
    b.back = seed(b0.back, BiteInput::back_tension);
    b.front = seed(b0.front, BiteInput::front_tension);
    bite_kernel::set_contact(b);

    const bite_kernel::BiteSolver<D> solver(b);
    const bite_kernel::Trial<D> t = solver.trial(D::variable(bite.neutral_point, xn_direction));
    const bite_kernel::SideResult<D> exit =
        t.valid ? solver.exit_side(t) : bite_kernel::SideResult<D>{false};
    const bite_kernel::SideResult<D> entry =
        t.valid ? solver.entry_side(t) : bite_kernel::SideResult<D>{false};
    // the residual's slope in x_n: negative where a root is (roll_bite.cpp, bracket_and_solve)
    const D residual = entry.end_pressure - exit.end_pressure;
    const double slope = residual.d[xn_direction];
    if (!exit.finite || !entry.finite || !(slope < 0.0)) {
        out.status = BiteStatus::solver_failure;
        out.message = "the bite's sensitivities are not finite at its neutral point";
        return out;
    }
    D outputs[bite_output_count];
    outputs[static_cast<int>(BiteOutput::force)] = b.width * (exit.integral_p - entry.integral_p);
    outputs[static_cast<int>(BiteOutput::entry_speed)] = t.entry_speed;
    outputs[static_cast<int>(BiteOutput::exit_speed)] =
        (t.entry_speed * b.y1 - b.contact_length * b.gap_rate) / b.y2;
    outputs[static_cast<int>(BiteOutput::inlet_angle)] = b.inlet_angle;
    outputs[static_cast<int>(BiteOutput::torque)] =
        -b.width * s.rolls.radius * (exit.integral_tau - entry.integral_tau);

    // the residual stays zero: dx_n/dalpha = -(dR/dalpha) / (dR/dx_n), and each output's total
    // derivative is its partial one plus its slope in x_n times that
    for (int j = 0; j < bite_input_count; ++j) {
        const auto input = static_cast<BiteInput>(j);
        if ((columns & bite_column(input)) == 0) continue;
        const double dxn = -residual.d[j] / slope;
        for (int i = 0; i < bite_output_count; ++i)
            out.derivative(i, j) = outputs[i].d[j] + outputs[i].d[xn_direction] * dxn;
        out.columns |= bite_column(input);
    }
    if (!out.derivative.allFinite()) {
        out.columns = 0;
        out.status = BiteStatus::solver_failure;
        out.message = "the bite's sensitivities are not finite at its neutral point";
        return out;
    }
    out.kernel_passes = 1;
    out.status = BiteStatus::ok;
    out.message = "ok";
    return out;
}

BiteJacobian bite_jacobian_differences(const Scenario& s, const BiteState& at,
                                       const BiteResult& bite, unsigned columns,
                                       const BiteSteps& steps) {
    BiteJacobian out;
    if (!linearisable(at, bite, columns, out)) return out;
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
