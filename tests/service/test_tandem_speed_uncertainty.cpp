// A mill's speed limit under its stands' calibration posteriors, through the one facade
// (tandem_speed_limit's options.posteriors, docs/model.md §13.7): the headline critical speed's
// sigma is g Σ gᵀ over the stands' parameters (the stands independent: rebuilt here from the
// answer's own rows and each posterior's correlation), the chatter limit is taken at
// (V_c − z sigma)(1 − m), each parameter's derivative is the one what_to_change reports for that
// field, a plant end is taken at its one-sided bound, the resolved echo answers the same, and
// every violation of the list is reported at once. The two-stand mill over 5-30 m/s: about 1 s.

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/mill_requests.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;

namespace tandem_speed_uncertainty_test {

const json search = {{"speed_min_m_per_s", 5},
                     {"speed_max_m_per_s", 30},
                     {"speed_step_m_per_s", 0.5},
                     {"relative_tolerance", 1e-8}};

json request(const json& options) {
    json o = search;
    o.update(options);
    return {{"analysis", "tandem_speed_limit"}, {"tandem", test::two_stands}, {"options", o}};
}

// Small posteriors (standard errors of 0.2-0.5 %) at the default stand's values: stand 1's
// viscosity alone, stand 2's viscosity and asperity factor correlated -0.5.
const json posteriors = json::array({
    {{"parameters",
      {{{"field", "/lubricant/viscosity_Pa_s"}, {"value", 0.00055}, {"standard_error", 1e-6}}}}},
    {{"parameters",
      {{{"field", "/lubricant/viscosity_Pa_s"}, {"value", 0.00055}, {"standard_error", 1e-6}},
       {{"field", "/friction/asperity_factor"}, {"value", 1.0}, {"standard_error", 0.005}}}},
     {"correlation", {{1.0, -0.5}, {-0.5, 1.0}}}},
});

bool has_error_at(const json& problem, const std::string& pointer) {
    for (const json& e : problem["errors"])
        if (e["pointer"] == pointer) return true;
    return false;
}

std::string message_at(const json& problem, const std::string& pointer) {
    for (const json& e : problem["errors"])
        if (e["pointer"] == pointer) return e["detail"].get<std::string>();
    return {};
}

}  // namespace tandem_speed_uncertainty_test

namespace tsu = tandem_speed_uncertainty_test;

TEST_CASE(
    "tandem speed uncertainty: the chatter limit at the headline's lower bound, sigma from "
    "the stands' rows") {
    const json changes =
        json::array({{{"field", "/stands/1/lubricant/viscosity_Pa_s"}, {"step", 0.0001}},
                     {{"field", "/stands/1/friction/asperity_factor"}, {"step", 0.05}}});
    const json answer = test::answer_of(tsu::request({{"chatter_margin", 0.05},
                                                      {"posteriors", tsu::posteriors},
                                                      {"changes", changes},
                                                      {"samples", 8},
                                                      {"seed", 3}}));
    const json& result = answer["result"];
    const json& u = result["uncertainty"];
    REQUIRE(u.is_object());
    REQUIRE(u["propagated"] == true);
    CHECK(u["crossing"] == result["critical_speeds"]["headline"]);
    const double vc = u["critical_speed_m_per_s"].get<double>();
    const double sigma = u["standard_deviation_m_per_s"].get<double>();
    const double z = u["z"].get<double>();
    CHECK(z == rollgap::test::approx(1.6448536269514722));
    CHECK(vc ==
          rollgap::test::approx(result["critical_speeds"]["critical_speed_m_per_s"].get<double>()));
    CHECK(u["lower_bound_m_per_s"].get<double>() == rollgap::test::approx(vc - z * sigma));
    REQUIRE(result["binding_limit"] == "chatter");
    CHECK(result["advised_speed_m_per_s"].get<double>() ==
          rollgap::test::approx(0.95 * (vc - z * sigma)).epsilon(1e-12));
    // sigma² = c ρ cᵀ over the rows' changes per standard error, the stands independent
    const json& rows = u["parameters"];
    REQUIRE(rows.size() == 3);
    CHECK(rows[0]["stand"] == 1);
    CHECK(rows[1]["stand"] == 2);
    CHECK(rows[2]["field"] == "/friction/asperity_factor");
    std::vector<double> c;
    for (const json& row : rows) c.push_back(row["critical_speed_change_m_per_s"].get<double>());
    const double variance = c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - 2.0 * 0.5 * c[1] * c[2];
    MESSAGE("headline " << vc << " m/s: sigma " << sigma << " m/s, rows " << c[0] << ", " << c[1]
                        << ", " << c[2]);
    CHECK(sigma == rollgap::test::approx(std::sqrt(variance)).epsilon(1e-9));
    // each stand-2 row's derivative is what_to_change's for that field, less the margin
    for (const json& row : result["what_to_change"]["changes"]) {
        const std::string field = row["field"].get<std::string>();
        const json& mine = field == changes[0]["field"] ? rows[1] : rows[2];
        const double per_unit = mine["critical_speed_change_m_per_s"].get<double>() /
                                mine["standard_error"].get<double>();
        CAPTURE(field);
        CHECK(row["advised_speed_change_m_per_s_per_unit"].get<double>() ==
              rollgap::test::approx(0.95 * per_unit).epsilon(2e-3));
    }
    // the seeded draws: 8 whole searches, their mean within 4 standard errors of V_c (σ/√8);
    // their agreement with sigma draw by draw is tests/core/test_mill_speed_uncertainty.cpp's
    const json& sampled = u["sampled"];
    REQUIRE(sampled.is_object());
    MESSAGE("sampled " << sampled.dump());
    CHECK(sampled["samples"].get<int>() + sampled["failed_samples"].get<int>() == 8);
    CHECK(std::abs(sampled["mean_m_per_s"].get<double>() - vc) < 4.0 * sigma / std::sqrt(8.0));
    // the echo lists the posteriors, samples and seed, and answers the same (the same draws)
    const json again = test::answer_of({{"analysis", "tandem_speed_limit"},
                                        {"tandem", test::two_stands},
                                        {"options", answer["options"]}});
    CHECK(answer["options"]["samples"] == 8);
    CHECK(answer["options"]["seed"] == 3);
    CHECK(again["options"] == answer["options"]);
    CHECK(again["result"]["advised_speed_m_per_s"] == result["advised_speed_m_per_s"]);
    CHECK(again["result"]["uncertainty"]["sampled"] == sampled);
}

