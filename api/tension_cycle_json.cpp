#include "api/tension_cycle_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>
#include <vector>

#include "api/json_pointer.h"
#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/result_json.h"
#include "api/result_table.h"
#include "api/scenario_consistency.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::string_view cycles_name = option_name(OptionId::cycles);
constexpr std::string_view phases_name = "phases";
constexpr std::array<std::string_view, 3> tension_cycle_members{
    cycles_name, phases_name, option_name(OptionId::integration_tolerance)};

void read_phases(const OptionsReader& reader, std::vector<double>& phases) {
    const nlohmann::json* value = reader.find(phases_name);
    if (value == nullptr) return;
    const std::string pointer = reader.at(phases_name);
    if (!value->is_array()) {
        reader.errors().add({pointer,
                             concat("must be an array of phases, got ", json_type_name(*value)),
                             std::nullopt, std::nullopt});
        return;
    }
    const std::string count_bound = concat("1 to ", std::to_string(max_phases), " phases");
    if (value->empty() || value->size() > static_cast<std::size_t>(max_phases)) {
        reader.errors().add(
            {pointer, concat("has ", std::to_string(value->size()), " phases; give ", count_bound),
             count_bound, std::nullopt});
        return;
    }
    std::vector<double> parsed;
    bool valid = true;
    for (std::size_t i = 0; i < value->size(); ++i) {
        const std::string item = append_pointer(pointer, std::to_string(i));
        const auto phase =
            read_number((*value)[i], item, closed_open(0.0, 1.0), units::one, reader.errors());
        if (!phase) {
            valid = false;
            continue;
        }
        if (std::find(parsed.begin(), parsed.end(), *phase) != parsed.end()) {
            reader.errors().add({item, concat("phase ", format_number(*phase), " is listed twice"),
                                 "distinct values in [0, 1)", std::string(units::one.code)});
            valid = false;
            continue;
        }
        parsed.push_back(*phase);
    }
    if (!valid) return;
    std::sort(parsed.begin(), parsed.end());
    phases = std::move(parsed);
}

std::string run_status(const core::TensionCycleResult& result) {
    if (result.steady_status != core::BiteStatus::ok) return "no_steady_state";
    return core::to_string(result.status);
}

}  // namespace

core::TensionCycleOptions tension_cycle_options_from_json(const nlohmann::json& options,
                                                          const std::string& pointer,
                                                          const core::Scenario* valid_scenario,
                                                          FieldErrors& errors) {
    core::TensionCycleOptions parsed;
    const OptionsReader reader(options, pointer, tension_cycle_members, errors);
    reader.read(OptionId::cycles, parsed.cycles);
    read_phases(reader, parsed.phases);
    reader.read(OptionId::integration_tolerance, parsed.relative_tolerance);

    // A slow sinusoid makes many cycles a long simulation.
    if (valid_scenario != nullptr && !reader.failed(cycles_name)) {
        const double frequency = valid_scenario->tensions.back.frequency;
        const double simulated = parsed.cycles / frequency;
        if (simulated > max_simulated_time_s) {
            const double most_cycles = std::floor(max_simulated_time_s * frequency);
            std::string detail =
                concat(std::to_string(parsed.cycles), " cycles of the ", format_number(frequency),
                       " Hz back-tension sinusoid (/scenario/tension/back/frequency_Hz) are ",
                       format_number(simulated), " s of simulated time; at most ",
                       format_number(max_simulated_time_s), " s are allowed");
            if (most_cycles < 1.0) {
                detail += concat(": raise the frequency to at least ",
                                 format_number(1.0 / max_simulated_time_s), " Hz");
            }
            errors.add({reader.at(cycles_name), std::move(detail),
                        most_cycles < 1.0 ? std::optional<std::string>()
                                          : closed(1.0, std::min(20.0, most_cycles)).text(),
                        std::string(units::one.code)});
        }
    }
    return parsed;
}

nlohmann::json tension_cycle_options_json(const core::TensionCycleOptions& options) {
    nlohmann::json document = {{phases_name, options.phases}};
    put_option(document, OptionId::cycles, options.cycles);
    put_option(document, OptionId::integration_tolerance, options.relative_tolerance);
    return document;
}

