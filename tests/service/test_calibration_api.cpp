// The analysis "calibrate" through the facade: invalid requests are refused with the pointer,
// bound and unit; the calibration example of docs/cli.md (examples/calibrate.json, the tests
// named "README example", which the README links to) is plant data made by the
// model at known values and the fit returns those values; the calibrated scenario is a merge
// patch that reproduces them.

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <random>

#include <nlohmann/json.hpp>

#include "api/calibration_json.h"
#include "api/scenario_json.h"
#include "service/evaluate.h"
#include "support/refused_options.h"
#include "support/repository.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

const json flow_stress = {{"field", "/strip/flow_stress_MPa"}};
const json force_at_5 = {{"scenario", {{"rolls", {{"speed_m_per_s", 5}}}}},
                         {"quantity", "roll_force_kN"},
                         {"value", 12000},
                         {"standard_uncertainty", 60}};

json options_with(const json& parameter, const json& observation) {
    return {{"parameters", {parameter}}, {"observations", {observation}}};
}

json with(json object, const std::string& key, const json& value) {
    object[key] = value;
    return object;
}

json example_request() {
    const auto path = rollgap::test::repository_root() / "examples" / "calibrate.json";
    std::ifstream file(path);
    REQUIRE_MESSAGE(file, "cannot read " << path.string());
    return json::parse(file);
}

// The "plant" values the example's observations were made at.
const std::map<std::string, double> example_truth{{"/strip/flow_stress_MPa", 410.0},
                                                  {"/friction/asperity_factor", 0.7},
                                                  {"/mill/rayleigh/damping_ratio", 0.05},
                                                  {"/tension/back/span_length_m", 8.0}};

}  // namespace

TEST_CASE("calibrate: bad parameters are refused with their pointer") {
    // Unknown pointer, with a suggestion.
    const json unknown = test::refused_options(
        "calibrate", options_with({{"field", "/strip/flow_stress_Pa"}}, force_at_5),
        "/options/parameters/0/field");
    CHECK(unknown["detail"].get<std::string>().find("/strip/flow_stress_MPa") != std::string::npos);
    // A field that is not a continuous number.
    test::refused_options("calibrate", options_with({{"field", "/friction/model"}}, force_at_5),
                          "/options/parameters/0/field");
    test::refused_options("calibrate",
                          options_with({{"field", "/numerics/bite_intervals"}}, force_at_5),
                          "/options/parameters/0/field");
    // Bounds outside the field's own, with its bound and unit.
    test::check_refused_options("calibrate", options_with(with(flow_stress, "min", 5), force_at_5),
                                "/options/parameters/0/min", "[10, 3000]", "MPa");
    test::refused_options("calibrate",
                          options_with(with(with(flow_stress, "min", 400), "max", 390), force_at_5),
                          "/options/parameters/0/max");
    // The start (the scenario's value, 380 MPa) must lie in the box.
    test::refused_options("calibrate", options_with(with(flow_stress, "min", 400), force_at_5),
                          "/options/parameters/0/min");
    // A prior needs a positive uncertainty.
    test::refused_options(
        "calibrate",
        options_with(with(flow_stress, "prior", {{"value", 380}, {"standard_uncertainty", 0}}),
                     force_at_5),
        "/options/parameters/0/prior/standard_uncertainty");
    // The same field twice.
    test::refused_options(
        "calibrate", {{"parameters", {flow_stress, flow_stress}}, {"observations", {force_at_5}}},
        "/options/parameters/1/field");
    test::refused_options("calibrate",
                          {{"parameters", json::array()}, {"observations", {force_at_5}}},
                          "/options/parameters");
}

