// The analysis "speed_limit" through the facade (docs/model.md §13): its options (strict,
// bounded, echoed), the posterior it reads, and its answer checked against core's own figures:
// each binding speed is where the steady figure equals the plant's limit, each utilisation is
// the figure's ratio at the operating speed, and the chatter limit is (V_c − zσ)(1 − margin)
// with σ propagated from the posterior (checked against differences of another step).

#include <doctest/doctest.h>

#include <cmath>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "api/speed_limit_json.h"
#include "core/propagation.h"
#include "core/speed_limit.h"
#include "core/stability.h"
#include "service/analyses/speed_limit.h"
#include "service/evaluate.h"
#include "support/refused_options.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace speed_limit_api_test {

json run_speed_limit(const json& options, const json& scenario = json::object()) {
    const Outcome outcome =
        evaluate({{"analysis", "speed_limit"}, {"scenario", scenario}, {"options", options}});
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    return outcome.body;
}

const json* find_limit(const json& result, const std::string& name) {
    for (const json& limit : result["limits"]) {
        if (limit["limit"] == name) return &limit;
    }
    return nullptr;
}

// A posterior on the lubricant's viscosity and the asperity factor, centred on the default
// stand, correlated: what a fit of force and slip leaves (docs/model.md §13.2).
json viscosity_asperity_posterior() {
    const core::Scenario s;
    return {{"parameters",
             {{{"field", "/lubricant/viscosity_Pa_s"},
               {"value", s.lubricant.viscosity},
               {"standard_error", 0.02 * s.lubricant.viscosity}},
              {{"field", "/friction/asperity_factor"},
               {"value", s.friction.asperity_factor},
               {"standard_error", 0.03 * s.friction.asperity_factor}}}},
            {"correlation", {{1.0, -0.5}, {-0.5, 1.0}}}};
}

}  // namespace speed_limit_api_test

using namespace speed_limit_api_test;

TEST_CASE("speed_limit options: the defaults are resolved and echoed") {
    api::FieldErrors errors;
    const PreparedAnalysis prepared =
        prepare_speed_limit(core::Scenario{}, json::object(), "/options", errors);
    CHECK(errors.empty());
    CHECK(prepared.resolved_options ==
          json{{"speed_min_m_per_s", 1.0},
               {"speed_max_m_per_s", 60.0},
               {"speed_step_m_per_s", 0.5},
               {"relative_tolerance", 1e-4},
               {"chatter", true},
               {"chatter_margin", 0.0},
               {"confidence", 0.95},
               {"samples", 0},
               {"seed", 1},
               {"what_to_change", true},
               {"changes",
                {{{"field", "/tension/back/stress_MPa"}, {"step", 5.0}},
                 {{"field", "/tension/front/stress_MPa"}, {"step", 5.0}},
                 {{"field", "/strip/reduction"}, {"step", 0.01}},
                 {{"field", "/lubricant/viscosity_Pa_s"}, {"step", 0.0001}},
                 {{"field", "/roughness/roll_rq_um"}, {"step", 0.1}},
                 {{"field", "/roughness/strip_rq_um"}, {"step", 0.1}},
                 {{"field", "/rolls/radius_mm"}, {"step", 10.0}}}},
               {"posterior", nullptr}});
}