void check_tension_cycle_scenario(const core::Scenario& scenario,
                                  const std::string& scenario_pointer, FieldErrors& errors) {
    if (scenario.tensions.back.mode == core::TensionMode::sinusoid)
        return;  // checked with the scenario
    core::Scenario as_run = scenario;
    as_run.tensions.back.mode = core::TensionMode::sinusoid;
    FieldErrors sinusoid_errors;
    check_scenario_consistency(as_run, scenario_pointer, sinusoid_errors);
    for (FieldError error : sinusoid_errors.reported()) {
        error.detail = concat("tension_cycle runs the back tension as a sinusoid: ", error.detail);
        errors.add(std::move(error));
    }
}

const ResultTable<core::PhaseDistribution>& tension_phase_table() {
    using core::PhaseDistribution;
    static const ResultTable<PhaseDistribution> table{
        "TensionCyclePhase",
        "The bite at one phase of the back-tension cycle.",
        {
            {"phase", "Phase T in the cycle, s_b = mean + amplitude·sin 2πT.",
             number_schema(units::one),
             [](const PhaseDistribution& p) { return quantity_json(p.phase, units::one); }},
            {"time_s", "Simulated time of the phase, in the last cycle.",
             number_schema(units::second),
             [](const PhaseDistribution& p) { return quantity_json(p.time, units::second); }},
            {"back_tension_MPa", "Back tension at this phase.", number_schema(units::megapascal),
             [](const PhaseDistribution& p) {
                 return quantity_json(p.back_tension, units::megapascal);
             }},
            {"gap_um", "Change of the work-roll gap (x3 − x4) from its steady value.",
             number_schema(units::micrometre),
             [](const PhaseDistribution& p) { return quantity_json(p.gap, units::micrometre); }},
            {"inlet_film_um", "Lubricant film thickness at the bite inlet.",
             number_schema(units::micrometre),
             [](const PhaseDistribution& p) {
                 return quantity_json(p.inlet_film, units::micrometre);
             }},
            {"roll_gap", "The bite at this phase, with its distributions.",
             ref_schema("RollGapResult"),
             [](const PhaseDistribution& p) { return bite_result_json(p.bite); }},
        }};
    return table;
}

const ResultTable<core::TensionCycleResult>& tension_cycle_result_table() {
    using core::TensionCycleResult;
    static const ResultTable<TensionCycleResult> table{
        "TensionCycleResult",
        "The bite at phases of a sinusoidal back tension, from the coupled model run over whole cycles "
        "(docs/model.md §7.2).",
        {
            {"status",
             "`ok`, `no_steady_state` (no steady bite to start from: steady_status says why), or what ended the run "
             "early.",
             enum_schema({"ok", "no_steady_state", "contact_lost", "skidding", "slack_strip",
                          "solver_failure"}),
             [](const TensionCycleResult& r) { return nlohmann::json(run_status(r)); }},
            {"message", "Why, for humans; empty when ok.", string_schema(),
             [](const TensionCycleResult& r) {
                 return nlohmann::json(r.message != nullptr ? r.message : "");
             }},
            {"steady_status", "The status of the steady bite the run starts from.",
             enum_schema({"ok", "skidding", "contact_lost", "solver_failure"}),
             [](const TensionCycleResult& r) {
                 return nlohmann::json(core::to_string(r.steady_status));
             }},
            {"frequency_Hz", "Frequency of the back-tension sinusoid.", number_schema(units::hertz),
             [](const TensionCycleResult& r) {
                 return quantity_json(r.frequency_Hz, units::hertz);
             }},
            {"phases", "One per phase of options.phases, ascending.",
             array_schema(ref_schema("TensionCyclePhase")),
             [](const TensionCycleResult& r) {
                 nlohmann::json phases = nlohmann::json::array();
                 for (const core::PhaseDistribution& phase : r.phases)
                     phases.push_back(tension_phase_table().write(phase));
                 return phases;
             }},
        }};
    return table;
}

std::vector<ResultSchema> tension_cycle_result_schemas() {
    return {result_schema(tension_phase_table()), result_schema(tension_cycle_result_table())};
}

nlohmann::json tension_cycle_result_json(const core::TensionCycleResult& result) {
    return tension_cycle_result_table().write(result);
}

}  // namespace rollgap::api
