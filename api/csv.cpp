#include "api/csv.h"

#include <algorithm>

#include "api/amplitude_json.h"
#include "api/calibration_json.h"
#include "api/map_json.h"
#include "api/plant_units.h"
#include "api/result_json.h"
#include "api/speed_limit_json.h"
#include "api/stability_json.h"
#include "api/sweep_json.h"
#include "api/tension_cycle_json.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

using nlohmann::json;

template <class Table>
std::function<std::vector<std::string>(const json&)> all_columns(const Table& (*table)()) {
    return [table](const json&) { return table().names(); };
}

template <class Table>
std::function<std::vector<std::string>(const json&)> scalar_columns(const Table& (*table)()) {
    return [table](const json&) { return table().scalar_names(); };
}

const json* at(const json& document, std::string_view pointer) {
    if (pointer.empty()) return &document;
    const json::json_pointer location{std::string(pointer)};
    return document.contains(location) ? &document.at(location) : nullptr;
}

// Per field of a record (the leading columns, then the columns): the plant unit its values
// are converted to, or null for a field that stays as it is. Empty: every field stays.
using Conversions = std::vector<const AlternateUnit*>;

std::string converted_record(std::vector<json> fields, const Conversions& conversions) {
    for (std::size_t i = 0; i < fields.size() && i < conversions.size(); ++i) {
        if (conversions[i] != nullptr && fields[i].is_number())
            fields[i] = plant_value(fields[i].get<double>(), *conversions[i]);
    }
    return csv_record(fields);
}

// Appends the records of one block of rows, each led by `lead`, converted by `conversions`.
bool append_rows(const json& rows, const std::vector<std::string>& columns,
                 const std::vector<json>& lead, const Conversions& conversions, std::string& text) {
    if (rows.is_array()) {
        for (const json& row : rows) {
            if (!row.is_object()) return false;
            std::vector<json> fields = lead;
            for (const std::string& column : columns) fields.push_back(row.value(column, json()));
            text += converted_record(std::move(fields), conversions);
        }
        return true;
    }
    if (!rows.is_object()) return false;
    std::size_t length = 0;
    for (const std::string& column : columns) {
        if (rows.contains(column) && rows[column].is_array())
            length = std::max(length, rows[column].size());
    }
    for (std::size_t i = 0; i < length; ++i) {
        std::vector<json> fields = lead;
        for (const std::string& column : columns) {
            const json* values = rows.contains(column) ? &rows[column] : nullptr;
            fields.push_back(values != nullptr && values->is_array() && i < values->size()
                                 ? (*values)[i]
                                 : json());
        }
        text += converted_record(std::move(fields), conversions);
    }
    return true;
}

std::string table_names(std::span<const CsvTable> offered) {
    std::string names;
    for (const CsvTable& table : offered) names += concat(names.empty() ? "" : ", ", table.name);
    return names;
}

}  // namespace

// A map's value columns: the two fields' pointers without the leading slash ("strip/reduction").
std::vector<std::string> map_value_columns(const json& result) {
    std::vector<std::string> names;
    for (const json& parameter : result.value("parameters", json::array())) {
        names.push_back(parameter.value("parameter", std::string()).substr(1));
    }
    return names;
}

json map_cell_rows(const json& result) {
    const std::vector<std::string> names = map_value_columns(result);
    json rows = json::array();
    for (const json& cell : result.value("cells", json::array())) {
        json row = cell;
        const json values = row.value("values", json::array());
        row.erase("values");
        for (std::size_t k = 0; k < names.size() && k < values.size(); ++k)
            row[names[k]] = values[k];
        rows.push_back(std::move(row));
    }
    return rows;
}

std::span<const CsvTable> roll_gap_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"distribution",
         "Quantities along the bite, one row per integration point.",
         "",
         {},
         "/distribution",
         all_columns(&bite_distribution_table)}};
    return tables;
}

std::span<const CsvTable> tension_cycle_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"distributions",
         "The bite's distributions at each phase, one row per phase and integration point.",
         "/phases",
         {{"phase", "phase"}, {"time_s", "time_s"}, {"back_tension_MPa", "back_tension_MPa"}},
         "/roll_gap/distribution",
         all_columns(&bite_distribution_table)},
        {"phases", "One row per phase.", "", {}, "/phases", scalar_columns(&tension_phase_table)}};
    return tables;
}

std::span<const CsvTable> stability_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"scan",
         "The critical-speed scan, one row per speed.",
         "",
         {},
         "/critical_speed/scan",
         scalar_columns(&scan_point_table)},
        {"damping_branches",
         "The damping ratio of each oscillatory mode over the scan, one row per mode and speed.",
         "/critical_speed/damping_branches",
         {{"branch", ""}},
         "",
         all_columns(&damping_branch_table)},
        {"eigenvalues",
         "The eigenvalues at the scenario's speed.",
         "",
         {},
         "/eigenvalues",
         all_columns(&eigenvalue_table)}};
    return tables;
}

