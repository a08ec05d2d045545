#include "api/option_names.h"
#include "api/map_json.h"

#include <string_view>

#include "api/chatter_json.h"
#include "api/json_pointer.h"
#include "api/options_reader.h"
#include "api/result_table.h"
#include "api/scenario_consistency.h"
#include "api/stability_json.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::string_view parameters_name = "parameters";
constexpr std::array<std::string_view, 2> map_members{parameters_name, critical_speed_name};
constexpr std::string_view speed_path = "/rolls/speed_m_per_s";

// The two axes, or fewer with the violation recorded.
void read_axes(const OptionsReader& reader, const core::Scenario* valid_scenario, MapPlan& plan) {
    const std::string pointer = reader.at(parameters_name);
    const nlohmann::json* parameters = reader.find(parameters_name);
    FieldErrors& errors = reader.errors();
    if (parameters == nullptr || !parameters->is_array() || parameters->size() != 2) {
        errors.add(
            {pointer,
             parameters == nullptr
                 ? "required: the two scenario fields of the map, [{\"parameter\", \"values\" | \"range\"}, {...}]"
                 : concat("must be an array of exactly two fields, got ",
                          parameters->is_array()
                              ? concat(std::to_string(parameters->size()), " items")
                              : std::string(json_type_name(*parameters))),
             "2 fields", std::nullopt});
        return;
    }
    for (std::size_t k = 0; k < 2; ++k) {
        const std::string at = append_pointer(pointer, std::to_string(k));
        plan.axes[k] = sweep_axis_from_json((*parameters)[k], at, valid_scenario, errors);
        const ScenarioField* field = plan.axes[k].field;
        if (field != nullptr && field->path == speed_path) {
            errors.add(
                {append_pointer(at, "parameter"),
                 "the critical-speed search scans the roll speed itself: map two other fields",
                 std::nullopt, std::nullopt});
            plan.axes[k].field = nullptr;
        }
    }
    if (plan.axes[0].field != nullptr && plan.axes[0].field == plan.axes[1].field) {
        errors.add({append_pointer(append_pointer(pointer, "1"), "parameter"),
                    concat("names the same field as the first parameter (",
                           plan.axes[0].field->path, "): a map needs two different fields"),
                    std::nullopt, std::nullopt});
        plan.axes[1].field = nullptr;
    }
}

std::size_t axis_count(const nlohmann::json& resolved) {
    if (resolved.contains("values")) return resolved["values"].size();
    if (resolved.contains("range")) return resolved["range"].value("count", std::size_t{0});
    return 0;
}

// Both values set: each passed its own field's checks; together they must pass the
// cross-field rules. Only the first failing cell is reported: the rest usually say the same.
void build_cells(MapPlan& plan, const std::string& pointer, FieldErrors& errors) {
    const SweepAxis& rows = plan.axes[0];
    const SweepAxis& columns = plan.axes[1];
    plan.cells.reserve(rows.scenarios.size() * columns.values.size());
    for (std::size_t i = 0; i < rows.scenarios.size(); ++i) {
        for (std::size_t j = 0; j < columns.values.size(); ++j) {
            core::Scenario cell = rows.scenarios[i];
            set_scenario_field(cell, *columns.field, columns.values[j]);
            FieldErrors cell_errors;
            check_scenario_consistency(cell, "/scenario", cell_errors);
            if (cell_errors.empty()) {
                plan.cells.push_back(cell);
                continue;
            }
            const FieldError& first = cell_errors.reported().front();
            errors.add(
                {pointer,
                 concat("with ", rows.field->path, " = ", format_number(rows.values[i]), " and ",
                        columns.field->path, " = ", format_number(columns.values[j]),
                        " the scenario is invalid at ", first.pointer, ": ", first.detail),
                 std::nullopt, std::nullopt});
            plan.cells.clear();
            return;
        }
    }
}

}  // namespace

MapPlan map_plan_from_json(const nlohmann::json& options, const std::string& pointer,
                           const core::Scenario* valid_scenario, FieldErrors& errors) {
    MapPlan plan;
    const OptionsReader reader(options, pointer, map_members, errors);
    if (!reader.is_object()) return plan;
    read_axes(reader, valid_scenario, plan);
    plan.critical_speed = critical_speed_options_from_json(
        reader.object_or_defaults(critical_speed_name), reader.at(critical_speed_name), errors);

    // The bounds, on the counts the client asked for (valid values or not).
    const long cells = static_cast<long>(axis_count(plan.axes[0].resolved)) *
                       static_cast<long>(axis_count(plan.axes[1].resolved));
    if (cells > max_map_cells) {
        errors.add(
            {reader.at(parameters_name),
             concat(std::to_string(axis_count(plan.axes[0].resolved)), " × ",
                    std::to_string(axis_count(plan.axes[1].resolved)), " = ", std::to_string(cells),
                    " cells; a map may have at most ", std::to_string(max_map_cells)),
             concat("at most ", std::to_string(max_map_cells), " cells"), std::nullopt});
    } else if (!errors.has_error_at_or_below(reader.at(critical_speed_name))) {
        const long total = cells * scan_point_count(plan.critical_speed);
        if (total > max_sweep_scan_points) {
            errors.add({append_pointer(reader.at(critical_speed_name), "speed_step_m_per_s"),
                        concat(std::to_string(cells), " cells × ",
                               std::to_string(scan_point_count(plan.critical_speed)),
                               " scan speeds each = ", std::to_string(total),
                               " stability evaluations; a map may do at most ",
                               std::to_string(max_sweep_scan_points),
                               ": use fewer values, a larger step or a narrower speed range"),
                        std::nullopt, std::nullopt});
        }
    }
    if (errors.empty() && plan.axes[0].field != nullptr && plan.axes[1].field != nullptr) {
        build_cells(plan, reader.at(parameters_name), errors);
    }
    plan.resolved_options = {
        {parameters_name, nlohmann::json::array({plan.axes[0].resolved, plan.axes[1].resolved})},
        {critical_speed_name, critical_speed_options_json(plan.critical_speed)},
    };
    return plan;
}