TEST_CASE("calibrate: bad observations are refused with their pointer") {
    test::refused_options("calibrate",
                          options_with(flow_stress, with(force_at_5, "standard_uncertainty", 0)),
                          "/options/observations/0/standard_uncertainty");
    test::refused_options(
        "calibrate", options_with(flow_stress, with(force_at_5, "quantity", "strip_temperature_K")),
        "/options/observations/0/quantity");
    test::refused_options("calibrate",
                          options_with(flow_stress, with(force_at_5, "value", "12 MN")),
                          "/options/observations/0/value");
    // A modal quantity needs its mode; other quantities have none.
    test::refused_options(
        "calibrate",
        options_with(flow_stress, with(force_at_5, "quantity", "natural_frequency_Hz")),
        "/options/observations/0/mode");
    test::refused_options("calibrate",
                          options_with(flow_stress, with(force_at_5, "mode", {{"index", 1}})),
                          "/options/observations/0/mode");
    // The conditions are read like a scenario, at their own pointer.
    const service::Outcome bad_condition =
        evaluate({{"analysis", "calibrate"},
                  {"options", options_with(flow_stress, with(force_at_5, "scenario",
                                                             {{"strip", {{"reduction", 0.9}}}}))}});
    CHECK(bad_condition.http_status == 422);
    CHECK(test::error_at(bad_condition, "/options/observations/0/scenario/strip/reduction")
              .is_object());
    // The fit sets its parameters in every condition: a condition may not.
    const service::Outcome sets_parameter = evaluate(
        {{"analysis", "calibrate"},
         {"options", options_with(flow_stress, with(force_at_5, "scenario",
                                                    {{"strip", {{"flow_stress_MPa", 400}}}}))}});
    CHECK(sets_parameter.http_status == 422);
    CHECK(test::error_at(sets_parameter, "/options/observations/0/scenario/strip/flow_stress_MPa")
              .is_object());
}

TEST_CASE("calibrate: the work is bounded before anything runs") {
    // 100 iterations of 2 parameters on 4 conditions with critical-speed observations at a
    // fine step: far beyond the budget, refused at max_iterations with the allowed range.
    json observations = json::array();
    for (int i = 0; i < 4; ++i) {
        observations.push_back({{"scenario", {{"strip", {{"reduction", 0.1 + 0.02 * i}}}}},
                                {"quantity", "critical_speed_m_per_s"},
                                {"value", 20},
                                {"standard_uncertainty", 0.5}});
    }
    const json options = {
        {"parameters", {flow_stress, {{"field", "/mill/rayleigh/damping_ratio"}}}},
        {"observations", observations},
        {"max_iterations", 100},
        {"critical_speed", {{"speed_step_m_per_s", 0.05}}}};
    const json error = test::refused_options("calibrate", options, "/options/max_iterations");
    CHECK(error["detail"].get<std::string>().find("250000") != std::string::npos);
}

TEST_CASE(
    "README example: the fit returns the plant's values, and its calibrated scenario reproduces them") {
    const json request = example_request();
    const service::Outcome outcome = evaluate(request);
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    const json& result = outcome.body["result"];
    CHECK(result["status"] == "converged");
    const auto& truth = example_truth;
    REQUIRE(result["parameters"].size() == truth.size());
    for (const json& parameter : result["parameters"]) {
        const std::string field = parameter["field"];
        CAPTURE(field);
        const double value = parameter["value"];
        CHECK(std::abs(value / truth.at(field) - 1.0) < 1e-4);
        CHECK(parameter["standard_error"].is_number());
        CHECK(parameter["at_bound"].is_null());
        MESSAGE(field << " = " << value << " ± " << parameter["standard_error"].get<double>());
    }
    CHECK(result["chi_squared_observations"].get<double>() < 1e-6);
    CHECK(result["warnings"].empty());
    // Sent back, the calibrated scenario carries the fitted values.
    const json patch = result["calibrated_scenario"];
    const service::Outcome rerun = evaluate(
        {{"analysis", "roll_gap"}, {"scenario", patch}, {"options", {{"distributions", false}}}});
    REQUIRE(rerun.ok());
    for (const json& parameter : result["parameters"]) {
        const json::json_pointer at(parameter["field"].get<std::string>());
        CHECK(rerun.body["scenario"][at] == parameter["value"]);
    }
}

TEST_CASE("README example: its observations are the model's predictions at the plant values") {
    const json request = example_request();
    json patch = json::object();
    for (const auto& [field, value] : example_truth) patch[json::json_pointer(field)] = value;
    api::FieldErrors errors;
    const core::Scenario plant = api::scenario_from_patch(patch, "/scenario", errors);
    const api::CalibrationPlan plan =
        api::calibration_plan_from_json(request["options"], "/options", &plant, errors);
    REQUIRE(errors.empty());
    Eigen::VectorXd x(static_cast<Eigen::Index>(plan.setup.parameters.size()));
    for (std::size_t j = 0; j < plan.setup.parameters.size(); ++j)
        x(static_cast<Eigen::Index>(j)) = plan.setup.parameters[j].start;
    const auto predicted = core::predict_observations(plan.setup, x);
    for (std::size_t i = 0; i < predicted.size(); ++i) {
        CAPTURE(i);
        // The file gives 8 significant digits.
        CHECK(predicted[i].value ==
              rollgap::test::approx(plan.setup.observations[i].value).epsilon(1e-7));
    }
}