std::span<const CsvTable> amplitude_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"points", "One row per speed.", "", {}, "/points", scalar_columns(&amplitude_point_table)},
        {"time_series",
         "The decimated time series of each speed (options.time_series), one row per sample.",
         "/points",
         {{"speed_m_per_s", "speed_m_per_s"}},
         "/time_series",
         all_columns(&time_series_table)},
        {"windows",
         "The ten 10 % windows of each speed.",
         "/points",
         {{"speed_m_per_s", "speed_m_per_s"}},
         "/windows",
         all_columns(&amplitude_window_table)}};
    return tables;
}

std::span<const CsvTable> sweep_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"points",
         "One row per swept value, the value first.",
         "",
         {},
         "/points",
         [](const json& result) {
             std::vector<std::string> columns{result.value("value_name", std::string("value"))};
             for (std::string& name :
                  sweep_point_columns(result.value("quantity", std::string()) == "amplitude")) {
                 columns.push_back(std::move(name));
             }
             return columns;
         }}};
    return tables;
}

std::span<const CsvTable> calibration_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"parameters",
         "One row per fitted field.",
         "",
         {},
         "/parameters",
         [](const json&) { return calibration_parameter_columns(); }},
        {"observations", "One row per observation.", "", {}, "/observations", [](const json&) {
             return calibration_observation_columns();
         }}};
    return tables;
}

std::span<const CsvTable> speed_limit_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"limits", "One row per checked limit.", "", {}, "/limits", [](const json&) {
             return speed_limit_check_columns();
         }}};
    return tables;
}

namespace {

std::vector<std::string> map_columns(const json& result) {
    std::vector<std::string> columns = map_value_columns(result);
    for (std::string& name : map_cell_columns()) columns.push_back(std::move(name));
    return columns;
}

}  // namespace

std::span<const CsvTable> map_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"cells",
         "One row per cell, the two fields' values first (columns named by their scenario pointers).",
         "",
         {},
         "",
         map_columns,
         map_cell_rows}};
    return tables;
}

std::string csv_field(const json& value) {
    if (value.is_null()) return {};
    std::string text = value.is_string() ? value.get<std::string>() : value.dump();
    // A text cell a spreadsheet would read as a formula (= + - @, or a tab or CR first: a coil
    // label "=HYPERLINK(...)" from a client) is written with a leading apostrophe, quoted, so it
    // opens as the text it is (OWASP, "CSV injection"). Numbers are numbers and stay as they are.
    const bool formula = value.is_string() && !text.empty() &&
                         std::string_view("=+-@\t\r").find(text.front()) != std::string_view::npos;
    if (formula) text.insert(text.begin(), '\'');
    if (!formula && text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (const char c : text) {
        if (c == '"') quoted += '"';
        quoted += c;
    }
    return quoted + '"';
}

std::string csv_record(const std::vector<json>& fields) {
    std::string record;
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i > 0) record += ',';
        record += csv_field(fields[i]);
    }
    return record + "\r\n";
}

CsvOutcome result_csv(std::span<const CsvTable> offered, std::string_view analysis,
                      const json& result, std::string_view table, CsvUnits units) {
    const auto chosen = table.empty()
                            ? offered.begin()
                            : std::find_if(offered.begin(), offered.end(),
                                           [table](const CsvTable& t) { return t.name == table; });
    if (chosen == offered.end()) {
        return {false,
                {},
                concat("the ", analysis, " result has no table '", table, "'; its tables are ",
                       table_names(offered))};
    }
    const std::vector<std::string> columns = chosen->columns(result);
    std::vector<json> header;
    for (const CsvKey& key : chosen->keys) header.emplace_back(key.column);
    for (const std::string& column : columns) header.emplace_back(column);
    Conversions conversions;
    if (units == CsvUnits::plant) {
        for (json& name : header) {
            const auto plant = plant_column(name.get<std::string>());
            conversions.push_back(plant ? plant->unit : nullptr);
            if (plant) name = plant->name;
        }
    }
    std::string text = csv_record(header);

    const std::string missing = concat(
        "this ", analysis, " result has no '", chosen->name, "' table (", chosen->description,
        " It is left out by options such as critical_speed false, detail \"summary\", time_series false, "
        "distributions false, or when the outcome produced none)");
    if (chosen->rows_of) {
        if (!append_rows(chosen->rows_of(result), columns, {}, conversions, text))
            return {false, {}, missing};
        return {true, std::move(text), {}};
    }
    if (chosen->outer.empty()) {
        const json* rows = at(result, chosen->rows);
        if (rows == nullptr || rows->is_null() ||
            !append_rows(*rows, columns, {}, conversions, text))
            return {false, {}, missing};
        return {true, std::move(text), {}};
    }
    const json* outer = at(result, chosen->outer);
    if (outer == nullptr || !outer->is_array()) return {false, {}, missing};
    bool any = false;
    for (std::size_t i = 0; i < outer->size(); ++i) {
        const json& element = (*outer)[i];
        const json* rows = at(element, chosen->rows);
        if (rows == nullptr || rows->is_null()) continue;
        std::vector<json> lead;
        for (const CsvKey& key : chosen->keys) {
            lead.push_back(key.member.empty() ? json(i)
                                              : element.value(std::string(key.member), json()));
        }
        if (!append_rows(*rows, columns, lead, conversions, text)) return {false, {}, missing};
        any = true;
    }
    if (!any) return {false, {}, missing};
    return {true, std::move(text), {}};
}

}  // namespace rollgap::api
