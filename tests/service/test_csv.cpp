// CSV of the tabular parts of results (api/csv.h, service/csv_answer.h): each table parsed
// with an RFC 4180 reader written here, independently of the writer, and compared cell by cell
// with the JSON the same request answers; the quoting rules; content negotiation; 406 where a
// result has no such table.

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"

using nlohmann::json;
using namespace rollgap;

namespace {

using Rows = std::vector<std::vector<std::string>>;

// RFC 4180: records end in CRLF; a quoted field may hold commas, CRLF and doubled quotes.
Rows parse_csv(const std::string& text) {
    Rows rows;
    std::vector<std::string> record;
    std::string field;
    bool quoted = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
                field += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                field += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            record.push_back(field);
            field.clear();
        } else if (c == '\r') {
            REQUIRE(i + 1 < text.size());
            REQUIRE(text[i + 1] == '\n');  // CRLF, never a bare CR or LF
            ++i;
            record.push_back(field);
            field.clear();
            rows.push_back(record);
            record.clear();
        } else {
            REQUIRE(c != '\n');
            field += c;
        }
    }
    REQUIRE(field.empty());
    REQUIRE(record.empty());  // the last record ends in CRLF too
    return rows;
}

// A CSV cell against the JSON value it stands for: numbers read back to the same double.
void check_cell(const std::string& cell, const json& value) {
    CAPTURE(cell);
    CAPTURE(value.dump());
    if (value.is_null()) {
        CHECK(cell.empty());
    } else if (value.is_number()) {
        CHECK(std::stod(cell) == value.get<double>());
    } else if (value.is_boolean()) {
        CHECK(cell == (value.get<bool>() ? "true" : "false"));
    } else {
        CHECK(cell == value.get<std::string>());
    }
}

json answer(const json& request) {
    const service::Outcome outcome = service::evaluate(request);
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    return outcome.body;
}

Rows table(const json& body, const std::string& name = "") {
    const service::CsvAnswer csv = service::csv_answer(body, name);
    REQUIRE_MESSAGE(csv.status == 200, csv.body);
    CHECK(csv.media_type == service::csv_content_type);
    Rows rows = parse_csv(csv.body);
    REQUIRE(rows.size() >= 2);
    for (const auto& row : rows) CHECK(row.size() == rows.front().size());
    return rows;
}

// Rows of an array of objects: one record per element, the header names its members.
void check_row_table(const Rows& rows, const json& elements, std::size_t leading = 0) {
    REQUIRE(rows.size() == elements.size() + 1);
    for (std::size_t r = 0; r < elements.size(); ++r) {
        for (std::size_t c = leading; c < rows[0].size(); ++c)
            check_cell(rows[r + 1][c], elements[r].at(rows[0][c]));
    }
}

// Rows of a columnar object (equal-length arrays) from `first`: record i is element i of each.
void check_columnar(const Rows& rows, std::size_t first, const json& columns,
                    std::size_t leading = 0) {
    const std::size_t n = columns.begin()->size();
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t c = leading; c < rows[0].size(); ++c)
            check_cell(rows[first + i][c], columns.at(rows[0][c])[i]);
    }
}

}  // namespace

TEST_CASE("csv: RFC 4180 fields and records") {
    CHECK(api::csv_field(nullptr).empty());
    CHECK(api::csv_field(1.5) == "1.5");
    CHECK(api::csv_field(true) == "true");
    CHECK(api::csv_field("plain") == "plain");
    CHECK(api::csv_field("a,b") == "\"a,b\"");
    CHECK(api::csv_field("say \"hi\"") == "\"say \"\"hi\"\"\"");
    CHECK(api::csv_field("two\nlines") == "\"two\nlines\"");
    // a text cell a spreadsheet would take for a formula opens as text; numbers stay numbers
    CHECK(api::csv_field("=HYPERLINK(\"http://x\")") == "\"'=HYPERLINK(\"\"http://x\"\")\"");
    CHECK(api::csv_field("+1") == "\"'+1\"");
    CHECK(api::csv_field("-5 kN") == "\"'-5 kN\"");
    CHECK(api::csv_field("@SUM(A1)") == "\"'@SUM(A1)\"");
    CHECK(api::csv_field("\tcmd") == "\"'\tcmd\"");
    CHECK(api::csv_field(-5) == "-5");
    CHECK(api::csv_field(-0.25) == "-0.25");
    CHECK(api::csv_field("coil-7") == "coil-7");
    const std::string record = api::csv_record({"x,y", 2, nullptr, "q\""});
    CHECK(record == "\"x,y\",2,,\"q\"\"\"\r\n");
    const Rows parsed = parse_csv(record);
    REQUIRE(parsed.size() == 1);
    CHECK(parsed[0] == std::vector<std::string>{"x,y", "2", "", "q\""});
}

