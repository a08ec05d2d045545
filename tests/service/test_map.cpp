// Stability maps (docs/model.md, "Stability maps"): every cell equals the critical-speed search
// run on its own scenario, whatever the thread count; the grid's neighbours where the crossing
// mode changes chatter type; and the options through the facade (values validated like their
// fields, the bounds on cells and work).

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "core/map.h"
#include "service/evaluate.h"
#include "support/pool_control.h"
#include "support/refused_options.h"

using nlohmann::json;
using namespace rollgap;

namespace {

// A fast search around the default critical speed (~20 m/s) and the rough strips' (~45-50 m/s).
core::CriticalSpeedOptions narrow() {
    core::CriticalSpeedOptions o;
    o.speed_min = 10.0;
    o.speed_max = 55.0;
    return o;
}

const json narrow_search = {{"speed_min_m_per_s", 10}, {"speed_max_m_per_s", 55}};

json axis(const std::string& pointer, const json& values) {
    return {{"parameter", pointer}, {"values", values}};
}

}  // namespace

TEST_CASE("grid neighbours: each cell with its right and lower neighbour") {
    const auto pairs = core::grid_neighbours(2, 3);
    CHECK(pairs.size() == 2 * 2 + 3 * 1);
    CHECK(pairs ==
          std::vector<std::pair<int, int>>{{0, 1}, {0, 3}, {1, 2}, {1, 4}, {2, 5}, {3, 4}, {4, 5}});
    CHECK(core::grid_neighbours(1, 1).empty());
}

TEST_CASE(
    "a map's cells equal single searches, row-major, with 1 and 2 threads, the type change is found along the rows") {
    // rows: strip roughness 8 and 9 um (the crossing moves from the ~109 Hz gap mode to the
    // ~480 Hz work-roll mode between them); columns: two viscosities
    std::vector<core::Scenario> cells;
    for (double rq : {8e-6, 9e-6}) {
        for (double viscosity : {5.5e-4, 6e-4}) {
            core::Scenario s;
            s.roughness.strip_rq = rq;
            s.lubricant.viscosity = viscosity;
            cells.push_back(s);
        }
    }
    const core::StabilityMap serial = core::stability_map(cells, 2, 2, narrow());
    const core::StabilityMap parallel =
        core::stability_map(cells, 2, 2, narrow(), rollgap::test::PoolControl(2).control);
    REQUIRE(serial.cells.size() == 4);
    for (std::size_t c = 0; c < 4; ++c) {
        const core::CriticalSpeedResult alone = core::critical_speed(cells[c], narrow());
        CHECK(serial.cells[c].status == alone.status);
        CHECK(serial.cells[c].critical_speed == alone.critical_speed);
        CHECK(serial.cells[c].unstable_mode.frequency_Hz == alone.unstable_mode.frequency_Hz);
        CHECK(parallel.cells[c].critical_speed == serial.cells[c].critical_speed);
        CHECK(serial.cells[c].scan.empty());  // a map keeps no scans
    }
    CHECK(serial.cells[0].unstable_mode.chatter.type == core::ChatterType::third_octave);
    CHECK(serial.cells[2].unstable_mode.chatter.type == core::ChatterType::fifth_octave);
    // the changes are the two vertical pairs (0, 2) and (1, 3), whichever viscosity
    REQUIRE(serial.changes.size() == 2);
    for (const auto& change : serial.changes) {
        CHECK(change.to - change.from == 2);
        CHECK(change.from_type == core::ChatterType::third_octave);
        CHECK(change.to_type == core::ChatterType::fifth_octave);
    }
}

