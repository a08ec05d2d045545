#include "api/tandem_map_json.h"

#include <string_view>

#include "api/chatter_json.h"
#include "api/json_pointer.h"
#include "api/options_reader.h"
#include "api/sweep_json.h"
#include "api/tandem_json.h"
#include "api/text.h"
#include "core/map.h"

namespace rollgap::api {
// Named, not anonymous: the unity build puts this file beside the stand's map and the mill
// sweep, whose anonymous helpers have the same names.
namespace tandem_map_detail {

using nlohmann::json;

constexpr std::string_view parameters_name = "parameters";
constexpr std::array<std::string_view, 3> map_members{parameters_name, "quantity",
                                                      "critical_speed"};
constexpr std::array<std::string_view, 3> axis_members{"parameter", "values", "range"};
constexpr std::string_view mill_speed = "/speed_m_per_s";

std::size_t requested_count(const json& resolved) {
    if (resolved.contains("values")) return resolved["values"].size();
    if (resolved.contains("range")) return resolved["range"].value("count", std::size_t{0});
    return 0;
}

// One axis: its parameter and values, each value checked alone against the mill. Returns false
// (with the violation recorded) when the axis is unusable.
bool read_axis(const json& options, const std::string& pointer, const json* document,
               const TandemPointSpec& spec, TandemMapAxis& axis, FieldErrors& errors) {
    const OptionsReader reader(options, pointer, axis_members, errors);
    if (!reader.is_object()) return false;
    const auto parameter = read_tandem_parameter(reader, document, axis.unit);
    json echo_values;
    const auto points = read_sweep_points(reader, echo_values, max_tandem_map_cells);
    axis.resolved = {{"parameter", parameter ? json(*parameter) : json(nullptr)}};
    if (echo_values.is_object()) axis.resolved.update(echo_values);
    if (parameter && *parameter == mill_speed &&
        spec.quantity == TandemSweepQuantity::critical_speed) {
        errors.add({reader.at("parameter"),
                    "the critical-speed search scans the mill speed itself: map two other "
                    "numbers, or the mill speed with quantity \"stability\"",
                    std::nullopt, std::nullopt});
        return false;
    }
    if (!parameter || !points) return false;
    axis.parameter = *parameter;
    if (document == nullptr) return false;
    const std::size_t before = errors.reported().size();
    axis.values = tandem_values(*points, *document, axis.parameter, errors).values;
    return errors.reported().size() == before;
}

// Both values of every cell written into the document: each value passed alone; together they
// must pass the mill's rules. Only the first failing cell is reported: the rest usually say the
// same.
void build_cells(TandemMapPlan& plan, const json& document, const std::string& pointer,
                 FieldErrors& errors) {
    const TandemMapAxis& rows = plan.axes[0];
    const TandemMapAxis& columns = plan.axes[1];
    plan.cells.reserve(rows.values.size() * columns.values.size());
    for (const double row : rows.values) {
        const json with_row = with_tandem_value(document, rows.parameter, row);
        for (const double column : columns.values) {
            FieldErrors cell_errors;
            core::Mill cell = mill_from_json(with_tandem_value(with_row, columns.parameter, column),
                                             "/tandem", cell_errors);
            if (cell_errors.empty()) {
                plan.cells.push_back(std::move(cell));
                continue;
            }
            const FieldError& first = cell_errors.reported().front();
            errors.add({pointer,
                        concat("with ", rows.parameter, " = ", format_number(row), " and ",
                               columns.parameter, " = ", format_number(column),
                               " the mill is invalid at ", first.pointer, ": ", first.detail),
                        std::nullopt, std::nullopt});
            plan.cells.clear();
            return;
        }
    }
}

// The pair of values of a cell (row-major index).
json values_of(const TandemMapPlan& plan, std::size_t cell) {
    const std::size_t columns = plan.axes[1].values.size();
    return json::array({plan.axes[0].values[cell / columns], plan.axes[1].values[cell % columns]});
}

// A cell's schema: a point's members and the pair of values.
json cell_schema(TandemSweepQuantity quantity) {
    json schema = tandem_point_schema(quantity);
    schema["description"] =
        concat(schema.value("description", std::string()),
               " A cell of a mill map: the first number at values[0], the second at values[1].");
    schema["properties"]["values"] = {
        {"type", "array"},
        {"items", {{"type", "number"}}},
        {"minItems", 2},
        {"maxItems", 2},
        {"description",
         "The cell's values of the two numbers, [first, second], each in its unit."}};
    schema["required"].push_back("values");
    return schema;
}

constexpr std::string_view critical_cell = "TandemMapCriticalSpeedCell";
constexpr std::string_view stability_cell = "TandemMapStabilityCell";

const ResultTable<TandemMapAxis>& parameter_table() {
    static const ResultTable<TandemMapAxis> table{
        "TandemMapParameter",
        "One number of a mill map and its values.",
        {
            {"parameter", "The number's JSON pointer in the tandem document.", string_schema(),
             [](const TandemMapAxis& axis) { return json(axis.parameter); }},
            {"unit", "Its unit (UCUM code); the values are in it.", string_schema(),
             [](const TandemMapAxis& axis) { return json(axis.unit.code); }},
            {"values", "Its values, in the order of the options' values or range.",
             array_schema({{"type", "number"}}),
             [](const TandemMapAxis& axis) { return json(axis.values); }},
        }};
    return table;
}

struct MapOutput {
    const TandemMapPlan& plan;
    json cells;
    json chatter_type_changes;
};

const ResultTable<MapOutput>& result_table() {
    static const ResultTable<MapOutput> table{
        "TandemMapResult",
        "A mill map: the mill's critical speeds or its stability over a grid of two numbers of "
        "its document (docs/model.md §12.10).",
        {
            {"parameters", "The two numbers: [rows, columns].",
             array_schema(ref_schema("TandemMapParameter")),
             [](const MapOutput& o) {
                 json parameters = json::array();
                 for (const TandemMapAxis& axis : o.plan.axes)
                     parameters.push_back(parameter_table().write(axis));
                 return parameters;
             }},
            {"quantity", "What each cell holds.", enum_schema({"critical_speed", "stability"}),
             [](const MapOutput& o) { return json(to_string(o.plan.spec.quantity)); }},
            {"cells", "One per pair of values, row-major (the second number varies fastest).",
             array_schema(
                 {{"oneOf", json::array({ref_schema(critical_cell), ref_schema(stability_cell)})}}),
             [](const MapOutput& o) { return o.cells; }},
            {"chatter_type_changes",
             "Each pair of neighbouring cells (along either number) whose chatter types by shape "
             "differ (the headline crossing's, or the rightmost root's).",
             chatter_type_changes_schema(array_schema({{"type", "number"}})),
             [](const MapOutput& o) { return o.chatter_type_changes; }},
        }};
    return table;
}

}  // namespace tandem_map_detail

TandemMapPlan tandem_map_plan_from_json(const nlohmann::json& options, const std::string& pointer,
                                        const core::Mill* valid_mill, FieldErrors& errors) {
    using namespace tandem_map_detail;
    TandemMapPlan plan;
    const OptionsReader reader(options, pointer, map_members, errors);
    if (!reader.is_object()) return plan;
    nlohmann::json echo_spec = nlohmann::json::object();
    read_tandem_point_spec(reader, plan.spec, echo_spec);
    const nlohmann::json document =
        valid_mill != nullptr ? resolved_tandem_json(*valid_mill) : nlohmann::json();

    const std::string at = reader.at(parameters_name);
    const nlohmann::json* parameters = reader.find(parameters_name);
    bool axes_valid = false;
    if (parameters == nullptr || !parameters->is_array() || parameters->size() != 2) {
        errors.add({at,
                    parameters == nullptr
                        ? "required: the two numbers of the map, [{\"parameter\", \"values\" | "
                          "\"range\"}, {...}], each a JSON pointer into the tandem document"
                        : concat("must be an array of exactly two numbers, got ",
                                 parameters->is_array()
                                     ? concat(std::to_string(parameters->size()), " items")
                                     : std::string(json_type_name(*parameters))),
                    "2 numbers", std::nullopt});
    } else {
        axes_valid = true;
        for (std::size_t k = 0; k < 2; ++k) {
            axes_valid &= read_axis((*parameters)[k], append_pointer(at, std::to_string(k)),
                                    valid_mill != nullptr ? &document : nullptr, plan.spec,
                                    plan.axes[k], errors);
        }
        const std::string& first = plan.axes[0].parameter;
        const std::string& second = plan.axes[1].parameter;
        if (!first.empty() && !second.empty() && tandem_parameters_overlap(first, second)) {
            errors.add({append_pointer(append_pointer(at, "1"), "parameter"),
                        concat("touches the same number as the first parameter (", first,
                               "): a map needs two different numbers"),
                        std::nullopt, std::nullopt});
            axes_valid = false;
        }
        const long cells = static_cast<long>(requested_count(plan.axes[0].resolved)) *
                           static_cast<long>(requested_count(plan.axes[1].resolved));
        if (cells > max_tandem_map_cells) {
            errors.add({at,
                        concat(std::to_string(requested_count(plan.axes[0].resolved)), " × ",
                               std::to_string(requested_count(plan.axes[1].resolved)), " = ",
                               std::to_string(cells), " cells; a mill map may have at most ",
                               std::to_string(max_tandem_map_cells)),
                        concat("at most ", std::to_string(max_tandem_map_cells), " cells"),
                        std::nullopt});
            axes_valid = false;
        }
    }
    if (axes_valid && errors.empty()) build_cells(plan, document, at, errors);

    plan.resolved_options = {
        {parameters_name, nlohmann::json::array({plan.axes[0].resolved, plan.axes[1].resolved})},
        {"quantity", echo_spec["quantity"]},
    };
    if (echo_spec.contains("critical_speed"))
        plan.resolved_options["critical_speed"] = std::move(echo_spec["critical_speed"]);
    return plan;
}

nlohmann::json tandem_map_cells_json(const TandemMapPlan& plan, std::size_t first,
                                     std::size_t count, const core::Control& control) {
    nlohmann::json cells = nlohmann::json::array();
    for (std::size_t i = first; i < first + count && i < plan.cells.size(); ++i) {
        if (control.should_stop()) break;  // the caller reports the cancellation
        nlohmann::json cell = tandem_point_json(plan.cells[i], plan.spec, control);
        cell["values"] = tandem_map_detail::values_of(plan, i);
        cells.push_back(std::move(cell));
        control.report(static_cast<double>(i + 1 - first) / static_cast<double>(count));
    }
    return cells;
}

nlohmann::json tandem_map_result_json(const TandemMapPlan& plan, nlohmann::json cells) {
    // From the documents of all cells: a cell's neighbours may have been computed in another
    // chunk.
    nlohmann::json changes = chatter_type_changes_json(
        cells,
        core::grid_neighbours(static_cast<int>(plan.axes[0].values.size()),
                              static_cast<int>(plan.axes[1].values.size())),
        [&plan](int cell) {
            return tandem_map_detail::values_of(plan, static_cast<std::size_t>(cell));
        });
    return tandem_map_detail::result_table().write({plan, std::move(cells), std::move(changes)});
}

std::vector<ResultSchema> tandem_map_result_schemas() {
    using namespace tandem_map_detail;
    return {result_schema(parameter_table()),
            {critical_cell, cell_schema(TandemSweepQuantity::critical_speed)},
            {stability_cell, cell_schema(TandemSweepQuantity::stability)},
            result_schema(result_table())};
}

std::span<const CsvTable> tandem_map_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"cells",
         "One row per cell, the two numbers' values first (columns named by their pointers into "
         "the tandem document).",
         "",
         {},
         "",
         [](const nlohmann::json& result) {
             return with_tandem_point_columns(map_value_columns(result), result);
         },
         map_cell_rows}};
    return tables;
}

}  // namespace rollgap::api
