#include "api/option_names.h"
#include "api/sweep_json.h"

#include <array>
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>

#include "api/amplitude_json.h"
#include "api/chatter_json.h"
#include "api/json_pointer.h"
#include "api/name_suggestion.h"
#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/result_table.h"
#include "api/scenario_json.h"
#include "api/stability_json.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::string_view parameter_name = "parameter";
constexpr std::string_view values_name = "values";
constexpr std::string_view range_name = "range";
constexpr std::string_view quantity_name = "quantity";
constexpr std::array<std::string_view, 6> sweep_members{
    parameter_name, values_name, range_name, quantity_name, critical_speed_name, amplitude_name};
constexpr std::array<std::string_view, 2> quantities{"critical_speed", "amplitude"};
constexpr std::array<std::string_view, 3> range_members{"from", "to", "count"};

bool numeric(const ScenarioField& field) {
    return field.kind == FieldKind::number || field.kind == FieldKind::integer;
}

const std::vector<std::string_view>& numeric_paths() {
    static const std::vector<std::string_view> paths = [] {
        std::vector<std::string_view> numeric_fields;
        for (const ScenarioField& field : scenario_fields()) {
            if (numeric(field)) numeric_fields.push_back(field.path);
        }
        return numeric_fields;
    }();
    return paths;
}

const ScenarioField* numeric_field(std::string_view path) {
    const ScenarioField* field = find_scenario_field(path);
    return field != nullptr && numeric(*field) ? field : nullptr;
}

std::string_view kind_name(FieldKind kind) {
    switch (kind) {
        case FieldKind::number: return "number";
        case FieldKind::integer: return "integer";
        case FieldKind::boolean: return "boolean";
        case FieldKind::choice: return "choice";
    }
    return "unknown";
}

// The field a parameter names, or nullptr with the violation recorded.
const ScenarioField* read_parameter(const OptionsReader& reader) {
    const std::string pointer = reader.at(parameter_name);
    const nlohmann::json* value = reader.find(parameter_name);
    if (value == nullptr) {
        reader.errors().add(
            {pointer,
             "required: the JSON pointer of the numeric scenario field to sweep, e.g. "
             "\"/lubricant/viscosity_Pa_s\"",
             std::nullopt, std::nullopt});
        return nullptr;
    }
    const auto path = read_string(*value, pointer, reader.errors());
    if (!path) return nullptr;
    if (const ScenarioField* field = numeric_field(*path)) return field;

    const std::string bound = choices_text(numeric_paths());
    std::string detail;
    if (const ScenarioField* field = find_scenario_field(*path)) {
        detail = concat(quoted_for_message(*path), " is a ", kind_name(field->kind),
                        " field; a sweep needs a numeric one");
    } else if (is_scenario_group(*path)) {
        detail = concat(quoted_for_message(*path), " is a group of fields, not a field");
    } else {
        detail = concat(
            quoted_for_message(*path),
            " is not a field of the scenario: give a JSON pointer into the scenario document "
            "(as 'rollgap scenario' prints it), e.g. \"/lubricant/viscosity_Pa_s\"");
        // The usual slips: no leading '/', the request's "/scenario" prefix, a typo.
        std::optional<std::string_view> suggestion;
        if (!path->starts_with('/') && numeric_field(concat("/", *path)) != nullptr) {
            suggestion = numeric_field(concat("/", *path))->path;
        } else if (path->starts_with("/scenario/") && numeric_field(path->substr(9)) != nullptr) {
            suggestion = numeric_field(path->substr(9))->path;
        } else {
            suggestion = closest_name(*path, numeric_paths());
        }
        detail += did_you_mean(suggestion);
    }
    reader.errors().add({pointer, std::move(detail), bound, std::nullopt});
    return nullptr;
}

// Nicer echoes for computed range points: 12 significant digits (0.30000000000000004 → 0.3).
double tidy(double value) {
    std::array<char, 32> text{};
    const auto written = std::to_chars(text.data(), text.data() + text.size(), value,
                                       std::chars_format::general, 12);
    double tidied = value;
    std::from_chars(text.data(), written.ptr, tidied);
    return tidied;
}

using Point = SweepPoint;

}  // namespace

