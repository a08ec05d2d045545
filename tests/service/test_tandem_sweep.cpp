// The analysis tandem_sweep (docs/model.md §12.10): a number of the tandem document over values,
// the mill at each. Each point is the tandem analysis of the mill with that value written into
// its document (the same computation, so equal to the last bit); a list parameter sets every
// element; a value the mill cannot have is refused at its own pointer; the points split into
// chunks that assemble into the single run. Small mills (two and three stands): every case here
// takes well under a second in Release and a few under ASan.

#include <doctest/doctest.h>

#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "core/control.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"
#include "support/mill_requests.h"

using nlohmann::json;
using namespace rollgap;

// Named, not anonymous: the unity build puts this file beside test_tandem_api.cpp, whose helpers
// have the same names.
namespace tandem_sweep_test {

using test::answer_of;
using test::refusal_of;
using test::two_stands;

json three_stands() {
    json mill = two_stands;
    mill["exit_thickness_mm"] = {1.6, 1.36, 1.2};
    mill["spans"] = {{"length_m", {5, 5}}, {"tension_MPa", {60, 70}}};
    mill["stands"] = json::array({json::object(), json::object(), json::object()});
    return mill;
}

// The tandem analysis' stability of `mill`, as a stability point reports it.
void check_point_is_tandem(const json& point, const json& mill) {
    const json tandem = answer_of(
        {{"analysis", "tandem"}, {"tandem", mill}, {"options", {{"critical_speed", false}}}});
    const json& stability = tandem["result"]["stability"];
    const json& root = stability["rightmost_root"];
    CHECK(point["status"] == "ok");
    CHECK(point["stable"] == stability["stable"]);
    CHECK(point["growth_rate_per_s"] == root["growth_rate_per_s"]);
    CHECK(point["frequency_Hz"] == root["frequency_Hz"]);
    CHECK(point["moving_stand"] == root["moving_stand"]);
    CHECK(point["feeding_stand"] == root["feeding_stand"]);
    CHECK(point["in_model_range"] == root["validity"]["valid"]);
    CHECK(point["regenerative_margin"] == stability["regenerative_margin"]);
    CHECK(point["frozen_stable"] == stability["frozen_stable"]);
    CHECK(point["roots_right_of_axis"] == stability["roots_right_of_axis"]);
    CHECK(point["roots_in_band"] == stability["roots_in_band"]);
}

TEST_CASE("a mill sweep's point is the tandem analysis of the mill with that value") {
    const json answer = answer_of({{"analysis", "tandem_sweep"},
                                   {"tandem", two_stands},
                                   {"options",
                                    {{"parameter", "/spans/length_m/0"},
                                     {"values", {4.0, 6.5}},
                                     {"quantity", "stability"}}}});
    const json& result = answer["result"];
    CHECK(result["parameter"] == "/spans/length_m/0");
    CHECK(result["unit"] == "m");
    CHECK(result["value_name"] == "value_m");
    REQUIRE(result["points"].size() == 2);
    for (const double length : {4.0, 6.5}) {
        CAPTURE(length);
        const json& point = result["points"][length == 4.0 ? 0 : 1];
        CHECK(point["value_m"] == length);
        json mill = two_stands;
        mill["spans"]["length_m"] = {length};
        check_point_is_tandem(point, mill);
    }
    // The span length moved the root: the sweep is not one answer repeated.
    CHECK(result["points"][0]["frequency_Hz"] != result["points"][1]["frequency_Hz"]);
}

TEST_CASE("a mill sweep: a list parameter sets every element, a stand's field, the CSV") {
    // Every span's tension set point at once.
    const json answer = answer_of(
        {{"analysis", "tandem_sweep"},
         {"tandem", three_stands()},
         {"options",
          {{"parameter", "/spans/tension_MPa"}, {"values", {80.0}}, {"quantity", "stability"}}}});
    json both = three_stands();
    both["spans"]["tension_MPa"] = {80, 80};
    check_point_is_tandem(answer["result"]["points"][0], both);

    // One stand's own field, in its scenario's units; stands are 0-based as in JSON pointers.
    const json stand = answer_of({{"analysis", "tandem_sweep"},
                                  {"tandem", two_stands},
                                  {"options",
                                   {{"parameter", "/stands/1/lubricant/viscosity_Pa_s"},
                                    {"range", {{"from", 0.0006}, {"to", 0.001}, {"count", 2}}},
                                    {"quantity", "stability"}}}});
    CHECK(stand["result"]["value_name"] == "value_Pa_s");
    json second = two_stands;
    second["stands"][1] = {{"lubricant", {{"viscosity_Pa_s", 0.001}}}};
    check_point_is_tandem(stand["result"]["points"][1], second);

    const service::CsvAnswer csv = service::csv_answer(stand, "points");
    REQUIRE(csv.status == 200);
    CHECK(csv.body.starts_with("value_Pa_s,status,stable,growth_rate_per_s,"));
    CHECK(std::count(csv.body.begin(), csv.body.end(), '\n') == 3);  // header + 2 values
}

TEST_CASE("a mill sweep of critical speeds: each point is the tandem analysis' headline") {
    // A narrow search keeps it short; the tandem analysis searches the same range.
    const json search = {{"speed_min_m_per_s", 5.0}, {"speed_max_m_per_s", 20.0}};
    const json answer = answer_of({{"analysis", "tandem_sweep"},
                                   {"tandem", two_stands},
                                   {"options",
                                    {{"parameter", "/spans/tension_MPa/0"},
                                     {"values", {60.0}},
                                     {"critical_speed", search}}}});
    const json& point = answer["result"]["points"][0];
    const json tandem =
        answer_of({{"analysis", "tandem"}, {"tandem", two_stands}, {"options", search}});
    const json& critical = tandem["result"]["critical_speeds"];
    CHECK(point["critical_speed_m_per_s"] == critical["critical_speed_m_per_s"]);
    CHECK(point["kind"] == critical["headline"]);
    const std::string kind = point["kind"].get<std::string>();
    CHECK(point["frequency_Hz"] == critical[kind]["frequency_Hz"]);
    CHECK(point["moving_stand"] == critical[kind]["moving_stand"]);
    CHECK(point["frozen_m_per_s"] == critical["frozen"]["speed_m_per_s"]);
    CHECK(point["nominal_delay_m_per_s"] == critical["nominal_delay"]["speed_m_per_s"]);
}

TEST_CASE("a mill sweep refuses what the mill cannot have, at the value's pointer") {
    const auto sweep = [](const json& options) {
        return json{{"analysis", "tandem_sweep"}, {"tandem", two_stands}, {"options", options}};
    };
    SUBCASE("a value out of the field's bounds: its bound and unit") {
        const json refused = refusal_of(sweep({{"parameter", "/spans/length_m/0"},
                                               {"values", {5.0, -1.0}},
                                               {"quantity", "stability"}}));
        REQUIRE(refused["errors"].size() == 1);
        CHECK(refused["errors"][0]["pointer"] == "/options/values/1");
        CHECK(refused["errors"][0].contains("bound"));
    }
    SUBCASE("a schedule that no longer falls: the mill's rule, named") {
        const json refused = refusal_of(sweep(
            {{"parameter", "/exit_thickness_mm/0"}, {"values", {2.0}}, {"quantity", "stability"}}));
        CHECK(refused["errors"][0]["pointer"] == "/options/values/0");
    }
    SUBCASE("a parameter that names no number of the document") {
        for (const char* parameter :
             {"/spans/length_m/3", "/spans/model", "/stand_defaults/rolls/radius_mm",
              "/stands/1/film_model", "spans/length_m", "/speed"}) {
            CAPTURE(parameter);
            const json refused = refusal_of(
                sweep({{"parameter", parameter}, {"values", {5.0}}, {"quantity", "stability"}}));
            CHECK(refused["errors"][0]["pointer"] == "/options/parameter");
        }
    }
    SUBCASE("a stand's field that the mill gives: the mill's field to sweep instead") {
        const json refused = refusal_of(sweep({{"parameter", "/stands/1/strip/reduction"},
                                               {"values", {0.2}},
                                               {"quantity", "stability"}}));
        CHECK(refused["errors"][0]["pointer"] == "/options/parameter");
        CHECK(refused["errors"][0]["detail"].get<std::string>().find("/exit_thickness_mm/1") !=
              std::string::npos);
    }
    SUBCASE("more values than a mill sweep takes") {
        const json refused =
            refusal_of(sweep({{"parameter", "/speed_m_per_s"},
                              {"range", {{"from", 10}, {"to", 20}, {"count", 201}}},
                              {"quantity", "stability"}}));
        REQUIRE(refused["errors"].size() == 1);
        CHECK(refused["errors"][0]["pointer"] == "/options/range/count");
    }
    SUBCASE("the mill speed in a sweep of critical speeds: the search scans it") {
        const json refused =
            refusal_of(sweep({{"parameter", "/speed_m_per_s"}, {"values", {10.0, 12.0}}}));
        REQUIRE(refused["errors"].size() == 1);
        CHECK(refused["errors"][0]["pointer"] == "/options/parameter");
    }
    SUBCASE("search options with quantity stability") {
        const json refused = refusal_of(sweep({{"parameter", "/speed_m_per_s"},
                                               {"values", {10}},
                                               {"quantity", "stability"},
                                               {"critical_speed", json::object()}}));
        CHECK(refused["errors"][0]["pointer"] == "/options/critical_speed");
    }
}

TEST_CASE("a mill sweep's chatter-type changes are the consecutive points whose types differ") {
    // Over the mill speed the rightmost root turns from the work rolls' fifth-octave mode to the
    // third-octave mill mode.
    const json result = answer_of({{"analysis", "tandem_sweep"},
                                   {"tandem", two_stands},
                                   {"options",
                                    {{"parameter", "/speed_m_per_s"},
                                     {"values", {5.0, 8.0, 11.0, 14.0, 17.0}},
                                     {"quantity", "stability"}}}})["result"];
    const json& points = result["points"];
    json expected = json::array();
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        if (points[i]["chatter_type"].is_null() || points[i + 1]["chatter_type"].is_null())
            continue;
        if (points[i]["chatter_type"] != points[i + 1]["chatter_type"])
            expected.push_back({points[i]["value_m_per_s"], points[i + 1]["value_m_per_s"]});
    }
    json listed = json::array();
    for (const json& change : result["chatter_type_changes"]) {
        listed.push_back({change["from"], change["to"]});
        CHECK(change["from_chatter_type"] != change["to_chatter_type"]);
    }
    CHECK(listed == expected);
    CHECK(!expected.empty());
}

TEST_CASE("a mill sweep's points in chunks assemble into the single run") {
    const json request = {{"analysis", "tandem_sweep"},
                          {"tandem", two_stands},
                          {"options",
                           {{"parameter", "/speed_m_per_s"},
                            {"values", {10.0, 12.0, 14.0}},
                            {"quantity", "stability"}}}};
    auto prepared = service::prepare(request);
    REQUIRE(std::holds_alternative<service::PreparedRequest>(prepared));
    const auto& points = std::get<service::PreparedRequest>(prepared).prepared.points;
    REQUIRE(points.has_value());
    REQUIRE(points->count == 3);
    json documents = points->compute(0, 2, core::Control{});
    for (json& point : points->compute(2, 3, core::Control{})) documents.push_back(point);
    CHECK(points->assemble(documents) == answer_of(request)["result"]);
}

}  // namespace tandem_sweep_test