TEST_CASE(
    "map through the facade: cells with their values, status, critical speed, frequency and chatter type") {
    const json options = {
        {"parameters",
         {axis("/strip/reduction", {0.15, 0.2}), axis("/roughness/strip_rq_um", {1.6})}},
        {"critical_speed", narrow_search}};
    const service::Outcome outcome = service::evaluate({{"analysis", "map"}, {"options", options}});
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    const json& result = outcome.body["result"];
    REQUIRE(result["cells"].size() == 2);
    CHECK(result["parameters"][0]["parameter"] == "/strip/reduction");
    CHECK(result["parameters"][1]["unit"] == "um");
    const json& first = result["cells"][0];
    CHECK(first["values"] == json{0.15, 1.6});
    CHECK(first["status"] == "found");
    CHECK(first["chatter_type"] == "third_octave");
    CHECK(first["chatter_band"] == "third_octave");
    // the default scenario's own critical speed, from the stability analysis
    const service::Outcome single =
        service::evaluate({{"analysis", "stability"},
                           {"options", {{"speed_min_m_per_s", 10}, {"speed_max_m_per_s", 55}}}});
    REQUIRE(single.ok());
    CHECK(first["critical_speed_m_per_s"] ==
          single.body["result"]["critical_speed"]["critical_speed_m_per_s"]);
    CHECK(result["cells"][1]["values"] == json{0.2, 1.6});
    CHECK(result["chatter_type_changes"].is_array());
    CHECK(outcome.body["options"]["parameters"][1]["parameter"] == "/roughness/strip_rq_um");
}

TEST_CASE("map options are refused with the pointer, bound and unit of the offending value") {
    // a value outside its field's bounds: at its own pointer, with the field's bound and unit
    const json bad_value = test::refused_options(
        "map",
        {{"parameters",
          {axis("/strip/reduction", {0.15}), axis("/strip/entry_thickness_mm", {1.6, 25.0})}}},
        "/options/parameters/1/values/1");
    CHECK(bad_value["unit"] == "mm");
    CHECK(bad_value.contains("bound"));
    // one field only, or not an array
    test::refused_options("map", {{"parameters", {axis("/strip/reduction", {0.15})}}},
                          "/options/parameters");
    test::refused_options("map", json::object(), "/options/parameters");
    // the same field twice; the roll speed (the search scans it)
    test::refused_options(
        "map", {{"parameters", {axis("/strip/reduction", {0.1}), axis("/strip/reduction", {0.2})}}},
        "/options/parameters/1/parameter");
    test::refused_options(
        "map",
        {{"parameters", {axis("/rolls/speed_m_per_s", {10}), axis("/strip/reduction", {0.2})}}},
        "/options/parameters/0/parameter");
    // not a numeric field
    test::refused_options(
        "map", {{"parameters", {axis("/friction/model", {1}), axis("/strip/reduction", {0.2})}}},
        "/options/parameters/0/parameter");
    // too many cells: 51 × 50 > 2500
    const json many = {{"parameters",
                        {{{"parameter", "/strip/reduction"},
                          {"range", {{"from", 0.1}, {"to", 0.3}, {"count", 51}}}},
                         {{"parameter", "/strip/entry_thickness_mm"},
                          {"range", {{"from", 1}, {"to", 2}, {"count", 50}}}}}}};
    const json cells_error = test::refused_options("map", many, "/options/parameters");
    CHECK(cells_error["bound"] == "at most 2500 cells");
    // too much work: 2500 cells × 119 default scan speeds
    const json work = {{"parameters",
                        {{{"parameter", "/strip/reduction"},
                          {"range", {{"from", 0.1}, {"to", 0.3}, {"count", 50}}}},
                         {{"parameter", "/strip/entry_thickness_mm"},
                          {"range", {{"from", 1}, {"to", 2}, {"count", 50}}}}}}};
    test::refused_options("map", work, "/options/critical_speed/speed_step_m_per_s");
    // each value fine on its own, the pair not: a back tension above the flow stress
    test::refused_options(
        "map",
        {{"parameters",
          {axis("/strip/flow_stress_MPa", {380, 20}), axis("/tension/back/stress_MPa", {18, 30})}}},
        "/options/parameters");
}
