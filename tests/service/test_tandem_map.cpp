// The analysis tandem_map (docs/model.md §12.10): a grid of two numbers of the tandem document,
// the mill at each cell. A cell is the mill sweep's point (itself the tandem analysis) of the mill
// with both values written into its document, equal to the last bit; cells are row-major; the
// chatter-type changes are exactly the neighbouring cells whose types differ; a value the mill
// cannot have is refused at its own pointer, a pair of values at the parameters; chunks assemble
// into the single run. Two stands: each case takes well under a second in Release.

#include <doctest/doctest.h>

#include <algorithm>
#include <set>
#include <string>
#include <tuple>
#include <variant>

#include <nlohmann/json.hpp>

#include "core/control.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"
#include "support/mill_requests.h"

using nlohmann::json;
using namespace rollgap;

// Named, not anonymous: the unity build puts this file beside the other service tests, whose
// helpers have the same names.
namespace tandem_map_test {

using test::answer_of;
using test::refusal_of;
using test::two_stands;

json map_request(const json& rows, const json& columns, const json& more = json::object()) {
    json options = {{"parameters", {rows, columns}}};
    options.update(more);
    return {{"analysis", "tandem_map"}, {"tandem", two_stands}, {"options", options}};
}

// Speed × the second stand's lubricant viscosity, at the mill's speed: the rightmost root turns
// from the work rolls' fifth-octave mode to the third-octave mill mode as speed or viscosity grows.
const json speeds = {{"parameter", "/speed_m_per_s"}, {"values", {5.0, 8.0, 11.0, 14.0}}};
const json viscosities = {{"parameter", "/stands/1/lubricant/viscosity_Pa_s"},
                          {"values", {0.0002, 0.001}}};
const json stability = {{"quantity", "stability"}};

TEST_CASE("a mill map's cell is the mill sweep's point of the mill with both values set") {
    const json result = answer_of(map_request(speeds, viscosities, stability))["result"];
    CHECK(result["quantity"] == "stability");
    REQUIRE(result["parameters"].size() == 2);
    CHECK(result["parameters"][0] ==
          json{{"parameter", "/speed_m_per_s"}, {"unit", "m/s"}, {"values", speeds["values"]}});
    CHECK(result["parameters"][1]["unit"] == "Pa.s");
    const json& cells = result["cells"];
    REQUIRE(cells.size() == 8);
    for (std::size_t i = 0; i < 4; ++i) {
        // The row's mill, swept over the columns' values.
        json mill = two_stands;
        mill["speed_m_per_s"] = speeds["values"][i];
        const json sweep = answer_of({{"analysis", "tandem_sweep"},
                                      {"tandem", mill},
                                      {"options",
                                       {{"parameter", viscosities["parameter"]},
                                        {"values", viscosities["values"]},
                                        {"quantity", "stability"}}}})["result"];
        for (std::size_t j = 0; j < 2; ++j) {
            CAPTURE(i);
            CAPTURE(j);
            json cell = cells[i * 2 + j];  // row-major: the second number varies fastest
            CHECK(cell["values"] == json{speeds["values"][i], viscosities["values"][j]});
            json point = sweep["points"][j];
            cell.erase("values");
            point.erase("value_Pa_s");
            CHECK(cell == point);
        }
    }
    // Not one answer repeated: speed and viscosity move the rightmost root.
    CHECK(cells[0]["growth_rate_per_s"] != cells[6]["growth_rate_per_s"]);
    CHECK(cells[2]["growth_rate_per_s"] != cells[3]["growth_rate_per_s"]);
}

TEST_CASE("a mill map's chatter-type changes are the neighbouring cells whose types differ") {
    const json result = answer_of(map_request(speeds, viscosities, stability))["result"];
    const json& cells = result["cells"];
    // Expected from the cells alone: each pair one step apart along one number.
    std::set<std::tuple<std::string, std::string>> expected;
    for (std::size_t a = 0; a < cells.size(); ++a) {
        for (std::size_t b = a + 1; b < cells.size(); ++b) {
            const bool along_rows = b == a + 2;
            const bool along_columns = b == a + 1 && a % 2 == 0;
            if (!along_rows && !along_columns) continue;
            if (cells[a]["chatter_type"].is_null() || cells[b]["chatter_type"].is_null()) continue;
            if (cells[a]["chatter_type"] != cells[b]["chatter_type"])
                expected.emplace(cells[a]["values"].dump(), cells[b]["values"].dump());
        }
    }
    std::set<std::tuple<std::string, std::string>> listed;
    for (const json& change : result["chatter_type_changes"]) {
        listed.emplace(change["from"].dump(), change["to"].dump());
        CHECK(change["from_chatter_type"] != change["to_chatter_type"]);
    }
    CHECK(listed == expected);
    // This map has some: the fifth-octave root at low speed and viscosity, third-octave above.
    CHECK(!expected.empty());
}

TEST_CASE("a mill map of critical speeds: a cell is the tandem analysis' headline") {
    const json search = {{"speed_min_m_per_s", 5.0}, {"speed_max_m_per_s", 20.0}};
    const json result =
        answer_of(map_request({{"parameter", "/spans/length_m/0"}, {"values", {4.0}}},
                              {{"parameter", "/spans/tension_MPa/0"}, {"values", {80.0}}},
                              {{"critical_speed", search}}))["result"];
    REQUIRE(result["cells"].size() == 1);
    const json& cell = result["cells"][0];
    json mill = two_stands;
    mill["spans"] = {{"length_m", {4.0}}, {"tension_MPa", {80.0}}};
    const json critical = answer_of({{"analysis", "tandem"},
                                     {"tandem", mill},
                                     {"options", search}})["result"]["critical_speeds"];
    CHECK(cell["critical_speed_m_per_s"] == critical["critical_speed_m_per_s"]);
    CHECK(cell["kind"] == critical["headline"]);
    const std::string kind = cell["kind"].get<std::string>();
    CHECK(cell["frequency_Hz"] == critical[kind]["frequency_Hz"]);
    CHECK(cell["chatter_type"] == critical[kind]["chatter_type"]);
    CHECK(cell["chatter_band"] == critical[kind]["band"]);
    CHECK(cell["frozen_m_per_s"] == critical["frozen"]["speed_m_per_s"]);
}

TEST_CASE("a mill map refuses what the mill cannot have, at the pointer that names it") {
    const json lengths = {{"parameter", "/spans/length_m/0"}, {"values", {4.0, 6.0}}};
    SUBCASE("a value out of its field's bounds: its bound and unit") {
        const json refused = refusal_of(map_request(
            lengths, {{"parameter", "/spans/tension_MPa/0"}, {"values", {60.0, -5.0}}}, stability));
        REQUIRE(refused["errors"].size() == 1);
        CHECK(refused["errors"][0]["pointer"] == "/options/parameters/1/values/1");
        CHECK(refused["errors"][0].contains("bound"));
    }
    SUBCASE("two values fine alone, not together: the cell named at the parameters") {
        // 1.5 mm from stand 1 and 1.55 mm from stand 2: the schedule no longer falls.
        const json refused = refusal_of(map_request(
            {{"parameter", "/exit_thickness_mm/0"}, {"values", {1.6, 1.5}}},
            {{"parameter", "/exit_thickness_mm/1"}, {"values", {1.36, 1.55}}}, stability));
        REQUIRE(refused["errors"].size() == 1);
        CHECK(refused["errors"][0]["pointer"] == "/options/parameters");
        const std::string detail = refused["errors"][0]["detail"];
        CHECK(detail.find("/exit_thickness_mm/0 = 1.5 and /exit_thickness_mm/1 = 1.55") !=
              std::string::npos);
    }
    SUBCASE("the same number twice, or one inside the other") {
        for (const char* second : {"/spans/length_m/0", "/spans/length_m"}) {
            CAPTURE(second);
            const json refused = refusal_of(
                map_request(lengths, {{"parameter", second}, {"values", {5.0}}}, stability));
            CHECK(refused["errors"][0]["pointer"] == "/options/parameters/1/parameter");
        }
    }
    SUBCASE("the mill speed in a map of critical speeds: the search scans it") {
        const json refused = refusal_of(map_request(speeds, lengths));
        CHECK(refused["errors"][0]["pointer"] == "/options/parameters/0/parameter");
    }
    SUBCASE("more cells than a mill map takes") {
        const json refused =
            refusal_of(map_request({{"parameter", "/spans/length_m/0"},
                                    {"range", {{"from", 3}, {"to", 8}, {"count", 21}}}},
                                   {{"parameter", "/spans/tension_MPa/0"},
                                    {"range", {{"from", 40}, {"to", 90}, {"count", 20}}}},
                                   stability));
        CHECK(refused["errors"][0]["pointer"] == "/options/parameters");
        CHECK(refused["errors"][0]["bound"] == "at most 400 cells");
    }
    SUBCASE("not two numbers") {
        json request = map_request(lengths, lengths, stability);
        request["options"]["parameters"] = {lengths};
        const json refused = refusal_of(request);
        CHECK(refused["errors"][0]["pointer"] == "/options/parameters");
    }
}

TEST_CASE("a mill map's cells in chunks assemble into the single run, its CSV") {
    const json request = map_request(speeds, viscosities, stability);
    auto prepared = service::prepare(request);
    REQUIRE(std::holds_alternative<service::PreparedRequest>(prepared));
    const auto& cells = std::get<service::PreparedRequest>(prepared).prepared.points;
    REQUIRE(cells.has_value());
    REQUIRE(cells->count == 8);
    json documents = cells->compute(0, 3, core::Control{});
    for (json& cell : cells->compute(3, 8, core::Control{})) documents.push_back(cell);
    const json answer = answer_of(request);
    CHECK(cells->assemble(documents) == answer["result"]);

    const service::CsvAnswer csv = service::csv_answer(answer, "cells");
    REQUIRE(csv.status == 200);
    CHECK(csv.body.starts_with(
        "speed_m_per_s,stands/1/lubricant/viscosity_Pa_s,status,stable,growth_rate_per_s,"));
    CHECK(std::count(csv.body.begin(), csv.body.end(), '\n') == 9);  // header + 8 cells
}

}  // namespace tandem_map_test
