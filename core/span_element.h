#pragma once
// A span element (docs/model.md §6): the strip between two points that take it in and give it
// out at their own speeds, an elastic span of length L whose tension s (Pa) is one state:
//   s' = (E / L) (downstream speed - upstream speed).
// The single stand has at most two: the entry span (upstream end a bridle or uncoiler held at
// the steady entry speed, downstream end the bite's entry speed u1) and the exit span (upstream
// end the bite's exit speed u2, downstream end a coiler at the steady exit speed). Between two
// stands of a mill both ends are bites.

namespace rollgap::core {

struct SpanElement {
    int index = -1;          // its tension in the model's state vector
    double stiffness = 0.0;  // E / L, Pa/m

    SpanElement() = default;
    SpanElement(int state_index, double youngs_modulus, double span_length)
        : index(state_index), stiffness(youngs_modulus / span_length) {}

    // s' for the speeds (m/s) at which the downstream end takes strip and the upstream end
    // gives it: a downstream end that runs faster stretches the span.
    double rate(double downstream_speed, double upstream_speed) const {
        return stiffness * (downstream_speed - upstream_speed);
    }

    // The central-difference step of the linearisation and the absolute tolerance of time
    // integration for the tension (docs/model.md §6, §7.3), Pa.
    static constexpr double perturbation = 1e3;
    static constexpr double absolute_tolerance = 1.0;
};

}  // namespace rollgap::core