namespace {

// A cell as written: its pair of values and its critical-speed outcome.
struct MapCellView {
    nlohmann::json values;
    const core::CriticalSpeedResult& result;
};

const ResultTable<MapCellView>& map_cell_table() {
    static const ResultTable<MapCellView> table{
        "MapCell",
        "The critical speed at one cell of the map: the first field at values[0], the second at values[1].",
        [] {
            std::vector<Member<MapCellView>> members{
                {"values",
                 "The cell's values of the two fields, [first, second], each in its field's unit.",
                 array_schema({{"type", "number"}}),
                 [](const MapCellView& cell) { return cell.values; }},
            };
            for (Member<MapCellView>& member :
                 lift<MapCellView>(crossing_members(),
                                   [](const MapCellView& cell) -> const core::CriticalSpeedResult& {
                                       return cell.result;
                                   })) {
                members.push_back(std::move(member));
            }
            return members;
        }()};
    return table;
}

const ResultTable<SweepAxis>& map_parameter_table() {
    static const ResultTable<SweepAxis> table{
        "MapParameter",
        "One field of the map and its values.",
        {
            {"parameter", "The field's JSON pointer in the scenario.", string_schema(),
             [](const SweepAxis& axis) { return nlohmann::json(axis.field->path); }},
            {"unit", "The field's unit (UCUM code); the values are in it.", string_schema(),
             [](const SweepAxis& axis) { return nlohmann::json(axis.field->unit.code); }},
            {"values", "The field's values, in the order of options.parameters' values or range.",
             array_schema({{"type", "number"}}),
             [](const SweepAxis& axis) { return nlohmann::json(axis.values); }},
        }};
    return table;
}

// The pair of values of a cell (row-major index).
nlohmann::json values_of(const MapPlan& plan, std::size_t cell) {
    const std::size_t columns = plan.axes[1].values.size();
    return nlohmann::json::array(
        {plan.axes[0].values[cell / columns], plan.axes[1].values[cell % columns]});
}

struct MapOutput {
    const MapPlan& plan;
    nlohmann::json cells;  // the cells' documents, row-major
};

const ResultTable<MapOutput>& map_result_table() {
    static const ResultTable<MapOutput> table{
        "MapResult",
        "The critical speed, its frequency and chatter type over a grid of two scenario fields "
        "(docs/model.md §10.2).",
        {
            {"parameters", "The two fields: [rows, columns].",
             array_schema(ref_schema("MapParameter")),
             [](const MapOutput& o) {
                 nlohmann::json parameters = nlohmann::json::array();
                 for (const SweepAxis& axis : o.plan.axes)
                     parameters.push_back(map_parameter_table().write(axis));
                 return parameters;
             }},
            {"cells", "One per pair of values, row-major (the second field varies fastest).",
             array_schema(ref_schema("MapCell")), [](const MapOutput& o) { return o.cells; }},
            {"chatter_type_changes",
             "Each pair of neighbouring cells (along either field) whose crossing modes differ in chatter type.",
             chatter_type_changes_schema(array_schema({{"type", "number"}})),
             [](const MapOutput& o) {
                 // From the documents of all cells: a cell's neighbours may have been computed
                 // in another chunk.
                 return chatter_type_changes_json(
                     o.cells,
                     core::grid_neighbours(static_cast<int>(o.plan.axes[0].values.size()),
                                           static_cast<int>(o.plan.axes[1].values.size())),
                     [&o](int cell) { return values_of(o.plan, static_cast<std::size_t>(cell)); });
             }},
        }};
    return table;
}

}  // namespace

std::vector<std::string> map_cell_columns() { return map_cell_table().scalar_names(); }

std::vector<ResultSchema> map_result_schemas() {
    return {result_schema(map_parameter_table()), result_schema(map_cell_table()),
            result_schema(map_result_table())};
}

nlohmann::json map_cells_json(const MapPlan& plan,
                              const std::vector<core::CriticalSpeedResult>& results,
                              std::size_t first) {
    nlohmann::json cells = nlohmann::json::array();
    for (std::size_t c = 0; c < results.size(); ++c)
        cells.push_back(map_cell_table().write({values_of(plan, first + c), results[c]}));
    return cells;
}

nlohmann::json map_result_json(const MapPlan& plan, nlohmann::json cells) {
    return map_result_table().write({plan, std::move(cells)});
}

nlohmann::json map_json(const MapPlan& plan, const core::StabilityMap& map) {
    return map_result_json(plan, map_cells_json(plan, map.cells, 0));
}

}  // namespace rollgap::api