TEST_CASE("speed_limit options: every bound is enforced, with its pointer, bound and unit") {
    const auto refused = [](const json& options, const std::string& pointer,
                            std::optional<std::string> bound, std::optional<std::string> unit) {
        test::check_refused_options("speed_limit", options, pointer, bound, unit);
    };
    refused({{"max_roll_force_kN", 0}}, "/options/max_roll_force_kN", "(0, 1000000]", "kN");
    refused({{"max_torque_kN_m", -1}}, "/options/max_torque_kN_m", "(0, 100000]", "kN.m");
    refused({{"max_power_kW", 2e6}}, "/options/max_power_kW", "(0, 1000000]", "kW");
    refused({{"min_forward_slip", 0.6}}, "/options/min_forward_slip", "[-0.5, 0.5]", "1");
    refused({{"chatter_margin", 1}}, "/options/chatter_margin", "[0, 1)", "1");
    refused({{"confidence", 0.4}}, "/options/confidence", "[0.5, 1)", "1");
    refused({{"confidence", 1}}, "/options/confidence", "[0.5, 1)", "1");
    refused({{"samples", 501}}, "/options/samples", "[0, 500]", "1");
    refused({{"chatter", "yes"}}, "/options/chatter", std::nullopt, std::nullopt);
    refused({{"speed_min_m_per_s", 30}, {"speed_max_m_per_s", 20}}, "/options/speed_max_m_per_s",
            "(30, 100]", "m/s");
    // draws need something to draw from
    refused({{"samples", 10}}, "/options/samples", std::nullopt, std::nullopt);
    // every violation at once
    const Outcome outcome = evaluate(
        {{"analysis", "speed_limit"}, {"options", {{"max_power_kW", 0}, {"chatter_margin", 2}}}});
    CHECK(outcome.http_status == 422);
    CHECK(test::error_at(outcome, "/options/max_power_kW").is_object());
    CHECK(test::error_at(outcome, "/options/chatter_margin").is_object());
}

TEST_CASE("speed_limit options: the posterior is read strictly, centred on the scenario") {
    json posterior = viscosity_asperity_posterior();
    SUBCASE("a field that is not one, with a suggestion") {
        posterior["parameters"][0]["field"] = "/lubricant/viscosity";
        const json error = test::refused_options("speed_limit", {{"posterior", posterior}},
                                                 "/options/posterior/parameters/0/field");
        CHECK(error["detail"].get<std::string>().find("viscosity_Pa_s") != std::string::npos);
    }
    SUBCASE("the same field twice") {
        posterior["parameters"][1]["field"] = "/lubricant/viscosity_Pa_s";
        test::refused_options("speed_limit", {{"posterior", posterior}},
                              "/options/posterior/parameters/1/field");
    }
    SUBCASE("a value that is not the scenario's") {
        posterior["parameters"][1]["value"] = 0.7;
        const json error = test::refused_options("speed_limit", {{"posterior", posterior}},
                                                 "/options/posterior/parameters/1/value");
        CHECK(error["detail"].get<std::string>().find("calibrated_scenario") != std::string::npos);
    }
    SUBCASE("a standard error of zero") {
        posterior["parameters"][0]["standard_error"] = 0;
        test::check_refused_options("speed_limit", {{"posterior", posterior}},
                                    "/options/posterior/parameters/0/standard_error", "(0, 1e+300]",
                                    "Pa.s");
    }
    SUBCASE("a unit that is not the field's") {
        posterior["parameters"][0]["unit"] = "mPa.s";
        test::check_refused_options("speed_limit", {{"posterior", posterior}},
                                    "/options/posterior/parameters/0/unit", "Pa.s", "Pa.s");
    }
    SUBCASE("a correlation no distribution has") {
        posterior["parameters"].push_back(
            {{"field", "/strip/flow_stress_MPa"}, {"value", 380}, {"standard_error", 5}});
        posterior["correlation"] = {{1, 0.9, 0.9}, {0.9, 1, -0.9}, {0.9, -0.9, 1}};
        test::refused_options("speed_limit", {{"posterior", posterior}},
                              "/options/posterior/correlation");
    }
    SUBCASE("an asymmetric correlation, a diagonal that is not 1") {
        posterior["correlation"] = {{1, 0.5}, {0.4, 1}};
        test::refused_options("speed_limit", {{"posterior", posterior}},
                              "/options/posterior/correlation/1/0");
        posterior["correlation"] = {{0.9, 0.5}, {0.5, 1}};
        test::check_refused_options("speed_limit", {{"posterior", posterior}},
                                    "/options/posterior/correlation/0/0", "[1, 1]", "1");
    }
    SUBCASE("calibrate's own parameter records are accepted as they are") {
        for (json& p : posterior["parameters"]) {
            p["start"] = p["value"];
            p["min"] = 0;
            p["max"] = 1;
            p["at_bound"] = nullptr;
            p["prior_normalised_residual"] = nullptr;
        }
        posterior["parameters"][0]["unit"] = "Pa.s";
        api::FieldErrors errors;
        prepare_speed_limit(core::Scenario{}, {{"posterior", posterior}, {"chatter", false}},
                            "/options", errors);
        CHECK(errors.empty());
    }
}

