#pragma once
// The scalar options of the analyses, each written once: name, type, unit, bounds and the
// description the OpenAPI document shows. `OptionsReader::read` reads a member by its row, and
// the OpenAPI generator writes the member's schema from the same row into every options
// component that lists it (`option_components()`), so the bounds the service enforces are the
// bounds the document states. Compound members (arrays, objects, choices such as `detail`) are
// read by their analysis and described in service/openapi.json.
//
// One name may have two rows: `relative_tolerance` refines a critical speed in [1e-8, 1e-2] but
// is a CVODE tolerance in [1e-9, 1e-3]; the components say which row they hold.

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "api/interval.h"
#include "api/units.h"

namespace rollgap::api {

enum class OptionId {
    // the critical-speed search (CriticalSpeedSearchOptions, StabilityOptions)
    search_speed_min,
    search_speed_max,
    search_speed_step,
    search_tolerance,
    // the stability analysis
    critical_speed,
    // the roll gap
    distributions,
    // a time integration (amplitude, tension cycle)
    window,
    excitation_amplitude,
    excitation_frequency,
    integration_tolerance,
    time_series,
    time_series_points,
    cycles,
    // calibration
    max_iterations,
    // the tandem mill's time domain (docs/model.md §12.9)
    mill_time_series,
    mill_window,
    kick_gap,
    kick_stand,
    // the speed limit (docs/model.md §13)
    max_roll_force,
    max_torque,
    max_power,
    min_forward_slip,
    chatter_limit,
    chatter_margin,
    confidence,
    samples,
    seed,
    what_to_change,
};

// The member names by OptionId, constexpr so that a reader's list of known members can name them.
inline constexpr std::array<std::string_view, 28> option_names{
    "speed_min_m_per_s",
    "speed_max_m_per_s",
    "speed_step_m_per_s",
    "relative_tolerance",
    "critical_speed",
    "distributions",
    "window_s",
    "excitation_amplitude_MPa",
    "excitation_frequency_Hz",
    "relative_tolerance",
    "time_series",
    "time_series_points",
    "cycles",
    "max_iterations",
    "time_series",
    "window_s",
    "kick_um",
    "kick_stand",
    "max_roll_force_kN",
    "max_torque_kN_m",
    "max_power_kW",
    "min_forward_slip",
    "chatter",
    "chatter_margin",
    "confidence",
    "samples",
    "seed",
    "what_to_change",
};
constexpr std::string_view option_name(OptionId id) {
    return option_names[static_cast<std::size_t>(id)];
}

// What a label or a form calls each option (the OpenAPI `title`), by OptionId: the name column
// the field tables have, so that no page shows `relative_tolerance` for "Search tolerance".
inline constexpr std::array<std::string_view, 28> option_titles{
    "Lowest search speed",
    "Highest search speed",
    "Search scan step",
    "Search tolerance",
    "Search the critical speed",
    "Distributions along the bite",
    "Simulated time per speed",
    "Excitation amplitude",
    "Excitation frequency",
    "Integration tolerance",
    "Time series",
    "Time series points",
    "Tension cycles",
    "Iterations at most",
    "Mill time series",
    "Simulated time",
    "Gap kick",
    "Kicked stand",
    "Largest roll force",
    "Largest torque per work roll",
    "Rated drive power",
    "Smallest forward slip",
    "Chatter as a limit",
    "Chatter margin",
    "Confidence",
    "Posterior draws",
    "Seed of the draws",
    "What to change",
};

enum class OptionType { number, integer, boolean };

struct Option {
    OptionId id;
    std::string_view name;  // option_name(id)
    OptionType type;
    Unit unit;       // the unit the client writes (units::one: dimensionless, and every integer)
    Interval range;  // in `unit`; unused for booleans
    std::string description;   // the glossary sentence; type, unit and bounds are appended
    std::string_view title{};  // option_titles[id]: what a label or a form calls it
};

// Every row, in OptionId order.
std::span<const Option> option_rows();
const Option& option(OptionId id);

// An options component of the OpenAPI document and the scalar members it holds, by row.
struct OptionComponent {
    std::string_view schema;  // e.g. "AmplitudeOptions"
    std::vector<OptionId> members;
};
std::span<const OptionComponent> option_components();

}  // namespace rollgap::api
