// The analysis "tandem" through the facade (docs/model.md §12.8), what the CLI, HTTP and jobs
// run: the identity of a one-stand mill with the single-stand analysis (docs/model.md §12.1,
// TANDEM identity 1) through the two requests, the schedule's mass flow in the answer, the
// answer's own consistency (the headline is the lowest valid crossing, participations sum to
// one, mark spacings are u2 / f), the echo that reruns, the CSV tables, and the speeds mode (a
// schedule's roll speeds given back recover its tensions; each mode's refusals at their pointers).
// Mills here have one or two stands: a two-stand mill's critical speeds take ~0.1 s in Release.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "service/analyses/table.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"
#include "support/mill_requests.h"

using nlohmann::json;
using namespace rollgap;

using test::answer_of;
using test::two_stands;

TEST_CASE("a one-stand mill held at constant exit tension is the single stand (identity 1)") {
    // The single-stand default: 1.6 mm, 15 % (exit 1.36 mm), a 5 m back span at 18 MPa, the
    // front held at 0 MPa. As a mill: the entry span is that back span, the exit constant.
    const json tandem = {
        {"entry_thickness_mm", 1.6},
        {"exit_thickness_mm", {1.36}},
        {"speed_m_per_s", 19},
        {"spans", {{"length_m", json::array()}, {"tension_MPa", json::array()}}},
        {"entry", {{"boundary", "span"}, {"span_length_m", 5}, {"tension_MPa", 18}}},
        {"exit", {{"boundary", "constant"}, {"tension_MPa", 0}}},
        {"stands", json::array({json::object()})}};
    const json options = {
        {"speed_min_m_per_s", 10}, {"speed_max_m_per_s", 30}, {"relative_tolerance", 1e-6}};
    const json mill = answer_of({{"analysis", "tandem"}, {"tandem", tandem}, {"options", options}});
    const json stand = answer_of({{"analysis", "stability"}, {"options", options}});
    const json& crossing = mill["result"]["critical_speeds"]["frozen"];
    REQUIRE(crossing["status"] == "found");
    const double v_mill = crossing["speed_m_per_s"].get<double>();
    const double v_stand =
        stand["result"]["critical_speed"]["critical_speed_m_per_s"].get<double>();
    CHECK(std::abs(v_mill - v_stand) <= 2e-6 * v_stand);  // both refined to 1e-6
    const double f_stand =
        stand["result"]["critical_speed"]["unstable_mode"]["frequency_Hz"].get<double>();
    CHECK(std::abs(crossing["frequency_Hz"].get<double>() - f_stand) <= 1e-3 * f_stand);
    // No span, no transport: rho = 0, so the delay-independent limit is where A0 turns
    // unstable, the frozen crossing; the headline is that speed, whichever of the two it names.
    const json& critical = mill["result"]["critical_speeds"];
    const json& robust = critical["delay_independent"];
    REQUIRE(robust["status"] == "found");
    CHECK(std::abs(robust["speed_m_per_s"].get<double>() - v_mill) <= 2e-6 * v_mill);
    CHECK(std::abs(critical["critical_speed_m_per_s"].get<double>() - v_mill) <= 2e-6 * v_mill);
    CHECK(crossing["moving_stand"] == 1);
    // the stand's own steady state: the force and slip of the single stand at 19 m/s
    const json roll_gap = answer_of({{"analysis", "roll_gap"}});
    const json& row = mill["result"]["steady_state"]["stands"][0];
    const double force = roll_gap["result"]["force_kN"].get<double>();
    CHECK(std::abs(row["force_kN"].get<double>() - force) <= 1e-9 * force);
    CHECK(row["roll_speed_m_per_s"] == 19.0);
}