TEST_CASE("speed_limit: each binding speed is where the steady figure meets the plant's limit") {
    const core::Scenario s;
    const double v = s.rolls.speed;
    const core::SteadyFigures at = core::steady_figures(s, v);
    REQUIRE(at.ok);
    // Limits the operating point meets with some room: the force 2 % above today's (a lower
    // speed bound, the force falls with speed), the power 30 % above (an upper bound).
    const double force_kN = 1.02 * at.force / 1e3;
    const double power_kW = 1.3 * at.power / 1e3;
    const json body = run_speed_limit({{"max_roll_force_kN", force_kN},
                                       {"max_power_kW", power_kW},
                                       {"min_forward_slip", 0.0},
                                       {"chatter_margin", 0.1}});
    const json& result = body["result"];
    CAPTURE(result.dump());
    CHECK(result["checked"] == json{"steady_state", "force", "power", "skid", "chatter"});
    CHECK(result["status"] == "ok");

    const json* force = find_limit(result, "force");
    REQUIRE(force != nullptr);
    CHECK((*force)["unit"] == "kN");
    CHECK((*force)["at_operating"].get<double>() ==
          rollgap::test::approx(at.force / 1e3).epsilon(1e-9));
    CHECK((*force)["utilisation"].get<double>() == rollgap::test::approx(1.0 / 1.02).epsilon(1e-9));
    REQUIRE((*force)["lower_speed_m_per_s"].is_number());
    const double force_speed = (*force)["lower_speed_m_per_s"].get<double>();
    CHECK(force_speed < v);
    CHECK(core::steady_figures(s, force_speed).force / 1e3 ==
          rollgap::test::approx(force_kN).epsilon(1e-6));

    const json* power = find_limit(result, "power");
    REQUIRE(power != nullptr);
    REQUIRE((*power)["upper_speed_m_per_s"].is_number());
    const double power_speed = (*power)["upper_speed_m_per_s"].get<double>();
    CHECK(power_speed > v);
    CHECK(core::steady_figures(s, power_speed).power / 1e3 ==
          rollgap::test::approx(power_kW).epsilon(1e-6));

    // The chatter limit is the critical speed less the margin, and the utilisation the
    // operating speed's share of it ("running at 62 % of the chatter limit").
    const json* chatter = find_limit(result, "chatter");
    REQUIRE(chatter != nullptr);
    REQUIRE(result["critical_speed"]["status"] == "found");
    const double critical = result["critical_speed"]["critical_speed_m_per_s"].get<double>();
    CHECK((*chatter)["value"].get<double>() ==
          rollgap::test::approx(0.9 * critical).epsilon(1e-12));
    CHECK((*chatter)["utilisation"].get<double>() ==
          rollgap::test::approx(v / (0.9 * critical)).epsilon(1e-12));

    // The window is the tightest of them, its ends named by the limits that set them.
    const double upper = std::min(power_speed, 0.9 * critical);
    CHECK(result["window_min_m_per_s"].get<double>() == rollgap::test::approx(force_speed));
    CHECK(result["binding_min"] == "force");
    CHECK(result["advised_speed_m_per_s"].get<double>() == rollgap::test::approx(upper));
    CHECK(result["binding_limit"] == (power_speed < 0.9 * critical ? "power" : "chatter"));
    // The default stand runs at 19 m/s, above 0.9 V_c = 18.09 m/s: not permitted, and said so.
    CHECK(result["operating_permitted"] == (v >= force_speed && v <= upper));
    CHECK(result["uncertainty"].is_null());
    MESSAGE(std::string(result["summary"].get<std::string>()));

    // The echo reruns to the same answer.
    const json again = run_speed_limit(body["options"]);
    CHECK(again["result"] == result);
}

TEST_CASE("speed_limit: a limit not given is not checked, and chatter can be left out") {
    const json result = run_speed_limit({{"chatter", false}})["result"];
    CHECK(result["checked"] == json{"steady_state"});
    CHECK(result["critical_speed"].is_null());
    CHECK(result["binding_limit"].is_null());  // the range's own end
    CHECK(result["advised_speed_m_per_s"].get<double>() == 60.0);
}