TEST_CASE("tandem speed uncertainty: a plant end is taken at its one-sided bound") {
    const json answer =
        test::answer_of(tsu::request({{"chatter", false},
                                      {"stands", {json::object(), {{"max_power_kW", 4700}}}},
                                      {"posteriors", tsu::posteriors}}));
    const json& result = answer["result"];
    CHECK(result["uncertainty"].is_null());  // no chatter limit
    REQUIRE(result["binding_limit"] == "power");
    for (const json& row : result["limits"]) {
        if (row["limit"] != "power") continue;
        REQUIRE(row["upper_speed_sd_m_per_s"].is_number());
        const double end = row["upper_speed_m_per_s"].get<double>();
        const double sd = row["upper_speed_sd_m_per_s"].get<double>();
        MESSAGE("stand 2's power end " << end << " m/s, sigma " << sd << " m/s");
        CHECK(sd > 0.0);
        CHECK(result["advised_speed_m_per_s"].get<double>() ==
              rollgap::test::approx(end - 1.6448536269514722 * sd).epsilon(1e-12));
    }
}

TEST_CASE("tandem speed uncertainty: every violation of the posteriors is reported at once") {
    json wrong = tsu::posteriors;
    wrong[0]["parameters"][0]["value"] = 0.0006;              // not stand 1's viscosity
    wrong[1]["parameters"][1]["field"] = "/strip/reduction";  // the mill gives it
    wrong[1]["parameters"][1]["value"] = 0.15;
    const json problem = test::refusal_of(tsu::request({{"posteriors", wrong}}));
    // the value elsewhere answered in the tandem document's terms: the stand's patch to merge into
    const std::string elsewhere =
        tsu::message_at(problem, "/options/posteriors/0/parameters/0/value");
    CHECK(elsewhere.find("/stands/0 over /stand_defaults") != std::string::npos);
    CHECK(elsewhere.find("calibrated_scenario for this stand into /stands/0") != std::string::npos);
    CHECK(tsu::has_error_at(problem, "/options/posteriors/1/parameters/1/field"));
    CHECK(problem.dump().find("/exit_thickness_mm/1") != std::string::npos);
    const json short_list = test::refusal_of(tsu::request({{"posteriors", {nullptr}}}));
    CHECK(tsu::has_error_at(short_list, "/options/posteriors"));
    // draws need posteriors, and a chatter limit whose uncertainty they check
    CHECK(tsu::has_error_at(test::refusal_of(tsu::request({{"samples", 4}})), "/options/samples"));
    const json unchecked = test::refusal_of(
        tsu::request({{"samples", 4}, {"chatter", false}, {"posteriors", tsu::posteriors}}));
    CHECK(tsu::has_error_at(unchecked, "/options/samples"));
}
