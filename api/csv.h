#pragma once
// CSV of the tabular parts of a result (Accept: text/csv, rollgap run --format csv).
//
// Format: RFC 4180 — a header row naming each column with its unit (the JSON member names,
// which carry it), fields separated by commas, CRLF line ends, a field quoted when it holds a
// comma, a quote, CR or LF (quotes doubled). null (a figure the outcome did not produce) is an
// empty field; numbers are written as in the JSON (shortest form that reads back exactly);
// booleans true / false.
//
// One CSV is one table. A result with several tables names them (<analysis>_csv_tables, listed
// in the analysis' row, service/analyses/analysis.h); the caller picks
// one by name (HTTP ?table=, CLI --table), the first one listed is the default. A table whose rows
// sit in the elements of an outer array (the distributions of each tension-cycle phase, the time
// series of each amplitude speed, the damping branches) repeats the outer element's key members
// as leading columns, so the whole is one flat sheet.
//
// Adding a table: one CsvTable row in its analysis' list in csv.cpp, its columns from the
// ResultTable that writes the JSON (names() for columnar objects, scalar_names() for arrays of
// objects).

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace rollgap::api {

inline constexpr std::string_view csv_media_type = "text/csv";

struct CsvKey {
    std::string_view column;  // the leading column's name
    std::string_view member;  // the outer element's member; "" for the element's index
};

struct CsvTable {
    std::string_view name;         // what ?table= / --table call it
    std::string_view description;  // for the documentation
    std::string_view
        outer;  // JSON pointer (in the result) of an array whose elements hold the rows; "" if none
    std::vector<CsvKey> keys;  // leading columns from each outer element
    std::string_view rows;  // JSON pointer (in the result, or in an outer element) of the rows: an
                            // array of objects, or an object of equal-length arrays (columnar)
    std::function<std::vector<std::string>(const nlohmann::json& result)> columns;  // in order
    // The rows computed from the result, instead of `rows`, when the JSON holds them in a form a
    // sheet cannot take (a map cell's pair of values becomes two columns); outer must be "".
    std::function<nlohmann::json(const nlohmann::json& result)> rows_of = {};
};

// The tables of each analysis' result that has some worth a sheet (first: the default).
std::span<const CsvTable> roll_gap_csv_tables();
std::span<const CsvTable> tension_cycle_csv_tables();
std::span<const CsvTable> stability_csv_tables();
std::span<const CsvTable> amplitude_csv_tables();
std::span<const CsvTable> sweep_csv_tables();
std::span<const CsvTable> map_csv_tables();
std::span<const CsvTable> calibration_csv_tables();
std::span<const CsvTable> speed_limit_csv_tables();

// A map's sheet, a stand's or a mill's: one row per cell, its pair of values as two columns
// named by the parameters' pointers without the leading slash ("strip/reduction"), then the
// cell's members.
std::vector<std::string> map_value_columns(const nlohmann::json& result);
nlohmann::json map_cell_rows(const nlohmann::json& result);

struct CsvOutcome {
    bool ok = false;
    std::string text;    // the CSV when ok
    std::string detail;  // why not, for a 406 problem
};

// The CSV of one of the tables `offered` (non-empty) of an `analysis` result; `table` "" is the
// first.
// The units of the columns: si (the JSON's, the default) or plant (units=plant: a column in
// m/s or Pa·s renamed and converted to m/min or mPa·s, plant_units.h plant_column).
enum class CsvUnits { si, plant };

CsvOutcome result_csv(std::span<const CsvTable> offered, std::string_view analysis,
                      const nlohmann::json& result, std::string_view table,
                      CsvUnits units = CsvUnits::si);

// One RFC 4180 field / record (CRLF included), for the writers and their tests.
std::string csv_field(const nlohmann::json& value);
std::string csv_record(const std::vector<nlohmann::json>& fields);

}  // namespace rollgap::api
