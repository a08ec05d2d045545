// What to change to run a tandem mill faster, through the one facade (tandem_speed_limit's
// what_to_change, docs/model.md §13.6): each row's derivative against the whole analysis rerun
// with the tandem document's field moved by ± a hundredth of its step, the derivative's own
// difference step (the nominal-delay crossing is the lowest of many lobes', and a wider move can
// hand it to another root: tests/core/test_mill_limit_sensitivity.cpp), with the chatter limit
// and with a stand's power limit binding; a change of every stand's number at once is the sum of
// the stands' own; the default fields for the request's stand count, echoed resolved; every
// violation of the list at once. The two-stand mill over 5-30 m/s: about 1 s.

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/mill_requests.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;

namespace tandem_what_to_change_test {

// The critical speeds refined to 1e-8 (the finest the options take) so that the reruns' differences
// are the crossing's own.
const json search = {{"speed_min_m_per_s", 5},
                     {"speed_max_m_per_s", 30},
                     {"speed_step_m_per_s", 0.5},
                     {"relative_tolerance", 1e-8}};

json request(const json& tandem, const json& options) {
    json o = search;
    o.update(options);
    return {{"analysis", "tandem_speed_limit"}, {"tandem", tandem}, {"options", o}};
}

json row_of(const json& result, const std::string& field) {
    for (const json& row : result["what_to_change"]["changes"])
        if (row["field"] == field) return row;
    FAIL("no row for " << field);
    return json();
}

// The advised mill speed with the tandem document's `field` set to `value`.
double advised_with(const json& options, const std::string& field, double value,
                    const std::string& binding) {
    json tandem = test::two_stands;
    tandem[json::json_pointer(field)] = value;
    json o = options;
    o["what_to_change"] = false;
    const json result = test::answer_of(request(tandem, o))["result"];
    CHECK(result["binding_limit"] == binding);  // the same limit binds on both sides
    return result["advised_speed_m_per_s"].get<double>();
}

// Each listed row's derivative against the analysis rerun at value ± step / 100.
void check_rows(const json& options, const std::vector<std::string>& fields,
                const std::string& binding) {
    const json result = test::answer_of(request(test::two_stands, options))["result"];
    REQUIRE(result["what_to_change"]["binding_limit"] == binding);
    for (const std::string& field : fields) {
        CAPTURE(field);
        const json row = row_of(result, field);
        REQUIRE(row["advised_speed_change_m_per_s_per_unit"].is_number());
        const double value = row["value"].get<double>();
        const double q = 0.01 * row["step"].get<double>();
        const double difference = (advised_with(options, field, value + q, binding) -
                                   advised_with(options, field, value - q, binding)) /
                                  (2.0 * q);
        const double derivative = row["advised_speed_change_m_per_s_per_unit"].get<double>();
        MESSAGE(field << ": " << derivative << " m/s per " << row["unit"].get<std::string>()
                      << " against " << difference << " rerun");
        CHECK(derivative == rollgap::test::approx(difference).epsilon(2e-3));
        // the gain per typical step, in the direction that gains
        CHECK(row["speed_gain_m_per_s"].get<double>() ==
              rollgap::test::approx(std::abs(derivative) * row["step"].get<double>()));
        CHECK(row["direction"] == (derivative >= 0.0 ? "raise" : "lower"));
    }
    // ranked by the gain
    double previous = INFINITY;
    for (const json& row : result["what_to_change"]["changes"]) {
        if (!row["speed_gain_m_per_s"].is_number()) continue;
        CHECK(row["speed_gain_m_per_s"].get<double>() <= previous);
        previous = row["speed_gain_m_per_s"].get<double>();
    }
}

bool has_error_at(const json& problem, const std::string& pointer) {
    for (const json& e : problem["errors"])
        if (e["pointer"] == pointer) return true;
    return false;
}

}  // namespace tandem_what_to_change_test

namespace wtc = tandem_what_to_change_test;