std::optional<std::vector<SweepPoint>> read_sweep_points(const OptionsReader& reader,
                                                         nlohmann::json& echo_values,
                                                         int max_points) {
    const nlohmann::json* values = reader.find(values_name);
    const nlohmann::json* range = reader.find(range_name);
    FieldErrors& errors = reader.errors();
    if ((values == nullptr) == (range == nullptr)) {
        errors.add({values == nullptr ? reader.at(values_name) : reader.at(range_name),
                    values == nullptr ? "required: the values to sweep, as \"values\": [...] or "
                                        "\"range\": {\"from\", \"to\", \"count\"}"
                                      : "give either \"values\" or \"range\", not both",
                    std::nullopt, std::nullopt});
        return std::nullopt;
    }
    const std::string count_bound = concat("1 to ", std::to_string(max_points), " values");
    std::vector<Point> points;
    if (values != nullptr) {
        const std::string pointer = reader.at(values_name);
        if (!values->is_array()) {
            errors.add({pointer,
                        concat("must be an array of values, got ", json_type_name(*values)),
                        std::nullopt, std::nullopt});
            return std::nullopt;
        }
        if (values->empty() || values->size() > static_cast<std::size_t>(max_points)) {
            errors.add(
                {pointer,
                 concat("has ", std::to_string(values->size()), " values; give ", count_bound),
                 count_bound, std::nullopt});
            return std::nullopt;
        }
        for (std::size_t i = 0; i < values->size(); ++i) {
            points.push_back(
                {(*values)[i], append_pointer(pointer, std::to_string(i)), std::nullopt});
        }
        echo_values = {{values_name, *values}};
        return points;
    }

    const OptionsReader range_reader(*range, reader.at(range_name), range_members, errors);
    if (!range_reader.is_object()) return std::nullopt;
    bool valid = true;
    std::optional<double> ends[2];
    for (int end = 0; end < 2; ++end) {
        const std::string_view name = range_members[static_cast<std::size_t>(end)];
        const nlohmann::json* value = range_reader.find(name);
        if (value == nullptr) {
            errors.add({range_reader.at(name),
                        concat("required: the ", end == 0 ? "first" : "last",
                               " value of the range, in the parameter's unit"),
                        std::nullopt, std::nullopt});
            valid = false;
        } else if (!value->is_number() || !std::isfinite(value->get<double>())) {
            // Bounds are the field's: checked with the scenario below.
            errors.add({range_reader.at(name),
                        concat("must be a number, got ", json_type_name(*value)), std::nullopt,
                        std::nullopt});
            valid = false;
        } else {
            ends[end] = value->get<double>();
        }
    }
    int count = 0;
    if (range_reader.find("count") == nullptr) {
        errors.add(
            {range_reader.at("count"),
             concat("required: the number of values, in [2, ", std::to_string(max_points), "]"),
             std::nullopt, std::nullopt});
        valid = false;
    } else if (!range_reader.integer("count", closed(2.0, max_points), count)) {
        valid = false;
    }
    if (!valid) return std::nullopt;
    const double from = *ends[0], to = *ends[1];
    for (int i = 0; i < count; ++i) {
        const bool first = i == 0, last = i == count - 1;
        const double value = first ? from : last ? to : tidy(from + (to - from) * i / (count - 1));
        points.push_back({value,
                          first  ? range_reader.at("from")
                          : last ? range_reader.at("to")
                                 : range_reader.pointer(),
                          first || last ? std::nullopt : std::optional<std::size_t>(i)});
    }
    echo_values = {{range_name, {{"from", from}, {"to", to}, {"count", count}}}};
    return points;
}

