// The mill's speed limit through the one facade (analysis tandem_speed_limit, docs/model.md
// §13.5): a stand's own limit binds at the mill speed where the mill's pass schedule (the
// `tandem` analysis, a different path through the code) gives that stand the limit's figure,
// and the answer names the stand; mill-wide limits apply to every stand and the echo lists them
// resolved, an echo that gives the same answer again; the chatter limit is the answer's own
// headline critical speed less the margin, bound by the headline's moving stand; every
// violation of the per-stand list is reported at once; the CSV sheet leads with the stand; a
// batch of mills carries each item's own answer. Two-stand mills over 5-30 m/s: about 1 s.

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/batch_json.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"
#include "support/mill_requests.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;

namespace tandem_speed_limit_test {

const json search = {{"speed_min_m_per_s", 5},
                     {"speed_max_m_per_s", 30},
                     {"speed_step_m_per_s", 0.5},
                     {"relative_tolerance", 1e-4}};

json request(const json& limits) {
    json options = search;
    options.update(limits);
    return {{"analysis", "tandem_speed_limit"}, {"tandem", test::two_stands}, {"options", options}};
}

// Stand `stand`'s (1-based) steady figures at mill speed `speed` from the tandem analysis.
json stand_at(double speed, int stand) {
    json mill = test::two_stands;
    mill["speed_m_per_s"] = speed;
    const json answer = test::answer_of(
        {{"analysis", "tandem"}, {"tandem", mill}, {"options", {{"critical_speed", false}}}});
    return answer["result"]["steady_state"]["stands"][stand - 1];
}

std::vector<json> rows_of(const json& result, const std::string& limit) {
    std::vector<json> rows;
    for (const json& row : result["limits"])
        if (row["limit"] == limit) rows.push_back(row);
    return rows;
}

bool has_error_at(const json& problem, const std::string& pointer) {
    for (const json& e : problem["errors"])
        if (e["pointer"] == pointer) return true;
    return false;
}

}  // namespace tandem_speed_limit_test

using namespace tandem_speed_limit_test;

TEST_CASE("tandem speed limit: a stand's own force limit binds where the schedule gives it") {
    const double speed = 11.3;  // between grid speeds
    const double force_kN = stand_at(speed, 2)["force_kN"].get<double>();
    REQUIRE(stand_at(speed + 1.0, 2)["force_kN"].get<double>() < force_kN);  // falls with V
    const json answer = test::answer_of(request(
        {{"chatter", false}, {"stands", {json::object(), {{"max_roll_force_kN", force_kN}}}}}));
    const json& result = answer["result"];
    CHECK(result["status"] == "ok");
    CHECK(result["window_min_m_per_s"].get<double>() == rollgap::test::approx(speed).epsilon(1e-7));
    CHECK(result["binding_min"] == "force");
    CHECK(result["binding_min_stand"] == 2);
    CHECK(result["binding_limit"].is_null());  // nothing above: the range's top
    CHECK(result["binding_stand"].is_null());
    CHECK(result["chatter_basis"] == "not_checked");
    CHECK(result["critical_speeds"].is_null());
    const std::vector<json> force = rows_of(result, "force");
    REQUIRE(force.size() == 1);  // stand 1 has no force limit
    CHECK(force[0]["stand"] == 2);
    CHECK(force[0]["value"].get<double>() == rollgap::test::approx(force_kN).epsilon(1e-12));
    // the figure at the mill's own speed (15 m/s) is the schedule's there
    const double at_operating = stand_at(15.0, 2)["force_kN"].get<double>();
    CHECK(force[0]["at_operating"].get<double>() ==
          rollgap::test::approx(at_operating).epsilon(1e-12));
    CHECK(result["checked"] == json({"steady_state", "force"}));
}

TEST_CASE("tandem speed limit: the echo lists every stand's limits resolved and answers again") {
    const json answer =
        test::answer_of(request({{"chatter", false},
                                 {"max_power_kW", 5000},
                                 {"stands", {{{"max_power_kW", 2000}}, json::object()}}}));
    const json& options = answer["options"];
    CHECK(options["max_power_kW"] == 5000.0);
    CHECK(options["stands"] == json({{{"max_power_kW", 2000.0}}, {{"max_power_kW", 5000.0}}}));
    const std::vector<json> power = rows_of(answer["result"], "power");
    REQUIRE(power.size() == 2);
    CHECK(power[0]["stand"] == 1);
    CHECK(power[0]["value"] == 2000.0);
    CHECK(power[1]["stand"] == 2);
    CHECK(power[1]["value"] == 5000.0);
    // the power rises with the speed: each power limit bounds it from above, at its own speed
    for (const json& row : power) {
        REQUIRE(row["upper_speed_m_per_s"].is_number());
        const double v = row["upper_speed_m_per_s"].get<double>();
        const double kW = stand_at(v, row["stand"].get<int>())["power_kW"].get<double>();
        CHECK(kW == rollgap::test::approx(row["value"].get<double>()).epsilon(1e-7));
    }
    // the echo, sent back, is the same request
    const json again = test::answer_of(
        {{"analysis", "tandem_speed_limit"}, {"tandem", answer["tandem"]}, {"options", options}});
    CHECK(again["result"] == answer["result"]);
}