TEST_CASE("csv: Accept negotiation") {
    CHECK(service::wants_csv("text/csv"));
    CHECK(service::wants_csv("text/csv, application/json;q=0.5"));
    CHECK(service::wants_csv("text/csv;q=0.9, */*;q=0.1"));
    CHECK_FALSE(service::wants_csv(""));
    CHECK_FALSE(service::wants_csv("*/*"));
    CHECK_FALSE(service::wants_csv("application/json"));
    CHECK_FALSE(service::wants_csv("application/json, text/csv;q=0.5"));
    CHECK_FALSE(service::wants_csv("text/csv;q=0"));
}

TEST_CASE("csv: the roll-gap distribution is the JSON's columns, row by row") {
    const json body = answer({{"analysis", "roll_gap"}});
    const Rows rows = table(body);
    const json& distribution = body["result"]["distribution"];
    CHECK(rows[0].front() == "x_mm");
    CHECK(rows[0].size() == distribution.size());
    REQUIRE(rows.size() == distribution["x_mm"].size() + 1);
    check_columnar(rows, 1, distribution);
}

TEST_CASE("csv: the stability scan, its branches and the eigenvalues") {
    const json body = answer({{"analysis", "stability"},
                              {"options", {{"speed_min_m_per_s", 15}, {"speed_max_m_per_s", 25}}}});
    const json& search = body["result"]["critical_speed"];
    check_row_table(table(body), search["scan"]);
    check_row_table(table(body, "eigenvalues"), body["result"]["eigenvalues"]);

    const Rows branches = table(body, "damping_branches");
    CHECK(branches[0].front() == "branch");
    std::size_t first = 1;
    for (std::size_t b = 0; b < search["damping_branches"].size(); ++b) {
        const json& branch = search["damping_branches"][b];
        check_columnar(branches, first, branch, 1);
        for (std::size_t i = 0; i < branch["speed_m_per_s"].size(); ++i)
            CHECK(branches[first + i][0] == std::to_string(b));
        first += branch["speed_m_per_s"].size();
    }
    CHECK(first == branches.size());

    SUBCASE("a summary has no scan: 406 naming the table") {
        const json summary = answer(
            {{"analysis", "stability"},
             {"options",
              {{"speed_min_m_per_s", 15}, {"speed_max_m_per_s", 25}, {"detail", "summary"}}}});
        const service::CsvAnswer refused = service::csv_answer(summary, "");
        CHECK(refused.status == 406);
        CHECK(json::parse(refused.body)["code"] == "not_acceptable");
        CHECK(json::parse(refused.body)["detail"].get<std::string>().find("'scan'") !=
              std::string::npos);
    }
}

TEST_CASE("csv: amplitude points and time series, led by the speed") {
    const json body = answer({{"analysis", "amplitude"},
                              {"options",
                               {{"speeds_m_per_s", {10, 15}},
                                {"window_s", 0.2},
                                {"time_series", true},
                                {"time_series_points", 20}}}});
    const json& points = body["result"]["points"];
    check_row_table(table(body), points);
    const Rows series = table(body, "time_series");
    CHECK(series[0][0] == "speed_m_per_s");
    CHECK(series[0][2] == "upper_work_roll_displacement_um");
    std::size_t first = 1;
    for (const json& point : points) {
        check_columnar(series, first, point["time_series"], 1);
        const std::size_t n = point["time_series"]["time_s"].size();
        for (std::size_t i = 0; i < n; ++i)
            check_cell(series[first + i][0], point["speed_m_per_s"]);
        first += n;
    }
    CHECK(first == series.size());
}