namespace {

std::string value_text(const nlohmann::json& value) {
    if (value.is_number()) return format_number(value.get<double>());
    return quoted_for_message(value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

// Sets each point into the scenario document and reads it back like a request's scenario.
// Violations of point i are reported at its pointer.
void build_scenarios(const ScenarioField& field, const std::vector<Point>& points,
                     const core::Scenario& scenario, SweepPlan& plan, FieldErrors& errors) {
    const nlohmann::json base = resolved_scenario_json(scenario);
    const nlohmann::json::json_pointer location(field.path);
    const std::string field_pointer = concat("/scenario", field.path);
    bool interior_reported = false;
    for (const Point& point : points) {
        nlohmann::json document = base;
        document[location] = point.value;
        FieldErrors point_errors;
        scenario_from_json(document, "/scenario", point_errors);
        if (point_errors.empty()) {
            // Valid: the request's scenario with exactly this field changed (not the document
            // read back, which could differ from it in the 17th digit of another field).
            const double value = point.value.get<double>();
            core::Scenario swept = scenario;
            set_scenario_field(swept, field, value);
            plan.values.push_back(value);
            plan.scenarios.push_back(swept);
            continue;
        }
        // Inside a range only the first failing point is reported: the rest say the same.
        if (point.range_index) {
            if (interior_reported) continue;
            interior_reported = true;
        }
        const std::string where = point.range_index
                                      ? concat("point ", std::to_string(*point.range_index),
                                               " of the range (", value_text(point.value), "): ")
                                      : std::string();
        for (const FieldError& error : point_errors.reported()) {
            if (error.pointer == field_pointer) {
                errors.add({point.pointer, concat(where, error.detail), error.bound, error.unit});
            } else {
                // A cross-field rule: the value is fine for the field but not with the rest.
                errors.add(
                    {point.pointer,
                     concat(where, "with ", field.path, " = ", value_text(point.value),
                            " the scenario is invalid at ", error.pointer, ": ", error.detail),
                     std::nullopt, std::nullopt});
            }
        }
    }
}

void reject_other_quantity(const OptionsReader& reader, std::string_view member,
                           std::string_view quantity) {
    if (!reader.given(member)) return;  // null: what an echo writes for the other quantity
    reader.errors().add({reader.at(member),
                         concat("applies to quantity '", member,
                                "' only; this sweep's quantity is '", quantity, "'"),
                         std::nullopt, std::nullopt});
}

void check_work(const OptionsReader& reader, SweepPlan& plan, std::size_t point_count) {
    const double n = static_cast<double>(point_count);
    if (plan.quantity == SweepQuantity::amplitude) {
        const std::string window_pointer = append_pointer(reader.at(amplitude_name), "window_s");
        if (reader.errors().has_error_at_or_below(window_pointer)) return;
        const double total = n * plan.amplitude.window;
        if (total <= max_sweep_simulated_time_s) return;
        const double longest = std::floor(max_sweep_simulated_time_s / n * 1e6) / 1e6;
        reader.errors().add(
            {window_pointer,
             concat(std::to_string(point_count), " values × window_s ",
                    format_number(plan.amplitude.window), " s = ", format_number(total),
                    " s of simulated time; a sweep may simulate at most ",
                    format_number(max_sweep_simulated_time_s),
                    " s: use fewer values or a shorter window"),
             open_closed(0.0, longest).text(), std::string(units::second.code)});
        return;
    }
    const std::string step_pointer =
        append_pointer(reader.at(critical_speed_name), option_name(OptionId::search_speed_step));
    if (reader.errors().has_error_at_or_below(reader.at(critical_speed_name))) return;
    const long scan = scan_point_count(plan.critical_speed);
    const long total = static_cast<long>(point_count) * scan;
    if (total <= max_sweep_scan_points) return;
    reader.errors().add(
        {step_pointer,
         concat(
             std::to_string(point_count), " values × ", std::to_string(scan),
             " scan speeds each = ", std::to_string(total),
             " stability evaluations; a sweep may do at most ",
             std::to_string(max_sweep_scan_points), " (",
             std::to_string(max_sweep_scan_points / static_cast<long>(point_count)),
             " scan speeds per value here): use fewer values, a larger step or a narrower speed range"),
         std::nullopt, std::nullopt});
}

}  // namespace

void set_scenario_field(core::Scenario& scenario, const ScenarioField& field, double value) {
    if (field.kind == FieldKind::integer) {
        field.integer(scenario) = static_cast<int>(value);  // validated: an integer in range
    } else {
        field.number(scenario) = to_si(value + 0.0, field.unit);
    }
}

SweepAxis sweep_axis_from_json(const nlohmann::json& axis, const std::string& pointer,
                               const core::Scenario* valid_scenario, FieldErrors& errors) {
    static constexpr std::array<std::string_view, 3> axis_members{parameter_name, values_name,
                                                                  range_name};
    SweepAxis out;
    const OptionsReader reader(axis, pointer, axis_members, errors);
    if (!reader.is_object()) return out;
    out.field = read_parameter(reader);
    nlohmann::json echo_values;
    const auto points = read_sweep_points(reader, echo_values, max_sweep_points);
    if (out.field != nullptr && points && valid_scenario != nullptr) {
        SweepPlan plan;
        build_scenarios(*out.field, *points, *valid_scenario, plan, errors);
        out.values = std::move(plan.values);
        out.scenarios = std::move(plan.scenarios);
    }
    out.resolved = {{parameter_name, out.field != nullptr ? nlohmann::json(out.field->path)
                                                          : nlohmann::json(nullptr)}};
    if (echo_values.is_object()) out.resolved.update(echo_values);
    return out;
}

SweepPlan sweep_plan_from_json(const nlohmann::json& options, const std::string& pointer,
                               const core::Scenario* valid_scenario, FieldErrors& errors) {
    SweepPlan plan;
    const OptionsReader reader(options, pointer, sweep_members, errors);
    if (!reader.is_object()) return plan;

    plan.field = read_parameter(reader);

    std::string quantity = "critical_speed";
    bool quantity_valid = true;
    if (const nlohmann::json* value = reader.find(quantity_name)) {
        if (auto choice = read_choice(*value, reader.at(quantity_name), quantities, errors)) {
            quantity = std::move(*choice);
        } else {
            quantity_valid = false;
        }
    }
    plan.quantity =
        quantity == "amplitude" ? SweepQuantity::amplitude : SweepQuantity::critical_speed;

    if (plan.field != nullptr && quantity_valid && plan.quantity == SweepQuantity::critical_speed &&
        plan.field->path == "/rolls/speed_m_per_s") {
        errors.add(
            {reader.at(parameter_name),
             "the critical-speed search scans the roll speed itself, so the scenario's speed does not "
             "change it: sweep another field, or sweep the speed with quantity 'amplitude'",
             std::nullopt, std::nullopt});
        plan.field = nullptr;
    }

    nlohmann::json echo_values;
    const auto points = read_sweep_points(reader, echo_values, max_sweep_points);

    nlohmann::json quantity_options;
    if (quantity_valid) {
        if (plan.quantity == SweepQuantity::critical_speed) {
            reject_other_quantity(reader, amplitude_name, quantity);
            plan.critical_speed =
                critical_speed_options_from_json(reader.object_or_defaults(critical_speed_name),
                                                 reader.at(critical_speed_name), errors);
            quantity_options = critical_speed_options_json(plan.critical_speed);
        } else {
            reject_other_quantity(reader, critical_speed_name, quantity);
            const AmplitudeOptions read = amplitude_options_from_json(
                reader.object_or_defaults(amplitude_name), reader.at(amplitude_name),
                AmplitudeMembers::sweep_point, 0.0, errors);
            plan.amplitude = read.run;
            quantity_options = amplitude_options_json(read, AmplitudeMembers::sweep_point);
        }
        if (points) check_work(reader, plan, points->size());
    }

    if (plan.field != nullptr && points && valid_scenario != nullptr) {
        build_scenarios(*plan.field, *points, *valid_scenario, plan, errors);
    }

    plan.resolved_options = {
        {parameter_name,
         plan.field != nullptr ? nlohmann::json(plan.field->path) : nlohmann::json(nullptr)},
        {quantity_name, quantity},
    };
    if (echo_values.is_object()) plan.resolved_options.update(echo_values);
    plan.resolved_options[quantity] = std::move(quantity_options);
    return plan;
}

namespace {

constexpr std::string_view value_pattern = "^value(_[A-Za-z0-9_]+)?$";

const ResultTable<core::CriticalSpeedResult>& critical_point_table() {
    using core::CriticalSpeedResult;
    static const ResultTable<CriticalSpeedResult> table{
        "SweepCriticalSpeedPoint",
        "The critical speed at one value of the swept field, which the point carries under value_name.",
        crossing_members()};
    return table;
}

const ResultTable<core::AmplitudeResult>& amplitude_point_figures_table() {
    static const ResultTable<core::AmplitudeResult> table{
        "SweepAmplitudePoint",
        "The vibration at one value of the swept field, which the point carries under value_name.",
        amplitude_figure_members("frequency_Hz")};
    return table;
}

}  // namespace

nlohmann::json sweep_point_schema(nlohmann::json schema) {
    schema["patternProperties"] = {
        {value_pattern,
         {{"type", "number"},
          {"description", "The swept value, in the field's unit (see value_name)."}}}};
    schema["minProperties"] = schema["required"].size() + 1;
    return schema;
}

std::string sweep_value_name(Unit unit) {
    if (unit.code == "1") return "value";
    std::string name = "value_";
    for (std::size_t i = 0; i < unit.code.size(); ++i) {
        const char c = unit.code[i];
        if (c == '/') {
            name += i == 0 ? "per_" : "_per_";
        } else if (c == '.') {
            name += '_';
        } else {
            name += c;
        }
    }
    return name;
}

namespace {

std::string value_name(Unit unit) { return sweep_value_name(unit); }

template <class Result, class Table>
nlohmann::json points_json(const SweepPlan& plan, const std::vector<Result>& results,
                           std::size_t first, const Table& table) {
    const std::string key = value_name(plan.field->unit);
    nlohmann::json points = nlohmann::json::array();
    for (std::size_t i = 0; i < results.size() && first + i < plan.values.size(); ++i) {
        nlohmann::json point = table.write(results[i]);
        point[key] = plan.values[first + i];
        points.push_back(std::move(point));
    }
    return points;
}

}  // namespace

const ResultTable<SweepOutput>& sweep_result_table() {
    static const ResultTable<SweepOutput> table{
        "SweepResult",
        "The critical speed or the vibration amplitude over the values of one scenario field (docs/model.md §7.5).",
        {
            {"parameter", "The swept field's JSON pointer in the scenario.", string_schema(),
             [](const SweepOutput& o) { return nlohmann::json(o.parameter); }},
            {"unit", "The swept field's unit (UCUM code).", string_schema(),
             [](const SweepOutput& o) { return nlohmann::json(o.unit); }},
            {"value_name",
             "The member under which each point carries its value: value_ and the unit (value_Pa_s, value_m_per_s; "
             "value when dimensionless).",
             {{"type", "string"}, {"pattern", value_pattern}},
             [](const SweepOutput& o) { return nlohmann::json(o.value_name); }},
            {"quantity", "What each point holds.", enum_schema({"critical_speed", "amplitude"}),
             [](const SweepOutput& o) { return nlohmann::json(o.quantity); }},
            {"points", "One per value, in the order of options.values or the range.",
             array_schema({{"oneOf", nlohmann::json::array({ref_schema("SweepCriticalSpeedPoint"),
                                                            ref_schema("SweepAmplitudePoint")})}}),
             [](const SweepOutput& o) { return o.points; }},
            {"chatter_type_changes",
             "Each pair of consecutive values whose crossing modes differ in chatter type; critical_speed sweeps "
             "only.",
             chatter_type_changes_schema({{"type", "number"}}),
             [](const SweepOutput& o) { return o.chatter_type_changes; }, true},
        }};
    return table;
}

std::vector<std::string> sweep_point_columns(bool amplitude) {
    return amplitude ? amplitude_point_figures_table().names() : critical_point_table().names();
}

std::vector<ResultSchema> sweep_result_schemas() {
    return {
        {critical_point_table().component(), sweep_point_schema(critical_point_table().schema())},
        {amplitude_point_figures_table().component(),
         sweep_point_schema(amplitude_point_figures_table().schema())},
        result_schema(sweep_result_table())};
}

nlohmann::json sweep_critical_speed_points_json(
    const SweepPlan& plan, const std::vector<core::CriticalSpeedResult>& results,
    std::size_t first) {
    return points_json(plan, results, first, critical_point_table());
}

nlohmann::json sweep_amplitude_points_json(const SweepPlan& plan,
                                           const std::vector<core::AmplitudeResult>& results,
                                           std::size_t first) {
    return points_json(plan, results, first, amplitude_point_figures_table());
}

nlohmann::json sweep_result_json(const SweepPlan& plan, nlohmann::json points) {
    const bool critical = plan.quantity == SweepQuantity::critical_speed;
    // The changes need each point's neighbour, which a chunk may not hold: they are derived
    // here, from the documents of all points, never carried in them.
    nlohmann::json changes =
        critical
            ? chatter_type_changes_json(
                  points, core::sequence_neighbours(static_cast<int>(points.size())),
                  [&](int i) { return nlohmann::json(plan.values[static_cast<std::size_t>(i)]); })
            : absent();
    return sweep_result_table().write(
        {plan.field->path, plan.field->unit.code, value_name(plan.field->unit),
         critical ? "critical_speed" : "amplitude", std::move(points), std::move(changes)});
}

nlohmann::json sweep_critical_speed_json(const SweepPlan& plan,
                                         const std::vector<core::CriticalSpeedResult>& results) {
    return sweep_result_json(plan, sweep_critical_speed_points_json(plan, results, 0));
}

nlohmann::json sweep_amplitude_json(const SweepPlan& plan,
                                    const std::vector<core::AmplitudeResult>& results) {
    return sweep_result_json(plan, sweep_amplitude_points_json(plan, results, 0));
}

}  // namespace rollgap::api