TEST_CASE("speed_limit result: a skid utilisation is null where the forward slip is not positive") {
    api::SpeedLimitReport report;
    report.result.status = core::SpeedLimitStatus::ok;
    core::LimitAnswer skid;
    skid.kind = core::SpeedLimitKind::skid;
    skid.limit = 0.005;
    skid.at_operating = -0.01;
    skid.utilisation = skid.limit / skid.at_operating;
    report.result.limits.push_back(skid);
    report.limits.chatter = false;
    const json written = api::speed_limit_result_json(report);
    CHECK(written["limits"][0]["utilisation"].is_null());
    CHECK(written["limits"][0]["at_operating"].get<double>() == -0.01);
}

TEST_CASE("speed_limit: a posterior reaches the chatter limit as (V_c - z sigma)(1 - margin)") {
    const json posterior = viscosity_asperity_posterior();
    const json body = run_speed_limit(
        {{"posterior", posterior}, {"chatter_margin", 0.05}, {"samples", 16}, {"seed", 7}});
    const json& result = body["result"];
    const json& u = result["uncertainty"];
    CAPTURE(u.dump());
    REQUIRE(u["propagated"] == true);
    const double vc = u["critical_speed_m_per_s"].get<double>();
    const double sigma = u["standard_deviation_m_per_s"].get<double>();
    CHECK(vc ==
          rollgap::test::approx(result["critical_speed"]["critical_speed_m_per_s"].get<double>()));
    CHECK(u["z"].get<double>() == rollgap::test::approx(1.6448536269514722).epsilon(1e-12));
    CHECK(u["lower_bound_m_per_s"].get<double>() ==
          rollgap::test::approx(vc - 1.6448536269514722 * sigma));
    const json* chatter = find_limit(result, "chatter");
    REQUIRE(chatter != nullptr);
    CHECK((*chatter)["value"].get<double>() ==
          rollgap::test::approx((vc - 1.6448536269514722 * sigma) * 0.95).epsilon(1e-12));

    // σ against differences of half a standard error, from core's critical speed directly:
    // the same σ if the response is near-linear over the posterior (and the units right).
    const core::Scenario s;
    core::CriticalSpeedOptions search;
    search.stop_at_crossing = true;
    const auto vc_at = [&](double viscosity, double asperity) {
        core::Scenario x = s;
        x.lubricant.viscosity = viscosity;
        x.friction.asperity_factor = asperity;
        const core::CriticalSpeedResult r = core::critical_speed(x, search);
        REQUIRE(r.status == core::CriticalSpeedStatus::found);
        return r.critical_speed;
    };
    const double se_mu = 0.02 * s.lubricant.viscosity, se_a = 0.03 * s.friction.asperity_factor;
    const double h_mu = 0.5 * se_mu, h_a = 0.5 * se_a;
    const double g_mu = (vc_at(s.lubricant.viscosity + h_mu, s.friction.asperity_factor) -
                         vc_at(s.lubricant.viscosity - h_mu, s.friction.asperity_factor)) /
                        (2 * h_mu);
    const double g_a = (vc_at(s.lubricant.viscosity, s.friction.asperity_factor + h_a) -
                        vc_at(s.lubricant.viscosity, s.friction.asperity_factor - h_a)) /
                       (2 * h_a);
    const double a = g_mu * se_mu, b = g_a * se_a;
    const double independent = std::sqrt(a * a + b * b + 2 * -0.5 * a * b);
    MESSAGE("sigma " << sigma << " m/s linear in the answer, " << independent
                     << " m/s from half-step differences; sampled " << u["sampled"].dump());
    CHECK(sigma == rollgap::test::approx(independent).epsilon(0.05));
    CHECK(u["parameters"][0]["critical_speed_change_m_per_s"].get<double>() ==
          rollgap::test::approx(a).epsilon(0.05));
    CHECK(u["parameters"][1]["critical_speed_change_m_per_s"].get<double>() ==
          rollgap::test::approx(b).epsilon(0.05));

    // The seeded draws: 16 critical speeds, their mean within 4 standard errors of the mean
    // (σ/√16) and their spread that of the linear σ to within what 16 draws resolve (the
    // agreement itself is tested with 400 draws in tests/core/test_propagation.cpp).
    const json& sampled = u["sampled"];
    REQUIRE(sampled.is_object());
    CHECK(sampled["samples"].get<int>() + sampled["failed_samples"].get<int>() == 16);
    CHECK(std::abs(sampled["mean_m_per_s"].get<double>() - vc) < 4.0 * sigma / 4.0);
    const double ratio = sampled["standard_deviation_m_per_s"].get<double>() / sigma;
    CHECK(ratio > 0.45);
    CHECK(ratio < 1.55);
    // The same seed draws the same samples.
    const json again = run_speed_limit(body["options"]);
    CHECK(again["result"]["uncertainty"]["sampled"] == sampled);
}