TEST_CASE("the two-stand answer: mass flow, stands numbered from 1, a consistent headline") {
    const json answer = answer_of({{"analysis", "tandem"}, {"tandem", two_stands}});
    const json& result = answer["result"];
    const json& steady = result["steady_state"];
    REQUIRE(steady["status"] == "ok");
    CHECK(steady["failed_stand"].is_null());
    CHECK(steady["mass_flow_residual"].get<double>() < 1e-10);
    const json& stands = steady["stands"];
    REQUIRE(stands.size() == 2);
    // u2_i y2_i = Q and u1_2 = u2_1 (identity 2), read from the answer's own figures
    const double q = steady["mass_flow_m2_per_s"].get<double>();
    for (const json& row : stands) {
        const double u2y2 =
            row["exit_speed_m_per_s"].get<double>() * row["exit_thickness_mm"].get<double>() * 1e-3;
        CHECK(std::abs(u2y2 - q) <= 1e-9 * q);
    }
    CHECK(stands[0]["stand"] == 1);
    CHECK(stands[1]["stand"] == 2);
    CHECK(stands[1]["roll_speed_m_per_s"] == 15.0);  // the mill speed is the last stand's
    CHECK(std::abs(stands[1]["entry_speed_m_per_s"].get<double>() -
                   stands[0]["exit_speed_m_per_s"].get<double>()) <=
          1e-9 * stands[0]["exit_speed_m_per_s"].get<double>());
    // tension stresses from the span's force: sigma_f,1 = T / y2_1 = 60 MPa, the same T over
    // y1_2 = y2_1 for stand 2's back
    CHECK(std::abs(stands[0]["front_tension_MPa"].get<double>() - 60.0) < 1e-9);
    CHECK(std::abs(stands[1]["back_tension_MPa"].get<double>() - 60.0) < 1e-9);

    const json& stability = result["stability"];
    CHECK(stability["status"] == "ok");
    const json& root = stability["rightmost_root"];
    REQUIRE(root.is_object());
    // the margin's peak judged as a root is: each stand's bite transit time x_w / u1 is the same
    // whichever frequency it is multiplied by, and the validity is the conjunction of its flags
    const json& margin_validity = stability["margin_validity"];
    REQUIRE(margin_validity.is_object());
    const double f_margin = stability["margin_frequency_Hz"].get<double>();
    const double f_root = root["frequency_Hz"].get<double>();
    for (std::size_t i = 0; i < 2; ++i)
        CHECK(std::abs(margin_validity["bite_transit_ratio"][i].get<double>() / f_margin -
                       root["validity"]["bite_transit_ratio"][i].get<double>() / f_root) <=
              1e-12 * margin_validity["bite_transit_ratio"][i].get<double>() / f_margin);
    CHECK(margin_validity["valid"] == (margin_validity["spring_law_valid"].get<bool>() &&
                                       margin_validity["quasi_static_bite_valid"].get<bool>()));
    REQUIRE(stability["margin_factors"].size() == 1);  // one span
    CHECK(std::abs(stability["margin_factors"][0]["tension_loop_gain"].get<double>() -
                   stability["regenerative_margin"].get<double>()) <=
          1e-9 * stability["regenerative_margin"].get<double>());
    double total = 0.0;
    for (const json& share : root["participation"]) total += share.get<double>();
    CHECK(std::abs(total - 1.0) < 1e-9);
    // chatter marks: u2 / f per stand
    const double f = root["frequency_Hz"].get<double>();
    const double sigma = root["growth_rate_per_s"].get<double>();
    CHECK(std::abs(root["damping_ratio"].get<double>() +
                   sigma / std::hypot(sigma, 2.0 * M_PI * f)) < 1e-12);
    for (const json& row : stands) {
        CHECK(std::abs(row["chatter_mark_spacing_mm"].get<double>() -
                       row["exit_speed_m_per_s"].get<double>() / f * 1e3) < 1e-9);
    }
    // stable as it runs iff no root lies right of the axis
    CHECK(stability["stable"] == (stability["roots_right_of_axis"] == 0));
    CHECK((root["growth_rate_per_s"].get<double>() < 0.0) == stability["stable"].get<bool>());

    // The headline is the lowest found crossing inside the model's range (docs/model.md §12.7).
    const json& critical = result["critical_speeds"];
    double lowest = INFINITY;
    std::string lowest_kind;
    for (const char* kind : {"frozen", "delay_independent", "nominal_delay"}) {
        const json& c = critical[kind];
        CHECK(c["kind"] == kind);
        if (c["status"] == "found" && c["validity"]["valid"] == true &&
            c["speed_m_per_s"].get<double>() < lowest) {
            lowest = c["speed_m_per_s"].get<double>();
            lowest_kind = kind;
        }
    }
    // the first crossing of any root is reported beside them, never above the band's crossing
    REQUIRE(critical["first_any"]["status"] == "found");
    if (critical["nominal_delay"]["status"] == "found")
        CHECK(critical["first_any"]["speed_m_per_s"].get<double>() <=
              critical["nominal_delay"]["speed_m_per_s"].get<double>());
    REQUIRE(!lowest_kind.empty());
    CHECK(critical["headline"] == lowest_kind);
    CHECK(critical["critical_speed_m_per_s"] == lowest);
    // every crossing below it lies outside the range, and is listed
    for (const json& kind : critical["outside_range_below"]) {
        const json& c = critical[kind.get<std::string>()];
        CHECK(c["validity"]["valid"] == false);
        CHECK(c["speed_m_per_s"].get<double>() < lowest);
    }
}

TEST_CASE("the echoed mill reruns to the same answer") {
    const json options = {{"critical_speed", false}};
    const json first =
        answer_of({{"analysis", "tandem"}, {"tandem", two_stands}, {"options", options}});
    const json again = answer_of(
        {{"analysis", "tandem"}, {"tandem", first["tandem"]}, {"options", first["options"]}});
    CHECK(again == first);
}

