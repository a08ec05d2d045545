#include "api/option_table.h"

#include <cassert>
#include <string>

#include "api/amplitude_json.h"
#include "api/calibration_json.h"
#include "api/scenario_schema.h"
#include "api/stability_json.h"
#include "api/tension_cycle_json.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

using enum OptionId;

// The speeds a search may scan are the speeds a scenario may have.
Interval speed_range() { return find_scenario_field("/rolls/speed_m_per_s")->range; }

const std::vector<Option>& rows() {
    static const std::vector<Option> table = [] {
        const std::string integration_tolerance_text =
            "Relative tolerance of the time integration (CVODE); 1e-6 resolves sub-micrometre "
            "roll vibration; tighter costs time.";
        std::vector<Option> all{
            {search_speed_min,
             {},
             OptionType::number,
             units::metre_per_second,
             speed_range(),
             "Lowest rolling speed v of the critical-speed search (docs/model.md §7.3); below "
             "speed_max_m_per_s. If the stand already chatters here the answer is "
             "unstable_at_lower_bound."},
            {search_speed_max,
             {},
             OptionType::number,
             units::metre_per_second,
             speed_range(),
             "Highest rolling speed v of the critical-speed search; if the stand is stable up to "
             "here the answer is stable_in_range."},
            {search_speed_step,
             {},
             OptionType::number,
             units::metre_per_second,
             open_closed(0.0, 0.5),
             concat("Scan step of the critical-speed search: the stability is computed at every "
                    "step and the first change from stable to unstable is refined; a smaller "
                    "step finds a narrower unstable window and costs more; at most ",
                    std::to_string(max_scan_points), " scan speeds.")},
            {search_tolerance,
             {},
             OptionType::number,
             units::one,
             closed(1e-8, 1e-2),
             "Relative tolerance to which the critical speed is refined (1e-4: 2 mm/s at 20 "
             "m/s)."},
            {critical_speed,
             {},
             OptionType::boolean,
             units::one,
             {},
             "Whether to search the critical speed (false: only the stability at the scenario's "
             "speed)."},
            {distributions,
             {},
             OptionType::boolean,
             units::one,
             {},
             "Whether the result carries the distributions along the bite "
             "(`result.distribution`)."},
            {window,
             {},
             OptionType::number,
             units::second,
             open_closed(0.0, 20.0),
             "Simulated time per speed (the window); amplitudes are read over its last 10 %, so "
             "it must let the response settle (the lightly damped ~100 Hz gap mode of the "
             "default stand needs 1-2 s)."},
            {excitation_amplitude,
             {},
             OptionType::number,
             units::megapascal,
             closed(0.0, 100.0),
             "Amplitude of the sinusoidal back-tension excitation added to the tension the bite "
             "sees (docs/model.md §7.4), like a ripple from an eccentric upstream roll; 1 MPa "
             "keeps the response linear."},
            {excitation_frequency,
             {},
             OptionType::number,
             units::hertz,
             closed(0.0, 2000.0),
             "Frequency of the excitation; 0: the least-damped eigenfrequency at each speed (the "
             "resonance, where the response peaks)."},
            {integration_tolerance,
             {},
             OptionType::number,
             units::one,
             closed(1e-9, 1e-3),
             integration_tolerance_text},
            {time_series,
             {},
             OptionType::boolean,
             units::one,
             {},
             "Whether the result carries the decimated time series of x3 (the upper work roll's "
             "displacement), the roll-gap change g = x3 - x4 and the force change P - P_ref."},
            {time_series_points,
             {},
             OptionType::integer,
             units::one,
             closed(2.0, max_time_series_points),
             "Most points of the decimated time series (every n-th integrator output is "
             "kept)."},
            {cycles,
             {},
             OptionType::integer,
             units::one,
             closed(1.0, 20.0),
             concat("Whole cycles of the back-tension sinusoid simulated (the first ones let the "
                    "start-up transient pass); cycles / frequency is at most ",
                    format_number(max_simulated_time_s), " s.")},
            {max_iterations,
             {},
             OptionType::integer,
             units::one,
             closed(1.0, max_calibration_iterations),
             "Levenberg–Marquardt iterations at most."},
            {mill_time_series,
             {},
             OptionType::boolean,
             units::one,
             {},
             "Whether to integrate the whole mill in time (docs/model.md §12.9: the thickness "
             "transport as a history of strip positions) from its steady state with a gap kick, "
             "and return each stand's time series (gap, force, tensions, thicknesses) in "
             "result.time_series."},
            {mill_window,
             {},
             OptionType::number,
             units::second,
             open_closed(0.0, 5.0),
             "Simulated time of the mill's time series. A root growing at 5 /s multiplies the "
             "kick by e in 0.2 s; the transport delay of a 5 m span at 15 m/s is 0.33 s."},
            {kick_gap,
             {},
             OptionType::number,
             units::micrometre,
             closed(0.0, 100.0),
             "The gap kick at t = 0: the kicked stand's work rolls moved apart by this much (its "
             "exit thickness rises by it). 0.1 um keeps the response linear."},
            {kick_stand,
             {},
             OptionType::integer,
             units::one,
             closed(0.0, 6.0),
             "The stand kicked, numbered from 1 at the entry; 0: the stand that moves most in "
             "the rightmost root (the last stand without one)."},
            {max_roll_force,
             {},
             OptionType::number,
             units::kilonewton,
             open_closed(0.0, 1e6),
             "The stand's largest permitted roll force (docs/model.md §13.1); the force falls "
             "as the speed rises (the film thickens), so this limit usually bounds the speed "
             "from below. Absent: not checked."},
            {max_torque,
             {},
             OptionType::number,
             units::kilonewton_metre,
             open_closed(0.0, 1e5),
             "The largest permitted rolling torque per work roll (its magnitude). Absent: not "
             "checked."},
            {max_power,
             {},
             OptionType::number,
             units::kilowatt,
             open_closed(0.0, 1e6),
             "The main drive's rated power for both work rolls, 2 |torque| v / R. Absent: not "
             "checked."},
            {min_forward_slip,
             {},
             OptionType::number,
             units::one,
             closed(-0.5, 0.5),
             "The skid margin: the smallest permitted forward slip (u2 - v) / v; as it nears 0 "
             "the neutral point reaches the exit and the rolls skid. 0.005 is a common margin. "
             "Absent: not checked."},
            {chatter_limit,
             {},
             OptionType::boolean,
             units::one,
             {},
             "Whether the critical chatter speed is a limit (docs/model.md §7.3)."},
            {chatter_margin,
             {},
             OptionType::number,
             units::one,
             closed_open(0.0, 1.0),
             "Safety margin on the chatter limit, a fraction: the limit is (V_c - z sigma)(1 - "
             "margin); 0.1 runs at most at 90 % of the critical speed."},
            {confidence,
             {},
             OptionType::number,
             units::one,
             closed_open(0.5, 1.0),
             "Confidence of the one-sided lower bound V_c - z sigma on the critical speed, when "
             "the scenario carries a posterior (0.95: z = 1.645)."},
            {samples,
             {},
             OptionType::integer,
             units::one,
             closed(0.0, 500.0),
             "Seeded draws from the posterior at which the critical speed is also computed, the "
             "check on the linear propagation (each draw is a critical-speed search); 0: none."},
            {seed,
             {},
             OptionType::integer,
             units::one,
             closed(0.0, 2147483647.0),
             "Seed of the draws: the same seed draws the same samples."},
            {what_to_change,
             {},
             OptionType::boolean,
             units::one,
             {},
             "Whether to answer what to change to run faster: the advised speed's derivative "
             "with respect to each field of `changes` at the binding limit (docs/model.md "
             "§13.4), ranked by the speed one typical step gains."},
        };
        static_assert(option_names.size() == static_cast<std::size_t>(what_to_change) + 1);
        static_assert(option_titles.size() == option_names.size());
        assert(all.size() == option_names.size());
        for (std::size_t i = 0; i < all.size(); ++i) {
            assert(static_cast<std::size_t>(all[i].id) == i && "rows in OptionId order");
            all[i].name = option_name(all[i].id);
            all[i].title = option_titles[i];
        }
        return all;
    }();
    return table;
}