TEST_CASE("speed_limit options: what to change is read strictly") {
    const auto refused = [](const json& changes, const std::string& pointer) {
        return test::refused_options("speed_limit", {{"changes", changes}}, pointer);
    };
    refused({{{"field", "/rolls/speed_m_per_s"}, {"step", 1}}}, "/options/changes/0/field");
    refused({{{"field", "/strip/reduction"}, {"step", 0.01}},
             {{"field", "/strip/reduction"}, {"step", 0.02}}},
            "/options/changes/1/field");
    const json zero =
        refused({{{"field", "/strip/reduction"}, {"step", 0}}}, "/options/changes/0/step");
    CHECK(zero["unit"] == "1");
    refused({{{"field", "/strip/reduction"}}}, "/options/changes/0/step");
    refused({{{"field", "/strip/reductio"}, {"step", 0.01}}}, "/options/changes/0/field");
    refused(json::object(), "/options/changes");
}

TEST_CASE("speed_limit: what to change equals central differences of the whole analysis") {
    // The default stand under a power limit of 4,800 kW (it uses 4,489 kW at 19 m/s) and the
    // chatter limit with a 10 % margin: the chatter limit binds at 0.9 V_c = 18.09 m/s. Each
    // derivative the answer gives is checked against the answer itself rerun at the field ± a
    // quarter of its step (the critical speed refined to 1e-8, so its tolerance is no noise).
    const json options = {{"max_power_kW", 4800},
                          {"chatter_margin", 0.1},
                          {"relative_tolerance", 1e-8},
                          {"changes",
                           {{{"field", "/strip/reduction"}, {"step", 0.01}},
                            {{"field", "/tension/back/stress_MPa"}, {"step", 5}},
                            {{"field", "/lubricant/viscosity_Pa_s"}, {"step", 0.0001}}}}};
    const json result = run_speed_limit(options)["result"];
    const json& what = result["what_to_change"];
    CAPTURE(what.dump());
    REQUIRE(what["binding_limit"] == result["binding_limit"]);
    const json& changes = what["changes"];
    REQUIRE(changes.size() == 3);
    for (std::size_t i = 1; i < changes.size(); ++i)
        CHECK(changes[i - 1]["speed_gain_m_per_s"].get<double>() >=
              changes[i]["speed_gain_m_per_s"].get<double>());
    json quiet = options;
    quiet["what_to_change"] = false;
    for (const json& change : changes) {
        const std::string field = change["field"].get<std::string>();
        CAPTURE(field);
        const double value = change["value"].get<double>();
        const double h = 0.25 * change["step"].get<double>();
        const auto advised = [&](double at) {
            json scenario = json::object();
            scenario[json::json_pointer(field)] = at;
            const json r = run_speed_limit(quiet, scenario)["result"];
            REQUIRE(r["binding_limit"] == result["binding_limit"]);
            return r["advised_speed_m_per_s"].get<double>();
        };
        const double differences = (advised(value + h) - advised(value - h)) / (2.0 * h);
        const double derivative = change["advised_speed_change_m_per_s_per_unit"].get<double>();
        MESSAGE(field << ": " << derivative << " m/s per unit in the answer, " << differences
                      << " from the whole analysis");
        CHECK(derivative == rollgap::test::approx(differences).epsilon(0.01));
        CHECK(change["speed_gain_m_per_s"].get<double>() ==
              rollgap::test::approx(std::abs(derivative) * change["step"].get<double>()));
        CHECK(change["direction"] == (derivative > 0 ? "raise" : "lower"));
    }
}