TEST_CASE("the tandem answer's CSV tables: stands and crossings, no time series unless asked") {
    const service::Analysis* tandem = service::find_analysis(service::analyses(), "tandem");
    REQUIRE(tandem != nullptr);
    const json answer = answer_of({{"analysis", "tandem"}, {"tandem", two_stands}});
    for (const api::CsvTable& table : tandem->tables()) {
        CAPTURE(table.name);
        const service::CsvAnswer csv = service::csv_answer(answer, table.name);
        CAPTURE(csv.body.substr(0, 300));
        if (table.name == "time_series") {  // not asked for: not there, and said so
            CHECK(csv.status == 406);
            continue;
        }
        REQUIRE(csv.status == 200);
        const auto lines = std::count(csv.body.begin(), csv.body.end(), '\n');
        if (table.name == "stands") CHECK(lines == 3);     // header + 2 stands
        if (table.name == "crossings") CHECK(lines == 4);  // header + 3 crossings
        CHECK(csv.body.find("\r\n") != std::string::npos);
    }
}

TEST_CASE("a scenario for a mill, or a mill for a stand, is an envelope problem") {
    const service::Outcome wrong_subject =
        service::evaluate({{"analysis", "tandem"}, {"scenario", json::object()}});
    CHECK(wrong_subject.http_status == 422);
    CHECK(wrong_subject.body["errors"][0]["pointer"] == "/scenario");
    const service::Outcome stand_with_mill =
        service::evaluate({{"analysis", "roll_gap"}, {"tandem", json::object()}});
    CHECK(stand_with_mill.http_status == 422);
    CHECK(stand_with_mill.body["errors"][0]["pointer"] == "/tandem");
}

TEST_CASE("the time series: the kicked stand, nothing arrives before the transport delay") {
    const json options = {{"critical_speed", false},
                          {"time_series", true},
                          {"window_s", 0.5},
                          {"time_series_points", 50}};
    const json answer =
        answer_of({{"analysis", "tandem"}, {"tandem", two_stands}, {"options", options}});
    const json& result = answer["result"];
    const json& series = result["time_series"];
    REQUIRE(series["status"] == "ok");
    CHECK(series["end_time_s"] == 0.5);
    // by default the stand the rightmost root moves most is kicked
    CHECK(series["kick_stand"] == result["stability"]["rightmost_root"]["moving_stand"]);
    const double tau = result["stability"]["delays_s"][0].get<double>();
    REQUIRE(tau < 0.5);
    const json& stands = series["stands"];
    REQUIRE(stands.size() == 2);
    const double y1_steady =
        result["steady_state"]["stands"][1]["entry_thickness_mm"].get<double>();
    const json& second = stands[1]["series"];
    REQUIRE(second["time_s"].size() == 50);
    bool arrived = false;
    for (std::size_t k = 0; k < 50; ++k) {
        const double t = second["time_s"][k].get<double>();
        const double y1 = second["entry_thickness_mm"][k].get<double>();
        // stand 2 receives what stand 1 delivered tau earlier: the steady strip until tau
        if (t < tau) CHECK(y1 == y1_steady);
        if (t > tau && y1 != y1_steady) arrived = true;
        // stand 1's entry is the mill's entry: nothing upstream moves
        CHECK(stands[0]["series"]["entry_thickness_mm"][k] ==
              result["steady_state"]["stands"][0]["entry_thickness_mm"]);
    }
    CHECK(arrived);  // stand 1 moves with the tension: its strip reaches stand 2 after tau
    // the series is judged by the rightmost root it grows or decays with, as the root is
    CHECK(series["in_model_range"] == result["stability"]["rightmost_root"]["validity"]["valid"]);
    CHECK_FALSE(series["range_note"].get<std::string>().empty());
    // a stand that is not there
    const service::Outcome wrong = service::evaluate(
        {{"analysis", "tandem"}, {"tandem", two_stands}, {"options", {{"kick_stand", 3}}}});
    CHECK(wrong.http_status == 422);
    CHECK(wrong.body["errors"][0]["pointer"] == "/options/kick_stand");
}

TEST_CASE("a mill's time series holds at most 20,000 points over all its stands") {
    // 10,000 points per stand is fine for two stands, not for three: the answer's size is
    // points x stands (api/tandem_options_json.h).
    const json options = {{"critical_speed", false}, {"time_series_points", 10000}};
    CHECK(std::holds_alternative<service::PreparedRequest>(
        service::prepare({{"analysis", "tandem"}, {"tandem", two_stands}, {"options", options}})));
    json three = two_stands;
    three["exit_thickness_mm"] = {1.6, 1.36, 1.2};
    three["spans"] = {{"length_m", {5, 5}}, {"tension_MPa", {60, 60}}};
    three["stands"] = json::array({json::object(), json::object(), json::object()});
    const service::Outcome refused =
        service::evaluate({{"analysis", "tandem"}, {"tandem", three}, {"options", options}});
    CHECK(refused.http_status == 422);
    CHECK(refused.body["errors"][0]["pointer"] == "/options/time_series_points");
    CHECK(refused.body["errors"][0]["bound"] == "[2, 6666]");
}