TEST_CASE("tandem speed limit: chatter is the headline less the margin, bound by its stand") {
    const json answer = test::answer_of(request({{"chatter_margin", 0.1}}));
    const json& result = answer["result"];
    const json& critical = result["critical_speeds"];
    REQUIRE(critical["headline"].is_string());
    CHECK(result["chatter_basis"] == "headline");
    const double v_c = critical["critical_speed_m_per_s"].get<double>();
    const json& head = critical[critical["headline"].get<std::string>()];
    const std::vector<json> chatter = rows_of(result, "chatter");
    REQUIRE(chatter.size() == 1);
    CHECK(chatter[0]["value"].get<double>() == rollgap::test::approx(0.9 * v_c).epsilon(1e-12));
    CHECK(chatter[0]["stand"] == head["moving_stand"]);
    REQUIRE(0.9 * v_c > 5.0);
    CHECK(result["advised_speed_m_per_s"].get<double>() ==
          rollgap::test::approx(0.9 * v_c).epsilon(1e-12));
    CHECK(result["binding_limit"] == "chatter");
    CHECK(result["binding_stand"] == head["moving_stand"]);
    CHECK(result["summary"].get<std::string>().find("chatter limit") != std::string::npos);
}

TEST_CASE("tandem speed limit: every violation of the per-stand list is reported at once") {
    // three entries for two stands, one of them out of bounds, one with an unknown member
    const json refused = test::refusal_of(request(
        {{"stands", {json::object(), {{"max_roll_force_kN", -1}}, {{"max_force_kN", 1000}}}},
         {"min_forward_slip", 2}}));
    CHECK(has_error_at(refused, "/options/stands"));
    CHECK(has_error_at(refused, "/options/stands/1/max_roll_force_kN"));
    CHECK(has_error_at(refused, "/options/stands/2/max_force_kN"));
    CHECK(has_error_at(refused, "/options/min_forward_slip"));
    for (const json& e : refused["errors"])
        if (e["pointer"] == "/options/stands") CHECK(e["bound"] == "2 items");
    // a stand's entry is an object ({} keeps the mill-wide limits), not null
    CHECK(has_error_at(test::refusal_of(request({{"stands", {nullptr, json::object()}}})),
                       "/options/stands/0"));
    // not a list
    CHECK(has_error_at(test::refusal_of(request({{"stands", 3}})), "/options/stands"));
}

TEST_CASE("tandem speed limit: the CSV sheet has one row per checked limit, led by its stand") {
    const json answer = test::answer_of(
        request({{"chatter", false}, {"max_roll_force_kN", 9000}, {"min_forward_slip", 0.0}}));
    const service::CsvAnswer csv = service::csv_answer(answer, "");
    REQUIRE(csv.status == 200);
    std::vector<std::string> lines;
    for (std::size_t at = 0; at < csv.body.size();) {
        const std::size_t end = csv.body.find("\r\n", at);
        lines.push_back(csv.body.substr(at, end - at));
        at = end + 2;
    }
    // the header, the mill's steady state, force and skid of each of two stands
    REQUIRE(lines.size() == 6);
    CHECK(lines[0].starts_with("stand,limit,unit,value,"));
    CHECK(lines[1].starts_with(",steady_state,"));
    CHECK(lines[2].starts_with("1,force,kN,9000"));
    CHECK(lines[5].starts_with("2,skid,1,0"));
}

TEST_CASE("tandem speed limit: a batch of mills carries each item's own answer") {
    json options = search;
    options["chatter"] = false;
    options["max_roll_force_kN"] = 7000;
    const json batch = test::answer_of(
        {{"analysis", "batch"},
         {"options",
          {{"analysis", "tandem_speed_limit"},
           {"tandem", test::two_stands},
           {"options", options},
           {"items",
            {{{"label", "M-1"}},
             {{"label", "M-2"},
              {"options", {{"stands", {json::object(), {{"max_roll_force_kN", 4650}}}}}}}}}}}});
    const json& rows = batch["result"]["items"];
    REQUIRE(rows.size() == 2);
    json second = request({{"chatter", false},
                           {"max_roll_force_kN", 7000},
                           {"stands", {json::object(), {{"max_roll_force_kN", 4650}}}}});
    const json own = test::answer_of(second)["result"];
    CHECK(rows[1]["status"] == "ok");
    CHECK(rows[1]["headline"] == api::batch_headline("tandem_speed_limit", own));
    CHECK(rows[1]["headline"]["binding_min_stand"] == own["binding_min_stand"]);
    CHECK(rows[1]["headline"]["advised_speed_m_per_s"] == own["advised_speed_m_per_s"]);
    CHECK(rows[0]["headline"] != rows[1]["headline"]);
}