const std::vector<OptionComponent>& components() {
    static const std::vector<OptionComponent> table{
        {"RollGapOptions", {distributions}},
        {"CriticalSpeedSearchOptions",
         {search_speed_min, search_speed_max, search_speed_step, search_tolerance}},
        {"StabilityOptions",
         {search_speed_min, search_speed_max, search_speed_step, search_tolerance, critical_speed}},
        {"AmplitudeOptions",
         {window, excitation_amplitude, excitation_frequency, integration_tolerance, time_series,
          time_series_points}},
        {"AmplitudeRunOptions",
         {window, excitation_amplitude, excitation_frequency, integration_tolerance, time_series,
          time_series_points}},
        {"SweepAmplitudeOptions",
         {window, excitation_amplitude, excitation_frequency, integration_tolerance}},
        {"TensionCycleOptions", {cycles, integration_tolerance}},
        {"CalibrateOptions", {max_iterations}},
        {"TandemOptions",
         {search_speed_min, search_speed_max, search_speed_step, search_tolerance, critical_speed,
          mill_time_series, mill_window, time_series_points, kick_gap, kick_stand}},
        {"SpeedLimitOptions",
         {search_speed_min, search_speed_max, search_speed_step, search_tolerance, max_roll_force,
          max_torque, max_power, min_forward_slip, chatter_limit, chatter_margin, confidence,
          samples, seed, what_to_change}},
        {"TandemSpeedLimitOptions",
         {search_speed_min, search_speed_max, search_speed_step, search_tolerance, max_roll_force,
          max_torque, max_power, min_forward_slip, chatter_limit, chatter_margin, confidence,
          what_to_change}},
        {"StandLimits", {max_roll_force, max_torque, max_power, min_forward_slip}},
    };
    return table;
}

}  // namespace

std::span<const Option> option_rows() { return rows(); }

const Option& option(OptionId id) { return rows()[static_cast<std::size_t>(id)]; }

std::span<const OptionComponent> option_components() { return components(); }

}  // namespace rollgap::api