TEST_CASE("the roots in the model's band: none just below the nominal-delay speed, some above") {
    // The nominal-delay critical speed is the first speed at which a root inside the band
    // crosses (docs/model.md §12.7): the answer's in-band count at the mill's own speed must say
    // 0 just below it and at least 1 just above it (0.2 % either side, well inside one lobe
    // period: ~0.16 m/s here against 0.02 m/s).
    const json critical = answer_of({{"analysis", "tandem"}, {"tandem", two_stands}});
    const json& nominal = critical["result"]["critical_speeds"]["nominal_delay"];
    REQUIRE(nominal["status"] == "found");
    const double speed = nominal["speed_m_per_s"].get<double>();
    CHECK(nominal["lobe_period_m_per_s"].get<double>() > 0.004 * speed);
    const auto at = [&](double v) {
        json mill = two_stands;
        mill["speed_m_per_s"] = v;
        return answer_of({{"analysis", "tandem"},
                          {"tandem", mill},
                          {"options", {{"critical_speed", false}}}})["result"]["stability"];
    };
    const json below = at(speed * 0.998);
    const json above = at(speed * 1.002);
    CHECK(below["roots_in_band"] == 0);
    CHECK(above["roots_in_band"].get<int>() >= 1);
    for (const json& s : {below, above}) {
        CHECK(s["roots_in_band"].get<int>() <= s["roots_right_of_axis"].get<int>());
        CHECK(s["band_top_Hz"].get<double>() > 0.0);
    }
    // the crossing root lies inside the band it is counted in
    CHECK(nominal["frequency_Hz"].get<double>() < above["band_top_Hz"].get<double>());
}

TEST_CASE("speeds mode: a schedule's roll speeds given back recover its tensions and forces") {
    // docs/model.md §12.3: the schedule solves each stand's roll speed from the mass flow; the
    // same roll speeds given per stand (mode speeds) make the interstand tension the unknown,
    // and the mass flow must return the schedule's set point and so its stands, whatever the
    // tension the speeds search starts from. Through the facade, as the CLI, HTTP and jobs run it.
    json schedule_request = {
        {"analysis", "tandem"}, {"tandem", two_stands}, {"options", {{"critical_speed", false}}}};
    const json schedule = answer_of(schedule_request)["result"]["steady_state"];
    REQUIRE(schedule["status"] == "ok");

    json mill = two_stands;
    mill["mode"] = "speeds";
    mill["spans"]["tension_MPa"] = {30};  // only the search's start in speeds mode
    for (int i = 0; i < 2; ++i)
        mill["stands"][i]["rolls"]["speed_m_per_s"] =
            schedule["stands"][i]["roll_speed_m_per_s"].get<double>();
    const json speeds =
        answer_of({{"analysis", "tandem"},
                   {"tandem", mill},
                   {"options", {{"critical_speed", false}}}})["result"]["steady_state"];
    REQUIRE(speeds["status"] == "ok");
    for (int i = 0; i < 2; ++i) {
        const json &a = schedule["stands"][i], &b = speeds["stands"][i];
        CAPTURE(i);
        for (const char* name : {"front_tension_MPa", "back_tension_MPa"})
            CHECK(std::abs(b[name].get<double>() - a[name].get<double>()) <=
                  1e-6 * std::max(1.0, std::abs(a[name].get<double>())));
        CHECK(std::abs(b["force_kN"].get<double>() - a["force_kN"].get<double>()) <=
              1e-6 * a["force_kN"].get<double>());
    }
    CHECK(std::abs(speeds["stands"][0]["front_tension_MPa"].get<double>() - 60.0) < 1e-6);

    // schedule mode refuses a stand's roll speed, speeds mode needs every one: each a 422 at the
    // stand's pointer
    json refused = two_stands;
    refused["stands"][0]["rolls"]["speed_m_per_s"] = 10.0;
    const service::Outcome a = service::evaluate({{"analysis", "tandem"}, {"tandem", refused}});
    CHECK(a.http_status == 422);
    CHECK(a.body.dump().find("/tandem/stands/0/rolls/speed_m_per_s") != std::string::npos);
    json missing = mill;
    missing["stands"][0]["rolls"].erase("speed_m_per_s");
    const service::Outcome b = service::evaluate({{"analysis", "tandem"}, {"tandem", missing}});
    CHECK(b.http_status == 422);
    CHECK(b.body.dump().find("/tandem/stands/0") != std::string::npos);
}