TEST_CASE("README example with seeded noise: the fitted values scatter by their standard errors") {
    // 4 seeds × 4 parameters: |error| > 2 standard errors has probability 4.6 % each; 4 or more
    // of 16 has probability 0.6 %.
    const json clean = example_request();
    int beyond_two = 0;
    for (unsigned seed = 1; seed <= 4; ++seed) {
        json request = clean;
        std::mt19937 generator(seed);
        std::normal_distribution<double> normal(0.0, 1.0);
        for (json& observation : request["options"]["observations"]) {
            observation["value"] =
                observation["value"].get<double>() +
                observation["standard_uncertainty"].get<double>() * normal(generator);
        }
        const service::Outcome outcome = evaluate(request);
        REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
        const json& result = outcome.body["result"];
        CHECK(result["status"] == "converged");
        for (const json& parameter : result["parameters"]) {
            const std::string field = parameter["field"];
            const double z = (parameter["value"].get<double>() - example_truth.at(field)) /
                             parameter["standard_error"].get<double>();
            CAPTURE(seed);
            CAPTURE(field);
            CAPTURE(z);
            CHECK(std::abs(z) < 4.0);
            beyond_two += std::abs(z) > 2.0 ? 1 : 0;
            MESSAGE("seed " << seed << ": " << field << " = " << parameter["value"].get<double>()
                            << " ± " << parameter["standard_error"].get<double>() << " (z = " << z
                            << ")");
        }
    }
    CHECK(beyond_two <= 3);
}

TEST_CASE("merge_patch_between is the inverse of a merge patch") {
    const json from = {{"a", 1}, {"b", {{"c", 2}, {"d", 3}}}, {"e", 4}};
    const json to = {{"a", 1}, {"b", {{"c", 5}, {"d", 3}}}, {"f", 6}};
    const json patch = api::merge_patch_between(from, to);
    CHECK(patch == json{{"b", {{"c", 5}}}, {"e", nullptr}, {"f", 6}});
}

TEST_CASE(
    "calibrate: a parameter stopped by its bound and two inseparable parameters are warnings that name them") {
    // 7000 kN at 19 m/s needs more than 390 MPa (the default 380 MPa gives ~6480 kN).
    const json force = {
        {"quantity", "roll_force_kN"}, {"value", 7000}, {"standard_uncertainty", 50}};
    const json capped = with(with(flow_stress, "min", 300), "max", 390);
    const service::Outcome bounded =
        evaluate({{"analysis", "calibrate"}, {"options", options_with(capped, force)}});
    REQUIRE_MESSAGE(bounded.ok(), bounded.body.dump());
    const json& fit = bounded.body["result"];
    CHECK(fit["status"] == "converged");
    CHECK(fit["parameters"][0]["value"] == 390.0);
    CHECK(fit["parameters"][0]["at_bound"] == "max");
    REQUIRE(fit["warnings"].size() == 1);
    CHECK(fit["warnings"][0]["code"] == "at_bound");
    CHECK(fit["warnings"][0]["fields"] == json::array({"/strip/flow_stress_MPa"}));

    // One natural frequency fixes k/m of the crosshead, not k and m.
    const json frequency = {{"quantity", "natural_frequency_Hz"},
                            {"mode", {{"index", 0}}},
                            {"value", 66},
                            {"standard_uncertainty", 0.5}};
    const json parameters =
        json::array({{{"field", "/mill/stiffness_GN_per_m/k1"}}, {{"field", "/mill/masses_t/m1"}}});
    const json options = {{"parameters", parameters}, {"observations", json::array({frequency})}};
    const service::Outcome pair = evaluate({{"analysis", "calibrate"}, {"options", options}});
    REQUIRE_MESSAGE(pair.ok(), pair.body.dump());
    const json& warnings = pair.body["result"]["warnings"];
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0]["code"] == "inseparable");
    CHECK(warnings[0]["fields"] ==
          json::array({"/mill/stiffness_GN_per_m/k1", "/mill/masses_t/m1"}));
    CHECK(pair.body["result"]["degrees_of_freedom"] == -1);
}
