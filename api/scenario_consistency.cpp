#include "api/scenario_consistency.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "api/text.h"
#include "api/units.h"

namespace rollgap::api {
namespace {

std::string mpa_text(double pascal) {
    return concat(format_number(from_si(pascal, units::megapascal)), " MPa");
}

struct Context {
    const core::Scenario& scenario;
    const std::string& pointer;
    FieldErrors& errors;
    std::span<const GivenAs> given_as;

    std::string at(std::string_view path) const { return pointer + std::string(path); }

    // A violation at `path` with its bound in `unit`; at the member the client gave instead
    // (a tension as a force: its pointer, the bound in kN, the force named in the detail).
    void report(const std::string& path, std::string detail, const Interval& allowed,
                std::string_view unit) const {
        for (const GivenAs& given : given_as) {
            if (given.canonical != path) continue;
            const Interval in_given{allowed.min * given.per_canonical,
                                    allowed.max * given.per_canonical, allowed.min_open,
                                    allowed.max_open};
            errors.add({at(given.given),
                        concat(detail, " (", format_number(given.value), " ", given.unit,
                               " over the strip's cross-section, ",
                               format_number(given.per_canonical / 1000.0 * 1e6), " mm²)"),
                        in_given.text(), std::string(given.unit)});
            return;
        }
        errors.add({at(path), std::move(detail), allowed.text(), std::string(unit)});
    }

    // A rule runs only if all its inputs passed their own checks.
    bool inputs_valid(std::initializer_list<std::string_view> paths) const {
        return std::none_of(paths.begin(), paths.end(), [this](std::string_view path) {
            return errors.has_error_at_or_below(at(path));
        });
    }
};

// A tension at or above the flow stress yields the strip in the span; the boundary pressure
// p = sigma - s would vanish or turn negative.
void check_tension_below_flow_stress(const Context& context, const std::string& side,
                                     const core::TensionSide& tension) {
    const std::string path = concat("/tension/", side, "/stress_MPa");
    if (!context.inputs_valid({"/strip/flow_stress_MPa", path})) return;
    const double flow_stress = context.scenario.strip.flow_stress;
    if (tension.stress < flow_stress) return;
    const Interval allowed = closed_open(0.0, from_si(flow_stress, units::megapascal));
    context.report(path,
                   concat(side, " tension ", mpa_text(tension.stress),
                          " must be below the flow stress ", mpa_text(flow_stress),
                          " (/strip/flow_stress_MPa): the strip would yield in the span"),
                   allowed, units::megapascal.code);
}

// s(t) = s + A sin(2 pi f t) must stay in [0, sigma): never slack, never yielding.
void check_sinusoid_within_limits(const Context& context, const std::string& side,
                                  const core::TensionSide& tension) {
    if (tension.mode != core::TensionMode::sinusoid) return;
    const std::string group = concat("/tension/", side);
    const std::string amplitude_path = concat(group, "/amplitude_MPa");
    if (!context.inputs_valid({"/strip/flow_stress_MPa", group})) return;
    const double flow_stress = context.scenario.strip.flow_stress;
    const bool goes_slack = tension.stress - tension.amplitude < 0.0;
    const bool yields = tension.stress + tension.amplitude >= flow_stress;
    if (!goes_slack && !yields) return;
    // The amplitude the mean allows: up to the mean (slack side), below sigma - mean (yield side).
    const double slack_limit = from_si(tension.stress, units::megapascal);
    const double yield_limit = from_si(flow_stress - tension.stress, units::megapascal);
    const Interval allowed =
        slack_limit < yield_limit ? closed(0.0, slack_limit) : closed_open(0.0, yield_limit);
    const std::string reason =
        goes_slack ? "would go slack (below 0): the amplitude must not exceed the mean tension"
                   : concat("would reach the flow stress ", mpa_text(flow_stress),
                            ": mean + amplitude must stay below it");
    context.report(amplitude_path,
                   concat("sinusoidal ", side, " tension ", mpa_text(tension.stress), " ± ",
                          mpa_text(tension.amplitude), " ", reason),
                   allowed, units::megapascal.code);
}

// The model's roll profile y = y2 + x^2 / a is the small-angle form of the circle (docs/model.md
// §1); cold mills bite at ~0.03 rad. 0.35 rad (20°) admits any real mill and rejects geometry
// where the profile, and with it every result, would be wrong.
constexpr double largest_bite_angle = 0.35;

void check_bite_angle_small(const Context& context) {
    if (!context.inputs_valid(
            {"/strip/entry_thickness_mm", "/strip/reduction", "/rolls/radius_mm"}))
        return;
    const core::Scenario& s = context.scenario;
    const double draft = s.strip.entry_thickness * s.strip.reduction;
    const double bite_angle = std::sqrt(draft / s.rolls.radius);
    if (bite_angle <= largest_bite_angle) return;
    // Rounded down to 4 decimals so the bound reads well and is itself allowed.
    const double largest_reduction = std::floor(largest_bite_angle * largest_bite_angle *
                                                s.rolls.radius / s.strip.entry_thickness * 1e4) /
                                     1e4;
    context.errors.add(
        {context.at("/strip/reduction"),
         concat("bite angle sqrt(entry thickness × reduction / roll radius) = ",
                format_number(std::round(bite_angle * 1000.0) / 1000.0), " rad exceeds ",
                format_number(largest_bite_angle),
                " rad: the model's parabolic roll profile needs a small angle; reduce the "
                "reduction or the entry thickness, or use a larger roll radius"),
         open_closed(0.0, largest_reduction).text(), std::string(units::one.code)});
}

void check_rayleigh_frequencies_ordered(const Context& context) {
    const std::string low_path = "/mill/rayleigh/low_frequency_Hz";
    const std::string high_path = "/mill/rayleigh/high_frequency_Hz";
    if (!context.inputs_valid({low_path, high_path})) return;
    const core::StandStructure& mill = context.scenario.structure;
    if (mill.rayleigh_frequency_low < mill.rayleigh_frequency_high) return;
    const Interval allowed = open_closed(mill.rayleigh_frequency_low, 1e5);
    context.errors.add(
        {context.at(high_path),
         concat("must be above low_frequency_Hz (", format_number(mill.rayleigh_frequency_low),
                " Hz): the two frequencies fix the Rayleigh coefficients"),
         allowed.text(), std::string(units::hertz.code)});
}

}  // namespace

void check_scenario_consistency(const core::Scenario& scenario, const std::string& pointer,
                                FieldErrors& errors, std::span<const GivenAs> given_as) {
    const Context context{scenario, pointer, errors, given_as};
    check_tension_below_flow_stress(context, "back", scenario.tensions.back);
    check_tension_below_flow_stress(context, "front", scenario.tensions.front);
    check_sinusoid_within_limits(context, "back", scenario.tensions.back);
    check_sinusoid_within_limits(context, "front", scenario.tensions.front);
    check_bite_angle_small(context);
    check_rayleigh_frequencies_ordered(context);
}

}  // namespace rollgap::api