TEST_CASE("tandem what to change: with the chatter limit binding, each row is the analysis rerun") {
    const json changes =
        json::array({{{"field", "/spans/tension_MPa/0"}, {"step", 5}},
                     {{"field", "/stands/1/lubricant/viscosity_Pa_s"}, {"step", 0.0001}},
                     {{"field", "/exit_thickness_mm/0"}, {"step", 0.02}},
                     {{"field", "/stands/0/rolls/radius_mm"}, {"step", 10}}});
    const json options = {{"chatter_margin", 0.05}, {"changes", changes}};
    const json result = test::answer_of(wtc::request(test::two_stands, options))["result"];
    const json& what = result["what_to_change"];
    REQUIRE(result["binding_limit"] == "chatter");
    const json& critical = result["critical_speeds"];
    const std::string headline = critical["headline"].get<std::string>();
    CHECK(what["crossing"] == headline);
    CHECK(what["binding_stand"] == result["binding_stand"]);
    CHECK(what["crossing_speed_m_per_s"].get<double>() ==
          rollgap::test::approx(critical[headline]["speed_m_per_s"].get<double>()));
    CHECK(what["note"].get<std::string>().find(headline) != std::string::npos);
    wtc::check_rows(options,
                    {"/spans/tension_MPa/0", "/stands/1/lubricant/viscosity_Pa_s",
                     "/exit_thickness_mm/0", "/stands/0/rolls/radius_mm"},
                    "chatter");
}

TEST_CASE(
    "tandem what to change: with a stand's power limit binding, each row is the analysis "
    "rerun") {
    const json changes =
        json::array({{{"field", "/spans/tension_MPa/0"}, {"step", 5}},
                     {{"field", "/exit/tension_MPa"}, {"step", 5}},
                     {{"field", "/stands/1/roughness/roll_rq_um"}, {"step", 0.1}}});
    // stand 2's power at 20 m/s (the tandem analysis' schedule) is its limit
    json at = test::two_stands;
    at["speed_m_per_s"] = 20.0;
    const double power_kW =
        test::answer_of(
            {{"analysis", "tandem"},
             {"tandem", at},
             {"options",
              {{"critical_speed", false}}}})["result"]["steady_state"]["stands"][1]["power_kW"]
            .get<double>();
    const json options = {{"chatter", false},
                          {"stands", {json::object(), {{"max_power_kW", power_kW}}}},
                          {"changes", changes}};
    const json result = test::answer_of(wtc::request(test::two_stands, options))["result"];
    REQUIRE(result["binding_limit"] == "power");
    CHECK(result["what_to_change"]["binding_stand"] == 2);
    CHECK(result["what_to_change"]["crossing"].is_null());
    CHECK(result["what_to_change"]["crossing_speed_m_per_s"].get<double>() ==
          rollgap::test::approx(result["advised_speed_m_per_s"].get<double>()));
    wtc::check_rows(options,
                    {"/spans/tension_MPa/0", "/exit/tension_MPa", "/stands/1/roughness/roll_rq_um"},
                    "power");
}

TEST_CASE("tandem what to change: every stand's viscosity at once is the sum of each stand's") {
    const json changes =
        json::array({{{"field", "/stand_defaults/lubricant/viscosity_Pa_s"}, {"step", 0.0001}},
                     {{"field", "/stands/0/lubricant/viscosity_Pa_s"}, {"step", 0.0001}},
                     {{"field", "/stands/1/lubricant/viscosity_Pa_s"}, {"step", 0.0001}}});
    const json result = test::answer_of(
        wtc::request(test::two_stands, {{"chatter_margin", 0.05}, {"changes", changes}}))["result"];
    const auto derivative = [&](const std::string& field) {
        return wtc::row_of(result, field)["advised_speed_change_m_per_s_per_unit"].get<double>();
    };
    const double both = derivative("/stand_defaults/lubricant/viscosity_Pa_s");
    const double sum = derivative("/stands/0/lubricant/viscosity_Pa_s") +
                       derivative("/stands/1/lubricant/viscosity_Pa_s");
    MESSAGE("every stand's viscosity: " << both << " m/s per Pa.s, the stands' sum " << sum);
    CHECK(both == rollgap::test::approx(sum).epsilon(1e-3));
    CHECK(wtc::row_of(result, "/stand_defaults/lubricant/viscosity_Pa_s")["value"] ==
          wtc::row_of(result, "/stands/0/lubricant/viscosity_Pa_s")["value"]);
}