namespace csv_test_sweep {
// A sweep of the lubricant's viscosity over two values (a column in Pa·s and one in m/s).
json viscosity_sweep() {
    return answer({{"analysis", "sweep"},
                   {"options",
                    {{"parameter", "/lubricant/viscosity_Pa_s"},
                     {"values", {4e-4, 7e-4}},
                     {"critical_speed", {{"speed_min_m_per_s", 10}, {"speed_max_m_per_s", 35}}}}}});
}
}  // namespace csv_test_sweep
using csv_test_sweep::viscosity_sweep;

TEST_CASE("csv: sweep points, the value first under its unit-carrying name") {
    const json body = viscosity_sweep();
    const Rows rows = table(body);
    CHECK(rows[0] == std::vector<std::string>{"value_Pa_s", "status", "critical_speed_m_per_s",
                                              "frequency_Hz", "chatter_type", "chatter_band"});
    check_row_table(rows, body["result"]["points"]);
}

TEST_CASE("csv: units=plant shows speeds in m/min and viscosities in mPa.s, the rest as it is") {
    const json body = viscosity_sweep();
    const service::CsvAnswer csv = service::csv_answer(body, "", "plant");
    REQUIRE_MESSAGE(csv.status == 200, csv.body);
    const Rows rows = parse_csv(csv.body);
    CHECK(rows[0] == std::vector<std::string>{"value_mPa_s", "status", "critical_speed_m_per_min",
                                              "frequency_Hz", "chatter_type", "chatter_band"});
    const json& points = body["result"]["points"];
    REQUIRE(rows.size() == points.size() + 1);
    for (std::size_t r = 0; r < points.size(); ++r) {
        const json& point = points[r];
        // 0.0004 Pa.s is exactly 0.4 mPa.s (the decimal shifted), a speed × 60
        CHECK(rows[r + 1][0] == (r == 0 ? "0.4" : "0.7"));
        CHECK(point["value_Pa_s"] == (r == 0 ? 4e-4 : 7e-4));
        if (point["critical_speed_m_per_s"].is_number())
            CHECK(std::stod(rows[r + 1][2]) ==
                  point["critical_speed_m_per_s"].get<double>() * 60.0);
        check_cell(rows[r + 1][3], point["frequency_Hz"]);
        check_cell(rows[r + 1][4], point["chatter_type"]);
    }
    // "si" and "" are the JSON's units; the JSON answer itself never changes
    CHECK(service::csv_answer(body, "", "si").body == service::csv_answer(body, "").body);
    CHECK(service::parse_csv_units("plant") == api::CsvUnits::plant);
    CHECK_FALSE(service::parse_csv_units("imperial").has_value());
}

TEST_CASE("csv: tension-cycle distributions, led by the phase") {
    const json body =
        answer({{"analysis", "tension_cycle"}, {"options", {{"phases", {0.25, 0.75}}}}});
    const json& phases = body["result"]["phases"];
    const Rows rows = table(body);
    CHECK(rows[0][0] == "phase");
    std::size_t first = 1;
    for (const json& phase : phases) {
        const json& distribution = phase["roll_gap"]["distribution"];
        check_columnar(rows, first, distribution, 3);
        const std::size_t n = distribution["x_mm"].size();
        for (std::size_t i = 0; i < n; ++i) check_cell(rows[first + i][0], phase["phase"]);
        first += n;
    }
    CHECK(first == rows.size());
    check_row_table(table(body, "phases"), phases);
}

TEST_CASE("csv: no table, an unknown table, an unfinished job: 406") {
    const json evaluation =
        answer({{"analysis", "evaluate"},
                {"options", {{"detail", "summary"}, {"amplitude", {{"window_s", 0.2}}}}}});
    CHECK(service::csv_answer(evaluation, "").status == 406);
    const json roll_gap = answer({{"analysis", "roll_gap"}});
    CHECK(service::csv_answer(roll_gap, "scan").status == 406);
    CHECK(service::csv_answer({{"id", "x"}, {"state", "running"}}, "").status == 406);
    // A succeeded job's result gives the same table as the answer itself.
    CHECK(
        service::csv_answer({{"id", "x"}, {"state", "succeeded"}, {"result", roll_gap}}, "").body ==
        service::csv_answer(roll_gap, "").body);
}