TEST_CASE("tandem what to change: the default fields follow the stand count, echoed resolved") {
    const json answer = test::answer_of(wtc::request(test::two_stands, {{"chatter", false}}));
    const json& changes = answer["options"]["changes"];
    std::vector<std::string> fields;
    for (const json& c : changes) fields.push_back(c["field"].get<std::string>());
    CHECK(fields == std::vector<std::string>{
                        "/entry/tension_MPa", "/spans/tension_MPa/0", "/exit/tension_MPa",
                        "/exit_thickness_mm/0", "/stands/0/lubricant/viscosity_Pa_s",
                        "/stands/0/roughness/roll_rq_um", "/stands/0/rolls/radius_mm",
                        "/stands/1/lubricant/viscosity_Pa_s", "/stands/1/roughness/roll_rq_um",
                        "/stands/1/rolls/radius_mm"});
    CHECK(changes[0]["step"] == 5);
    CHECK(changes[3]["step"] == 0.02);
    CHECK(answer["options"]["what_to_change"] == true);
    // nothing binds below 30 m/s without chatter or plant limits: nothing to gain, said so
    const json& what = answer["result"]["what_to_change"];
    CHECK(what["binding_limit"].is_null());
    CHECK(what["changes"].size() == 10);
    for (const json& row : what["changes"])
        CHECK(row["advised_speed_change_m_per_s_per_unit"].is_null());
    // the echo answers the same
    json again = wtc::request(test::two_stands, answer["options"]);
    CHECK(test::answer_of(again)["options"] == answer["options"]);
    // what_to_change false: no answer to it
    CHECK(test::answer_of(wtc::request(
        test::two_stands,
        {{"chatter", false}, {"what_to_change", false}}))["result"]["what_to_change"]
              .is_null());
}

TEST_CASE("tandem what to change: every violation of the list is reported at once") {
    const json changes = json::array({
        {{"field", "/stands/2/lubricant/viscosity_Pa_s"}, {"step", 0.0001}},  // 2 stands: 0, 1
        {{"field", "/stands/0/strip/reduction"}, {"step", 0.01}},  // the mill's: exit_thickness
        {{"field", "/speed_m_per_s"}, {"step", 1}},                // the answer
        {{"field", "/spans/tension_MPa"}, {"step", 5}},            // a list, not an element
        {{"field", "/spans/tension_MPa/1"}, {"step", 5}},          // one span: element 0 only
        {{"field", "/entry/tension_MPa"}, {"step", 0}},            // a step > 0
        {{"field", "/exit/tension_MPa"}, {"step", 5}},
        {{"field", "/exit/tension_MPa"}, {"step", 5}},         // twice
        {{"field", "/stands/0/friction/model"}, {"step", 1}},  // not a number
        {{"step", 1}},                                         // no field
    });
    const json problem = test::refusal_of(wtc::request(test::two_stands, {{"changes", changes}}));
    for (const char* pointer :
         {"/options/changes/0/field", "/options/changes/1/field", "/options/changes/2/field",
          "/options/changes/3/field", "/options/changes/4/field", "/options/changes/5/step",
          "/options/changes/7/field", "/options/changes/8/field", "/options/changes/9/field"}) {
        CAPTURE(pointer);
        CHECK(wtc::has_error_at(problem, pointer));
    }
    CHECK_FALSE(wtc::has_error_at(problem, "/options/changes/6/field"));
    // the mill's own field is named where a stand's is refused
    CHECK(problem.dump().find("/exit_thickness_mm/0") != std::string::npos);
}
